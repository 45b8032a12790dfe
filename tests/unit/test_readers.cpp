// The readers added for the files users have: .xyz/.pwn, OFF and its variants, STL (ascii and binary), glTF
// (.gltf with data-URI or external buffers, .glb), and the PLY header lines writers add. Each is checked on
// files written here, refusals with their messages, and once through `inkwell render`.
#include "base/common.h"
#include "io/points.h"
#include "run_command.h"

#include "glb_writer.h"

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using Eigen::Vector3d;
using ink::Error;
using ink::OrientedPoints;
using ink::parsePoints;

namespace {

namespace fs = std::filesystem;

bool near(const Vector3d& a, const Vector3d& b, double eps = 1e-6) { return (a - b).norm() <= eps; }

// The regular tetrahedron: each vertex's area-weighted normal points away from the centre.
const Vector3d kTetra[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
const int kTetraFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};  // counter-clockwise from outside

// The unit cube's corners and its twelve outward triangles.
Vector3d cubeCorner(int i) { return Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1); }
const int kCubeFaces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

std::vector<std::array<Vector3d, 3>> cubeTriangles() {
    std::vector<std::array<Vector3d, 3>> t;
    for (const auto& f : kCubeFaces) {
        t.push_back({cubeCorner(f[0]), cubeCorner(f[1]), cubeCorner(f[2])});
        t.push_back({cubeCorner(f[0]), cubeCorner(f[2]), cubeCorner(f[3])});
    }
    return t;
}

std::vector<std::array<Vector3d, 3>> tetraTriangles() {
    std::vector<std::array<Vector3d, 3>> t;
    for (const auto& f : kTetraFaces) t.push_back({kTetra[f[0]], kTetra[f[1]], kTetra[f[2]]});
    return t;
}

std::string asciiStl(const std::vector<std::array<Vector3d, 3>>& triangles) {
    std::string s = "solid test\n";
    for (const auto& t : triangles) {
        s += "  facet normal 0 0 0\n    outer loop\n";  // zero facet normals, as writers leave them
        for (const Vector3d& v : t)
            s += "      vertex " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) +
                 "\n";
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid test\n";
}

std::string binaryStl(const std::vector<std::array<Vector3d, 3>>& triangles, const std::string& header) {
    std::string s = header;
    s.resize(80, ' ');
    put(s, uint32_t(triangles.size()));
    for (const auto& t : triangles) {
        for (int k = 0; k < 3; ++k) put(s, 0.0f);
        for (const Vector3d& v : t)
            for (int k = 0; k < 3; ++k) put(s, float(v[k]));
        put(s, uint16_t(0));
    }
    return s;
}

std::string base64(const std::string& in) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
        if (i + 2 < in.size()) v |= uint32_t(uint8_t(in[i + 2]));
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? kAlphabet[v & 63] : '=';
    }
    return out;
}

// The tetrahedron as a glTF buffer: 4 float positions (48 bytes), then 12 ushort indices (24 bytes).
std::string tetraBuffer() {
    std::string b;
    for (const Vector3d& v : kTetra)
        for (int k = 0; k < 3; ++k) put(b, float(v[k]));
    for (const auto& f : kTetraFaces)
        for (int k = 0; k < 3; ++k) put(b, uint16_t(f[k]));
    return b;
}

// glTF JSON for the tetrahedron: `node` is the node's transform members, `uri` the buffer's (empty: the .glb
// chunk), `positionCount` the POSITION accessor's count.
std::string tetraJson(const std::string& node, const std::string& uri, int positionCount = 4) {
    std::string buffer = "{\"byteLength\": 72" + (uri.empty() ? std::string() : ", \"uri\": \"" + uri + "\"") + "}";
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
"nodes": [{"mesh": 0)" +
           (node.empty() ? "" : ", " + node) + R"(}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
           std::to_string(positionCount) + R"(, "type": "VEC3"},
              {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
"buffers": [)" +
           buffer + "]}";
}

void checkTetra(const OrientedPoints& p, double scale = 1, const Vector3d& offset = Vector3d::Zero()) {
    REQUIRE(p.positions.size() == 4);
    for (size_t i = 0; i < 4; ++i) {
        // Points may come in any order; find each corner.
        bool found = false;
        for (const Vector3d& v : kTetra)
            if (near(p.positions[i], scale * v + offset, 1e-5)) {
                found = true;
                CHECK(near(p.normals[i], v.normalized(), 1e-6));
            }
        CHECK(found);
    }
}

void checkCube(const OrientedPoints& p) {
    REQUIRE(p.positions.size() == 8);  // welded
    Vector3d centre(0.5, 0.5, 0.5);
    for (size_t i = 0; i < 8; ++i) {
        Vector3d out = p.positions[i] - centre;
        CHECK(std::abs(p.normals[i].norm() - 1) < 1e-12);
        // Outward, within the corner's octant.
        for (int k = 0; k < 3; ++k) CHECK(p.normals[i][k] * out[k] > 0);
    }
}

void bad(const std::string& bytes, const char* format, const std::string& message) {
    CAPTURE(bytes.substr(0, 200));
    std::string name = std::string("bad.") + format;
    CHECK_THROWS_WITH_AS(parsePoints(bytes, format, name), doctest::Contains((name + ": " + message).c_str()), Error);
}

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("inkwell_test_readers_" + std::to_string(std::random_device()()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string write(const std::string& file, const std::string& bytes) const {
        std::ofstream(path / file, std::ios::binary) << bytes;
        return (path / file).string();
    }
};

struct Notes {
    std::vector<std::string> lines;
    ink::Reporter reporter{[this](const std::string& line) { lines.push_back(line); }, nullptr};
};

const char* kCubeOff = R"(OFF
# the unit cube, quads
8 6 12
0 0 0
1 0 0
0 1 0
1 1 0   # a trailing comment
0 0 1
1 0 1

0 1 1
1 1 1
4 0 2 3 1
4 4 5 7 6
4 0 1 5 4
4 2 6 7 3
4 0 4 6 2
4 1 3 7 5
)";

}  // namespace

TEST_CASE("readers: stl ascii and binary, corners welded, normals from the winding" * doctest::test_suite("unit")) {
    SUBCASE("ascii tetrahedron: exact normals despite zero facet normals") {
        checkTetra(parsePoints(asciiStl(tetraTriangles()), "stl", "t.stl"));
    }
    SUBCASE("ascii cube: 36 corners welded to 8") { checkCube(parsePoints(asciiStl(cubeTriangles()), "stl", "c.stl")); }
    SUBCASE("binary cube, its header starting with 'solid' (decided by the size)") {
        checkCube(parsePoints(binaryStl(cubeTriangles(), "solid cube exported by a CAD program"), "stl", "c.stl"));
    }
    SUBCASE("binary tetrahedron") { checkTetra(parsePoints(binaryStl(tetraTriangles(), "binary"), "stl", "t.stl")); }
    SUBCASE("uppercase keywords and several solids") {
        std::string two =
            asciiStl({tetraTriangles()[0], tetraTriangles()[1]}) + asciiStl({tetraTriangles()[2], tetraTriangles()[3]});
        for (char& c : two)
            if (c >= 'a' && c <= 'z') c = char(c - 32);
        checkTetra(parsePoints(two, "stl", "t.stl"));
    }
    SUBCASE("a vertex only zero-area triangles use is dropped with a note") {
        auto t = tetraTriangles();
        t.push_back({kTetra[0], kTetra[1], Vector3d((kTetra[0] + kTetra[1]) / 2)});  // a sliver on an edge
        Notes notes;
        ink::ScopedReporter reporting(notes.reporter);
        checkTetra(parsePoints(binaryStl(t, "x"), "stl", "t.stl"));
        REQUIRE(notes.lines.size() == 1);
        CHECK(notes.lines[0] == "t.stl: dropped 1 vertex whose triangles all have zero area");
    }
    SUBCASE("refused") {
        std::string binary = binaryStl(cubeTriangles(), "binary");
        bad(binary.substr(0, binary.size() - 7), "stl",
            "binary STL: the header declares 12 triangles, which take 684 bytes, but the file has 677");
        bad("hello", "stl", "not an STL file: 5 bytes, too short");
        std::string ascii = asciiStl(tetraTriangles());
        bad(ascii.substr(0, ascii.size() / 2), "stl", "truncated");
        bad("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n", "stl",
            "line 6: a facet with 2 vertices; STL facets have 3");
        bad("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n", "stl", "line 4: 'zero' is not a number");
        bad("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 nan\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
            "endsolid\n",
            "stl", "line 4: coordinate is not finite");
        bad("solid x\nfacets\n", "stl", "line 2: expected 'facet', found 'facets'");
        bad("solid x\nendsolid x\n", "stl", "no triangles");
        bad(binaryStl({{kTetra[0], kTetra[0], kTetra[1]}}, "b"), "stl", "every triangle has zero area");
        std::string huge(84, ' ');
        huge[80] = huge[81] = huge[82] = huge[83] = char(0xff);
        bad(huge, "stl", "binary STL: the header declares 4294967295 triangles, which take 214748364834 bytes");
    }
}

TEST_CASE("readers: off and its variants" * doctest::test_suite("unit")) {
    SUBCASE("OFF cube: comments, blank lines, quads") { checkCube(parsePoints(kCubeOff, "off", "c.off")); }
    SUBCASE("counts on the header line, CRLF, no edge count") {
        std::string s = "OFF 4 4\r\n";
        for (const Vector3d& v : kTetra)
            s += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\r\n";
        for (const auto& f : kTetraFaces)
            s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\r\n";
        checkTetra(parsePoints(s, "off", "t.off"));
    }
    SUBCASE("COFF: vertex colours (rgb and rgba) and face colours are read past") {
        std::string s = "COFF\n4 4 6\n";
        int k = 0;
        for (const Vector3d& v : kTetra)
            s += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) +
                 (k++ % 2 ? " 255 0 0\n" : " 0.5 0.5 0.5 1\n");
        for (const auto& f : kTetraFaces)
            s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + " 1 0 0\n";
        checkTetra(parsePoints(s, "off", "t.off"));
    }
    SUBCASE("NOFF and CNOFF: the file's normals are used, even with faces") {
        std::string noff = "NOFF\n3 0 0\n0 0 0 0 0 2\n1 0 0 0 0 2\n0 1 0 0 1 0\n";
        OrientedPoints p = parsePoints(noff, "off", "n.off");
        REQUIRE(p.positions.size() == 3);
        CHECK(near(p.normals[0], Vector3d(0, 0, 1)));
        CHECK(near(p.normals[2], Vector3d(0, 1, 0)));
        std::string cnoff = "CNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0\n1 0 0 0 0 1 1 0 0 1\n0 1 0 1 0 0 0 0 1\n3 0 1 2\n";
        p = parsePoints(cnoff, "off", "cn.off");
        REQUIRE(p.positions.size() == 3);
        CHECK(near(p.normals[2], Vector3d(1, 0, 0)));  // given, not the face's (0, 0, 1)
    }
    SUBCASE("refused") {
        bad("PLY\n", "off", "line 1: not an OFF file (the header is 'PLY', expected OFF, COFF, NOFF or CNOFF)");
        bad("", "off", "empty file");
        bad("OFF\n", "off", "no vertex and face counts");
        bad("OFF\n3\n", "off", "line 2: expected the counts 'VERTICES FACES EDGES', found 1 fields");
        bad("OFF\n-3 1 0\n", "off", "line 2: the vertices count '-3' is not a non-negative integer");
        bad("OFF\n4000000000 1 0\n", "off", "line 2: the header claims 4000000000 vertices; the limit is 100000000");
        bad("OFF\n1000000 0 0\n0 0 0\n", "off", "truncated: the header declares 1000000 vertices and 0 faces");
        bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "off",
            "line 6 (face 0): vertex index 3 is out of range (the file has 3 vertices)");
        bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", "off", "line 6 (face 0): vertex index -1 is out of range");
        bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "off",
            "line 6 (face 0): has 2 vertices; at least 3 are needed");
        bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "off",
            "line 6 (face 0): claims 4 vertices but the line has 3");
        bad("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "off", "line 4 (vertex 1): expected 3 numbers, found 2 fields");
        bad("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", "off", "line 4 (vertex 1): 'x' is not a number");
        bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", "off", "line 7: more data after the 1 faces");
        bad("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "off", "truncated: expected 2 faces, file ends after 1");
        bad("4OFF\n", "off", "line 1: '4OFF' (homogeneous or n-dimensional vertices) is not supported");
        bad("OFF BINARY\n", "off", "line 1: binary OFF is not supported");
        bad("OFF\n3 1 0\n0 0 0\n0 0 0\n0 0 0\n3 0 1 2\n", "off",
            "vertex 0 (line 3): normal is zero (the faces around it have no area, or their windings cancel)");
    }
}

TEST_CASE("readers: xyz and pwn are oriented point text, with an optional count line" * doctest::test_suite("unit")) {
    OrientedPoints p = parsePoints("2\n0 0 0 0 0 1\n1 0 0 0 2 0\n", "xyz", "p.xyz");
    REQUIRE(p.positions.size() == 2);
    CHECK(near(p.normals[1], Vector3d(0, 1, 0)));
    CHECK(parsePoints("0 0 0 0 0 1\n", "xyz", "p.pwn").positions.size() == 1);
    bad("3\n0 0 0 0 0 1\n", "xyz", "line 1: the count line says 3 points, the file has 1");
    bad("0 0 0 1\n", "xyz", "line 1: expected 6 numbers (x y z nx ny nz) or 3 (x y z), found 4 fields");
    bad("x\n", "xyz",
        "line 1: expected a point count, or a point's 6 numbers (x y z nx ny nz) or 3 (x y z), found 'x'");
    // .pts keeps refusing a lone number.
    bad("2\n0 0 0 0 0 1\n", "pts", "line 1: expected 6 numbers (x y z nx ny nz) or 3 (x y z), found 1 fields");
}

TEST_CASE("readers: glTF and glb" * doctest::test_suite("unit")) {
    SUBCASE(".glb with a node translation and scale: the positions move") {
        OrientedPoints p = parsePoints(
            glb(tetraJson("\"translation\": [10, 0, 0], \"scale\": [2, 2, 2]", ""), tetraBuffer()), "glb", "t.glb");
        checkTetra(p, 2, Vector3d(10, 0, 0));
    }
    SUBCASE("a mirroring scale keeps the normals outward") {
        OrientedPoints p = parsePoints(glb(tetraJson("\"scale\": [-1, 1, 1]", ""), tetraBuffer()), "glb", "t.glb");
        REQUIRE(p.positions.size() == 4);
        for (size_t i = 0; i < 4; ++i) CHECK(near(p.normals[i], p.positions[i].normalized()));
    }
    SUBCASE("a matrix, and a parent's transform applied to its child") {
        std::string json = tetraJson("", "");
        // Node 0 becomes the child of a new node 1 that translates by (0, 5, 0); the scene's root is node 1.
        json.replace(json.find("\"nodes\": [0]"), 12, "\"nodes\": [1]");
        json.replace(json.find("\"nodes\": [{\"mesh\": 0}]"), 22,
                     "\"nodes\": [{\"mesh\": 0, \"matrix\": [3,0,0,0, 0,3,0,0, 0,0,3,0, 1,0,0,1]},"
                     " {\"children\": [0], \"translation\": [0, 5, 0]}]");
        checkTetra(parsePoints(glb(json, tetraBuffer()), "glb", "t.glb"), 3, Vector3d(1, 5, 0));
    }
    SUBCASE(".gltf with a data-URI buffer") {
        std::string uri = "data:application/octet-stream;base64," + base64(tetraBuffer());
        checkTetra(parsePoints(tetraJson("\"translation\": [0, 0, -1]", uri), "gltf", "t.gltf"), 1, Vector3d(0, 0, -1));
    }
    SUBCASE("NORMAL attributes are used, turned by the node's rotation") {
        std::string bin;
        for (const Vector3d& v : kTetra)
            for (int k = 0; k < 3; ++k) put(bin, float(v[k]));
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k) put(bin, float(k == 2));  // all (0, 0, 1)
        std::string json =
            R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0, "rotation": [0.70710678, 0, 0, 0.70710678]}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
              {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 3, "type": "VEC3"}],
"bufferViews": [{"buffer": 0, "byteLength": 96}], "buffers": [{"byteLength": 96}]})";
        OrientedPoints p = parsePoints(glb(json, bin), "glb", "n.glb");
        REQUIRE(p.positions.size() == 3);
        // 90 degrees about x takes z to -y.
        for (const Vector3d& n : p.normals) CHECK(near(n, Vector3d(0, -1, 0)));
    }
    SUBCASE("an external buffer beside the file; none outside its directory") {
        TempDir dir;
        dir.write("tetra.bin", tetraBuffer());
        checkTetra(ink::loadPoints(dir.write("t.gltf", tetraJson("", "tetra.bin"))));
        checkTetra(ink::loadPoints(dir.write("T.GLTF", tetraJson("", "tetra%2Ebin"))));  // percent-encoded
        std::string up = dir.write("up.gltf", tetraJson("", "../tetra.bin"));
        CHECK_THROWS_WITH_AS(ink::loadPoints(up),
                             doctest::Contains((up + ": glTF buffer 0: 'uri' '../tetra.bin' is not a file in the glTF "
                                                     "file's directory")
                                                   .c_str()),
                             Error);
        std::string abs = dir.write("abs.gltf", tetraJson("", "/etc/passwd"));
        CHECK_THROWS_WITH_AS(ink::loadPoints(abs), doctest::Contains("'/etc/passwd' is not a file in the glTF"), Error);
        std::string missing = dir.write("missing.gltf", tetraJson("", "nothere.bin"));
        CHECK_THROWS_WITH_AS(ink::loadPoints(missing), doctest::Contains("nothere.bin"), Error);
    }
    SUBCASE("refused") {
        std::string bin = tetraBuffer();
        bad(glb(tetraJson("", "", 5), bin), "glb",
            "glTF POSITION accessor 0: 5 elements of 12 bytes, every 12 from byte 0, run past the end of buffer view 0 "
            "(48 bytes)");
        std::string json = tetraJson("", "");
        std::string far = json;
        far.replace(far.find("\"byteOffset\": 48, \"byteLength\": 24"), 34, "\"byteOffset\": 60, \"byteLength\": 24");
        bad(glb(far, bin), "glb", "glTF buffer view 1: bytes 60 + 24 lie outside buffer 0 (72 bytes)");
        std::string index = bin;
        index[48] = 9;  // the first index: 9 of 4 vertices
        bad(glb(json, index), "glb", "glTF mesh 0 primitive 0: index 9 is out of range (the primitive has 4 vertices)");
        std::string g = glb(json, bin);
        bad(g.substr(0, g.size() - 4), "glb", "binary glTF header says 604 bytes, the file has 600 (truncated?)");
        bad("glTF", "glb", "not a binary glTF file");
        bad("{", "gltf", "glTF JSON: [json.exception.parse_error.101]");
        bad(R"({"asset": {"version": "1.0"}})", "gltf", "glTF: asset version '1.0'; this reader reads glTF 2.0");
        bad(R"({"asset": {"version": 1}})", "gltf", "glTF: asset version 1 (glTF 1.0); this reader reads glTF 2.0");
        bad(R"({"asset": {}})", "gltf", "glTF: no asset version (this reader reads glTF 2.0)");
        bad(R"({"asset": {"version": "2.0"}})", "gltf", "glTF: the scene has no triangles");
        bad(R"({"asset": {"version": "2.0"}, "extensionsRequired": ["KHR_draco_mesh_compression"]})", "gltf",
            "glTF: requires the extension 'KHR_draco_mesh_compression', which is not supported");
        std::string two = json;
        two.replace(two.find("\"buffers\": [{\"byteLength\": 72}]"), 31,
                    "\"buffers\": [{\"byteLength\": 72}, {\"byteLength\": 72}]");
        bad(glb(two, bin), "glb", "glTF buffer 1: no 'uri' (only buffer 0 of a .glb is its binary chunk)");
        std::string cycle = json;
        cycle.replace(cycle.find("\"nodes\": [{\"mesh\": 0}]"), 22,
                      "\"nodes\": [{\"mesh\": 0, \"children\": [1]}, {\"children\": [0]}]");
        bad(glb(cycle, bin), "glb", "glTF: the node hierarchy has a cycle");
    }
}

TEST_CASE("readers: ply header lines writers add are passed over with a note, garbage is not" *
          doctest::test_suite("unit")) {
    std::string body =
        "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n"
        "property float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n";
    Notes notes;
    ink::ScopedReporter reporting(notes.reporter);
    OrientedPoints p =
        parsePoints("ply\nformat ascii 1.0\nCreated by SomeScanner 2.1\nobj_info num_cols 1\n" + body, "ply", "w.ply");
    CHECK(p.positions.size() == 1);
    REQUIRE(notes.lines.size() == 1);
    CHECK(notes.lines[0] == "w.ply: header line 3: ignored the unknown header line 'Created by SomeScanner 2.1'");
    bad("ply\nformat ascii 1.0\n\x01\x02garbage\n" + body, "ply", "header line 3: unknown header keyword");
    bad("ply\nformat ascii 1.0\n0.5 0.25 1\n" + body, "ply", "header line 3: unknown header keyword '0.5'");
    bad("ply\nformat ascii 1.0\nelment vertex 1\n" + body, "ply", "header line 3: unknown header keyword 'elment'");
}

TEST_CASE("readers: every fuzz seed and regression of the new readers parses or throws ink::Error naming the file" *
          doctest::test_suite("unit")) {
    size_t files = 0;
    for (const char* root : {INKWELL_SOURCE_DIR "/tests/regressions", INKWELL_SOURCE_DIR "/fuzz/corpus"}) {
        for (const char* format : {"off", "stl", "glb"}) {
            fs::path folder = fs::path(root) / format;
            if (!fs::exists(folder)) continue;
            for (const auto& entry : fs::directory_iterator(folder)) {
                std::ifstream in(entry.path(), std::ios::binary);
                std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
                std::string name = entry.path().filename().string();
                CAPTURE(entry.path().string());
                auto start = std::chrono::steady_clock::now();
                try {
                    parsePoints(bytes, format, name);
                } catch (const Error& e) {
                    std::string message = e.what();
                    CHECK(message.rfind(name + ": ", 0) == 0);
                    CHECK(message.find('\n') == std::string::npos);
                } catch (const std::exception& e) {
                    FAIL_CHECK("not an ink::Error: " << e.what());
                }
                CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
                ++files;
            }
        }
    }
    CHECK(files >= 15);
}

// Writes each (name, bytes) file and renders it at 128², refined two levels (enough to draw; a mesh's 20,000 face
// samples gave 338,000 points at the default four, 18 s a file under the sanitizers): it must draw. Two test
// cases, so that they run side by side.
static void rendersEach(const std::vector<std::pair<const char*, std::string>>& files) {
    TempDir dir;
    for (const auto& entry : files) {
        const char* file = entry.first;  // CAPTURE's lambda cannot capture a structured binding before clang 16
        CAPTURE(file);
        std::string model = dir.write(file, entry.second);
        std::string png = (dir.path / (std::string(file) + ".png")).string();
        Run r = runInkwell("render " + model + " -o " + png + " --size 128 128 --levels 2");
        CAPTURE(r.output);
        CHECK(r.status == 0);
        CHECK(fs::exists(png));
    }
}

TEST_CASE("readers: each new mesh format (STL, OFF) fits and renders through the command line" *
          doctest::test_suite("cli")) {
    std::string tetraOff = "OFF\n4 4 6\n";
    for (const Vector3d& v : kTetra)
        tetraOff += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
    for (const auto& f : kTetraFaces)
        tetraOff += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    rendersEach({
        {"cube.stl", binaryStl(cubeTriangles(), "solid")},
        {"cube-ascii.stl", asciiStl(cubeTriangles())},
        {"cube.off", kCubeOff},
        {"tetra.off", tetraOff},
    });
}

TEST_CASE("readers: each new point and glTF format fits and renders through the command line" *
          doctest::test_suite("cli")) {
    std::string xyz;
    for (int i = 0; i < 200; ++i) {  // points on a sphere
        double z = 1 - 2 * (i + 0.5) / 200, r = std::sqrt(1 - z * z), a = i * 2.399963;
        Vector3d v(r * std::cos(a), r * std::sin(a), z);
        xyz += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + " " +
               std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
    }
    rendersEach({
        {"sphere.xyz", "200\n" + xyz},
        {"sphere.pwn", xyz},
        {"tetra.glb", glb(tetraJson("\"scale\": [2, 1, 1]", ""), tetraBuffer())},
        {"tetra.gltf", tetraJson("", "data:application/octet-stream;base64," + base64(tetraBuffer()))},
    });
}

TEST_CASE("readers: a PLY header of a million elements is read in one pass (it was quadratic: 100 s for 200,000)" *
          doctest::test_suite("unit")) {
    // Each element is checked against the names before it with a set; a scan of the earlier ones would take an
    // hour here and CTest's timeout would fail the test.
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\n";
    for (int i = 0; i < 1000000; ++i) ply += "element e" + std::to_string(i) + " 0\n";
    ply += "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    ink::OrientedPoints points = ink::parsePoints(ply, "ply", "many.ply");
    CHECK(points.positions.size() == 3);
    CHECK(points.normals[0].z() == doctest::Approx(1.0));
    // A repeated name is still refused, also far apart.
    std::string twice = ply;
    twice.replace(twice.find("element e999999 0"), 17, "element e7 0");
    CHECK_THROWS_WITH_AS(ink::parsePoints(twice, "ply", "twice.ply"), doctest::Contains("a second element 'e7'"),
                         ink::Error);
}

TEST_CASE("readers: a mesh's normals given as zero take their faces' normals (OBJ, PLY, OFF, glTF), with a note" *
          doctest::test_suite("unit")) {
    // The tetrahedron with its given normals (its corners' directions from the centre, which are also its area
    // normals) except corner 2's, written as 0 0 0; checkTetra wants every normal to be the area normal.
    auto given = [](int i) { return i == 2 ? Vector3d::Zero() : kTetra[i].normalized(); };
    auto number = [](double x) { return std::to_string(x); };
    auto check = [&](const std::string& bytes, const char* format, const std::string& name) {
        CAPTURE(format);
        Notes notes;
        ink::ScopedReporter reporting(notes.reporter);
        checkTetra(parsePoints(bytes, format, name));
        REQUIRE(notes.lines.size() == 1);
        CHECK(notes.lines[0] == name + ": 1 vertex with a zero normal in the file takes its faces' normal");
    };
    std::string objText,
        plyText =
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "element face 4\nproperty list uchar int vertex_indices\nend_header\n",
        offText = "NOFF\n4 4 0\n";
    for (int i = 0; i < 4; ++i) {
        std::string p = number(kTetra[i].x()) + " " + number(kTetra[i].y()) + " " + number(kTetra[i].z()),
                    n = number(given(i).x()) + " " + number(given(i).y()) + " " + number(given(i).z());
        objText += "v " + p + "\nvn " + n + "\n";
        plyText += p + " " + n + "\n";
        offText += p + " " + n + "\n";
    }
    for (const auto& f : kTetraFaces) {
        objText += "f " + std::to_string(f[0] + 1) + "//" + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) +
                   "//" + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "//" + std::to_string(f[2] + 1) +
                   "\n";
        plyText += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
        offText += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    }
    check(objText, "obj", "t.obj");
    check(plyText, "ply", "t.ply");
    check(offText, "off", "t.off");
    // glTF: the tetrahedron's buffer with a NORMAL accessor after the indices.
    std::string bin = tetraBuffer();
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) put(bin, float(given(i)[k]));
    std::string json = tetraJson("", "");
    const std::string from = "\"POSITION\": 0}", to = "\"POSITION\": 0, \"NORMAL\": 2}";
    json.replace(json.find(from), from.size(), to);
    json.replace(
        json.find("\"type\": \"SCALAR\"}"), 17,
        "\"type\": \"SCALAR\"}, {\"bufferView\": 2, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"}");
    json.replace(json.find("\"byteLength\": 24}"), 17,
                 "\"byteLength\": 24}, {\"buffer\": 0, \"byteOffset\": 72, \"byteLength\": 48}");
    json.replace(json.find("{\"byteLength\": 72}"), 18, "{\"byteLength\": 120}");
    check(glb(json, bin), "glb", "t.glb");

    // A point cloud's zero normal cannot be replaced ("readers: OFF" above); nor can one on a vertex whose faces'
    // windings cancel, which OBJ refuses. One whose faces have no area takes its neighbours' in OBJ (below;
    // test_points.cpp: refused when no vertex is left).
    bad(objText + "v 3 3 3\nv 3 4 3\nv 4 3 3\nvn 0 0 0\nf 5//5 6//5 7//5\nf 5//5 7//5 6//5\n", "obj",
        "vertex 5 (line 13): normal is zero (the faces around it have no area, or their windings cancel)");
    Notes notes;
    ink::ScopedReporter reporting(notes.reporter);
    // A sliver from corner 1 (a zero-area face; its two new corners' normals zero): they take corner 1's, and the
    // mesh keeps the face. A sliver of such corners alone has no neighbour to take one from: it goes.
    const std::string sliver = objText + "v 0.5 0.5 0.5\nv 2 2 2\nvn 0 0 0\nf 1//1 5//5 6//5\n";
    OrientedPoints p = parsePoints(sliver, "obj", "s.obj");
    REQUIRE(p.positions.size() == 6);
    CHECK(near(p.normals[4], kTetra[0].normalized()));
    CHECK(near(p.normals[5], kTetra[0].normalized()));
    CHECK(p.triangles.size() == 5);
    REQUIRE(notes.lines.size() == 2);
    CHECK(notes.lines[1] ==
          "s.obj: 2 vertices with a zero normal in the file and faces without area take their neighbours' normal");
    notes.lines.clear();
    p = parsePoints(objText + "v 5 5 5\nv 6 6 6\nv 7 7 7\nvn 0 0 0\nf 5//5 6//5 7//5\n", "obj", "d.obj");
    CHECK(p.positions.size() == 4);
    CHECK(p.triangles.size() == 4);
    REQUIRE(notes.lines.size() == 2);
    CHECK(
        notes.lines[1] ==
        "d.obj: dropped 3 vertices with a zero normal in the file, faces without area and no neighbour with a normal");
}
