// One reader per format, each from the file's bytes; load.cpp picks one by extension. `name` is the file
// named in every message. Each throws ink::Error as points.h says.
#pragma once

#include "points.h"

#include <string>

namespace ink::io {

OrientedPoints parseObj(const std::string& bytes, const std::string& name);  // obj.cpp
OrientedPoints parsePly(const std::string& bytes, const std::string& name);  // ply.cpp
OrientedPoints parsePts(const std::string& bytes, const std::string& name);  // pts.cpp: .pts .xyzn .txt

}  // namespace ink::io
