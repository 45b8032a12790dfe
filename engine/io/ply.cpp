// The PLY reader: the header, then the body in any of the three encodings, read value by value by one
// loop, with every declared count checked against the limit and the bytes left before anything is allocated.
#include "base/common.h"
#include "io/normals.h"
#include "io/readers.h"
#include "io/text.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <system_error>
#include <unordered_set>

namespace ink::io {
namespace {

using Eigen::Vector3d;

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool plyType(std::string_view s, PlyType& t) {
    static const std::pair<std::string_view, PlyType> kTypes[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& [word, type] : kTypes)
        if (word == s) {
            t = type;
            return true;
        }
    return false;
}

size_t sizeOf(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
    }
    return 8;
}

bool isInteger(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
    std::string name;
    bool list = false;
    PlyType countType = PlyType::UInt8;
    PlyType type = PlyType::Float32;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;

    // The fewest bytes one entry can take: every scalar at full size, every list empty.
    uint64_t minBinarySize() const {
        uint64_t size = 0;
        for (const PlyProperty& p : properties) size += sizeOf(p.list ? p.countType : p.type);
        return size;
    }
    int find(std::string_view property) const {
        for (size_t i = 0; i < properties.size(); ++i)
            if (properties[i].name == property) return int(i);
        return -1;
    }
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t bodyStart = 0;
    size_t bodyFirstLine = 0;  // for ascii messages
};

size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

// An unknown header line that is free text a writer added (it starts with a word, and is printable), rather
// than garbage (control bytes, a number: body data where the header should be) or a misspelt keyword, which
// would otherwise be skipped and leave a more puzzling error later.
bool looksLikeWriterNote(std::string_view line, std::string_view word) {
    if (!std::isalpha(static_cast<unsigned char>(word[0]))) return false;
    for (char c : line)
        if (static_cast<unsigned char>(c) < 32 && c != '\t') return false;
    for (std::string_view keyword : {"ply", "format", "element", "property", "end_header", "comment", "obj_info"})
        if (editDistance(word.substr(0, 16), keyword) <= (keyword.size() > 6 ? 2u : 1u)) return false;
    return true;
}

PlyHeader parsePlyHeader(const std::string& bytes, const std::string& name) {
    PlyHeader header;
    size_t pos = 0, number = 0;
    // The header is always "\n" (or "\r\n") separated text, and a binary body starts right after the
    // end_header line, so lines are cut here by hand rather than with Lines.
    auto next = [&](std::string_view& line) {
        if (pos >= bytes.size()) return false;
        size_t end = bytes.find('\n', pos);
        size_t stop = end == std::string::npos ? bytes.size() : end;
        line = std::string_view(bytes).substr(pos, stop - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = stop == bytes.size() ? stop : stop + 1;
        ++number;
        return true;
    };
    std::string_view line;
    if (!next(line) || line != "ply") fail(name, "not a PLY file (the first line is not 'ply')");

    bool haveFormat = false;
    std::unordered_set<std::string> elementNames, propertyNames;  // of the header; properties of the last element
    std::vector<std::string_view> f;
    // Unknown lines writers add get a note each, the first few: a header of 10,000 of them gets 3 and a count.
    constexpr size_t kMaxLineNotes = 3;
    size_t unknownLines = 0;
    auto noteUnknown = [&] {
        if (unknownLines > kMaxLineNotes)
            note(name + ": and " + std::to_string(unknownLines - kMaxLineNotes) + " more unknown header lines ignored");
    };
    while (next(line)) {
        auto where = [&] { return "header line " + std::to_string(number); };
        splitFields(line, f);
        // obj_info is not in the original specification but common (Paul Bourke's, VTK and others write it):
        // like comment, free text.
        if (f.empty() || f[0] == "comment" || f[0] == "obj_info") continue;
        if (f[0] == "end_header") {
            if (!haveFormat) fail(name, "header has no format line");
            noteUnknown();
            header.bodyStart = pos;
            header.bodyFirstLine = number + 1;
            return header;
        }
        if (f[0] == "format") {
            double version = 0;
            bool ok = f.size() == 3 && toDouble(f[2], version) && version == 1.0;
            if (ok && f[1] == "ascii")
                header.format = PlyFormat::Ascii;
            else if (ok && f[1] == "binary_little_endian")
                header.format = PlyFormat::BinaryLittleEndian;
            else if (ok && f[1] == "binary_big_endian")
                header.format = PlyFormat::BinaryBigEndian;
            else
                fail(name, where() + ": bad format line " + quoted(line) +
                               " (expected 'format ascii|binary_little_endian|binary_big_endian 1.0')");
            if (haveFormat) fail(name, where() + ": a second format line");
            haveFormat = true;
        } else if (f[0] == "element") {
            uint64_t count = 0;
            bool ok = f.size() == 3;
            if (ok) {
                auto [end, ec] = std::from_chars(f[2].data(), f[2].data() + f[2].size(), count);
                ok = ec == std::errc() && end == f[2].data() + f[2].size();
            }
            if (!ok) fail(name, where() + ": bad element line " + quoted(line) + " (expected 'element NAME COUNT')");
            if (count > kMaxElements)
                fail(name, where() + ": element '" + std::string(f[1]) + "' claims " + std::to_string(count) +
                               " entries; the limit is " + std::to_string(kMaxElements));
            // Sets, not scans of what came before: a header of 200,000 elements took 100 s that way.
            if (!elementNames.insert(std::string(f[1])).second)
                fail(name, where() + ": a second element '" + std::string(f[1]) + "'");
            propertyNames.clear();
            header.elements.push_back({std::string(f[1]), count, {}});
        } else if (f[0] == "property") {
            if (header.elements.empty()) fail(name, where() + ": property before any element");
            PlyProperty p;
            bool ok;
            if (f.size() >= 2 && f[1] == "list") {
                ok = f.size() == 5 && plyType(f[2], p.countType) && isInteger(p.countType) && plyType(f[3], p.type);
                p.list = true;
            } else {
                ok = f.size() == 3 && plyType(f[1], p.type);
            }
            if (!ok)
                fail(name, where() + ": bad property line " + quoted(line) +
                               " (expected 'property TYPE NAME' or 'property list INTTYPE TYPE NAME')");
            p.name = std::string(f.back());
            PlyElement& e = header.elements.back();
            if (!propertyNames.insert(p.name).second)
                fail(name, where() + ": a second property '" + p.name + "' in '" + e.name + "'");
            e.properties.push_back(std::move(p));
        } else if (looksLikeWriterNote(line, f[0])) {
            // Lines the format does not define but writers add ("Created by ...", "TextureFile x.png"):
            // passed over with a note, as other readers do.
            if (++unknownLines <= kMaxLineNotes)
                note(name + ": " + where() + ": ignored the unknown header line " + quoted(line));
        } else {
            fail(name, where() + ": unknown header keyword " + quoted(f[0]));
        }
    }
    fail(name, "header has no end_header line");
}

// Reads the body value by value in either encoding, so one loop serves ascii and both binaries. Knows
// which entry it is in, for messages.
class PlyBody {
public:
    PlyBody(const std::string& bytes, const PlyHeader& header, const std::string& name)
        : bytes_(bytes),
          name_(name),
          format_(header.format),
          pos_(header.bodyStart),
          lines_(bytes, header.bodyStart, header.bodyFirstLine) {}

    // Refuses an element the rest of the file cannot possibly hold before anything is allocated for it.
    void beginElement(const PlyElement& e) {
        element_ = &e;
        entry_ = 0;
        if (format_ == PlyFormat::Ascii) {
            // Each value needs at least one character.
            if (e.count * e.properties.size() > lines_.remaining())
                fail(name_, "truncated: the header declares " + std::to_string(e.count) + " " + plural() +
                                " but only " + std::to_string(lines_.remaining()) + " bytes are left");
            return;
        }
        uint64_t size = e.minBinarySize(), left = bytes_.size() - pos_;
        if (size == 0 || e.count * size <= left) return;
        bool fixed = std::none_of(e.properties.begin(), e.properties.end(), [](auto& p) { return p.list; });
        if (fixed) {
            entry_ = left / size;
            truncated();
        }
        fail(name_, "truncated: the header declares " + std::to_string(e.count) + " " + plural() + " of at least " +
                        std::to_string(size) + " bytes, but only " + std::to_string(left) + " bytes are left");
    }

    void beginEntry(uint64_t entry) {
        entry_ = entry;
        field_ = 0;
        fields_.clear();
        if (format_ != PlyFormat::Ascii || element_->properties.empty()) return;
        std::string_view line;
        do {
            if (!lines_.next(line)) truncated();
            rejectBinary(line, name_, lines_.number());
            splitFields(line, fields_);
        } while (fields_.empty());
    }

    void endEntry() {
        if (format_ == PlyFormat::Ascii && field_ != fields_.size())
            fail(name_,
                 where() + ": " + std::to_string(fields_.size() - field_) + " more values than the header declares");
    }

    double scalar(PlyType t) {
        if (format_ == PlyFormat::Ascii) {
            if (field_ == fields_.size()) fail(name_, where() + ": fewer values than the header declares");
            std::string_view s = fields_[field_++];
            double v;
            if (!toDouble(s, v)) fail(name_, where() + ": " + quoted(s) + " is not a number");
            if (isInteger(t) && v != std::floor(v)) fail(name_, where() + ": " + quoted(s) + " is not an integer");
            return v;
        }
        size_t n = sizeOf(t);
        if (bytes_.size() - pos_ < n) truncated();
        unsigned char b[8];
        std::memcpy(b, bytes_.data() + pos_, n);
        pos_ += n;
        bool big = format_ == PlyFormat::BinaryBigEndian;
        if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
        auto get = [&b](auto v) {
            std::memcpy(&v, b, sizeof v);
            return double(v);
        };
        switch (t) {
            case PlyType::Int8:
                return get(int8_t());
            case PlyType::UInt8:
                return get(uint8_t());
            case PlyType::Int16:
                return get(int16_t());
            case PlyType::UInt16:
                return get(uint16_t());
            case PlyType::Int32:
                return get(int32_t());
            case PlyType::UInt32:
                return get(uint32_t());
            case PlyType::Float32:
                return get(float());
            case PlyType::Float64:
                return get(double());
        }
        return 0;
    }

    // A list's length, checked against what is left so a corrupt count fails fast instead of looping.
    uint64_t listCount(const PlyProperty& p) {
        double v = scalar(p.countType);
        if (v < 0) fail(name_, where() + ": negative list length " + num(v));
        uint64_t left = format_ == PlyFormat::Ascii ? fields_.size() - field_ : (bytes_.size() - pos_) / sizeOf(p.type);
        if (v > double(left)) {
            if (format_ == PlyFormat::Ascii)
                fail(name_, where() + ": list '" + p.name + "' claims " + num(v) + " items but the line has " +
                                std::to_string(left) + " more values");
            truncated();
        }
        return uint64_t(v);
    }

    void skip(const PlyProperty& p) {
        if (!p.list) {
            scalar(p.type);
            return;
        }
        uint64_t count = listCount(p);
        if (format_ == PlyFormat::Ascii) {
            for (uint64_t k = 0; k < count; ++k) scalar(p.type);  // still checks they are numbers
        } else {
            pos_ += count * sizeOf(p.type);  // listCount checked it fits
        }
    }

    // Whatever data follows the last element is ignored, as other PLY readers do.

    std::string where() const {
        std::string entry = element_->name + " " + std::to_string(entry_);
        if (format_ != PlyFormat::Ascii) return entry;
        return "line " + std::to_string(lines_.number()) + " (" + entry + ")";
    }

    [[noreturn]] void truncated() const {
        fail(name_, "truncated: expected " + std::to_string(element_->count) + " " + plural() + ", file ends in " +
                        element_->name + " " + std::to_string(entry_));
    }

private:
    std::string plural() const { return element_->name == "vertex" ? "vertices" : "'" + element_->name + "' entries"; }

    const std::string& bytes_;
    const std::string& name_;
    PlyFormat format_;
    size_t pos_;   // binary
    Lines lines_;  // ascii
    std::vector<std::string_view> fields_;
    size_t field_ = 0;
    const PlyElement* element_ = nullptr;
    uint64_t entry_ = 0;
};

}  // namespace

OrientedPoints parsePly(const std::string& bytes, const std::string& name) {
    PlyHeader header = parsePlyHeader(bytes, name);

    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex") vertex = &e;
        if (e.name == "face") face = &e;
    }
    if (!vertex) fail(name, "has no 'element vertex' in its header");
    if (vertex->count == 0) fail(name, "no vertices");
    // Slot k of the vertex holds x y z nx ny nz; -1 where absent.
    static const char* const kSlots[6] = {"x", "y", "z", "nx", "ny", "nz"};
    int slot[6];
    for (int k = 0; k < 6; ++k) {
        slot[k] = vertex->find(kSlots[k]);
        if (slot[k] >= 0 && vertex->properties[size_t(slot[k])].list)
            fail(name, std::string("vertex property '") + kSlots[k] + "' is a list; it must be a number");
    }
    if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0) fail(name, "vertex element lacks x, y or z");
    int normalSlots = (slot[3] >= 0) + (slot[4] >= 0) + (slot[5] >= 0);
    if (normalSlots != 0 && normalSlots != 3) fail(name, "vertex element has some of nx, ny, nz but not all three");
    bool hasNormals = normalSlots == 3;
    int faceList = -1;
    if (face) {
        faceList = face->find("vertex_indices");
        if (faceList < 0) faceList = face->find("vertex_index");
        if (faceList < 0 || !face->properties[size_t(faceList)].list)
            fail(name, "face element has no 'vertex_indices' list");
        if (!isInteger(face->properties[size_t(faceList)].type)) fail(name, "face vertex indices must be integers");
    }
    const bool cloud = !face || face->count == 0;  // a point cloud: its missing or zero normals are estimated

    OrientedPoints points;
    Polygons polygons;
    PlyBody body(bytes, header, name);
    for (const PlyElement& e : header.elements) {
        body.beginElement(e);
        // An element without properties has nothing to read, in either encoding (an ascii entry would be
        // an empty line, and blank lines are skipped): skip it rather than count to a hostile 100 million,
        // fifty times over in a header of one kilobyte.
        if (e.properties.empty()) continue;
        if (&e == vertex) {
            points.positions.assign(e.count, Vector3d::Zero());
            points.normals.assign(e.count, Vector3d::Zero());
        }
        for (uint64_t i = 0; i < e.count; ++i) {
            body.beginEntry(i);
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& p = e.properties[k];
                if (&e == vertex && !p.list) {
                    double value = body.scalar(p.type);
                    for (int s = 0; s < 6; ++s)
                        if (slot[s] == int(k)) (s < 3 ? points.positions : points.normals)[i][s % 3] = value;
                } else if (&e == face && int(k) == faceList) {
                    uint64_t count = body.listCount(p);
                    if (count < 3)
                        fail(name,
                             body.where() + ": has " + std::to_string(count) + " vertices; at least 3 are needed");
                    for (uint64_t c = 0; c < count; ++c) {
                        double index = body.scalar(p.type);
                        if (index < 0 || index >= double(vertex->count))
                            fail(name, body.where() + ": vertex index " + num(index) +
                                           " is out of range (the file has " + std::to_string(vertex->count) +
                                           " vertices)");
                        polygons.indices.push_back(uint32_t(index));
                    }
                    polygons.sizes.push_back(uint32_t(count));
                } else {
                    body.skip(p);
                }
            }
            body.endEntry();
        }
    }

    auto where = [](size_t i) { return "vertex " + std::to_string(i); };
    if (hasNormals || cloud) {
        appendTriangles(polygons, {}, 0, points.triangles);
        replaceZeroNormals(points, name);
        finish(points, name, where, cloud ? ZeroNormal::Estimated : ZeroNormal::Refused);
        return points;
    }
    // Vertices no face uses have no normal and are dropped, keeping their original numbers for messages.
    return meshPoints(points.positions, polygons, name, where);
}

}  // namespace ink::io
