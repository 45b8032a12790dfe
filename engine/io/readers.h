// One reader per format, each from the file's bytes; load.cpp picks one by extension. `name` is the file
// named in every message. Each throws ink::Error as points.h says.
#pragma once

#include "io/points.h"

#include <string>

namespace ink::io {

OrientedPoints parseObj(const std::string& bytes, const std::string& name);  // obj.cpp
OrientedPoints parsePly(const std::string& bytes, const std::string& name);  // ply.cpp
// pts.cpp: .pts .xyzn .txt, and with `countLine` .xyz .pwn (whose first line may be the number of points).
OrientedPoints parsePts(const std::string& bytes, const std::string& name, bool countLine = false);
OrientedPoints parseOff(const std::string& bytes, const std::string& name);  // off.cpp
OrientedPoints parseStl(const std::string& bytes, const std::string& name);  // stl.cpp: ascii and binary
// gltf.cpp: `binary` for .glb. With `externalFiles`, buffers may name files beside `name` (never outside its
// directory); without, only data URIs and the .glb's own chunk are read (the fuzzer's way).
OrientedPoints parseGltf(const std::string& bytes, const std::string& name, bool binary, bool externalFiles);

}  // namespace ink::io
