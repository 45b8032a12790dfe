#include "base/common.h"
#include "io/points.h"
#include "temp_dir.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

using Eigen::Vector3d;
using ink::Error;
using ink::OrientedPoints;
using ink::parsePoints;

namespace {

// Little byte writer for binary PLY bodies.
struct Bytes {
    bool bigEndian;
    std::string data;

    template <class T>
    Bytes& put(T value) {
        char b[sizeof(T)];
        std::memcpy(b, &value, sizeof b);
        if (bigEndian != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof b);
        data.append(b, sizeof b);
        return *this;
    }
};

bool near(const Vector3d& a, const Vector3d& b, double eps = 1e-9) { return (a - b).norm() <= eps; }

bool allUnit(const OrientedPoints& p) {
    for (const Vector3d& n : p.normals)
        if (std::abs(n.norm() - 1.0) > 1e-12) return false;
    return p.normals.size() == p.positions.size();
}

// A point cloud's normals may also be zero (none in the file: the fit estimates them); a mesh's may not.
bool unitOrCloudZero(const OrientedPoints& p) {
    for (const Vector3d& n : p.normals)
        if (std::abs(n.norm() - 1.0) > 1e-12 && !(p.triangles.empty() && n == Vector3d::Zero())) return false;
    return p.normals.size() == p.positions.size();
}

OrientedPoints obj(const std::string& text) { return parsePoints(text, "obj", "t.obj"); }
OrientedPoints ply(const std::string& bytes) { return parsePoints(bytes, "ply", "t.ply"); }
OrientedPoints pts(const std::string& text) { return parsePoints(text, "pts", "t.pts"); }

// Unit cube with outward (counter-clockwise seen from outside) quads.
const char* kCube = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

}  // namespace

// --- OBJ -------------------------------------------------------------------------------------------------

TEST_CASE("points: obj with vn uses the given normals, averaged per vertex" * doctest::test_suite("unit")) {
    OrientedPoints p =
        obj("# two triangles sharing an edge, with different normals\n"
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
            "vn 0 0 2\nvn 1 0 0\n"
            "f 1//1 2//1 3//1\n"
            "f 2/1/2 4/1/2 3/1/2\n"
            "vt 0 0\n");
    REQUIRE(p.positions.size() == 4);
    CHECK(allUnit(p));
    CHECK(near(p.normals[0], {0, 0, 1}));
    CHECK(near(p.normals[3], {1, 0, 0}));
    CHECK(near(p.normals[1], Vector3d(1, 0, 1).normalized()));
    CHECK(near(p.positions[3], {1, 1, 0}));
}

TEST_CASE("points: obj without normals gets area-weighted vertex normals" * doctest::test_suite("unit")) {
    SUBCASE("cube corners point diagonally outward") {
        OrientedPoints p = obj(kCube);
        REQUIRE(p.positions.size() == 8);
        CHECK(allUnit(p));
        Vector3d center(0.5, 0.5, 0.5);
        for (size_t i = 0; i < 8; ++i) CHECK(near(p.normals[i], (p.positions[i] - center).normalized()));
    }
    SUBCASE("larger faces weigh more") {
        // Vertex 1 touches a big triangle in the xy plane and a small one in the xz plane.
        OrientedPoints p = obj("v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 -1\nv 1 0 0\nf 1 2 3\nf 1 4 5\n");
        REQUIRE(p.positions.size() == 5);
        // Areas 8 (normal +z) and 0.5 (normal +y... orientation of 1,4,5: (0,0,-1)x(1,0,0) = (0,-1,0)).
        CHECK(near(p.normals[0], Vector3d(0, -0.5, 8).normalized()));
    }
    SUBCASE("tetrahedron normals point away from its centroid") {
        OrientedPoints p = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
        REQUIRE(p.positions.size() == 4);
        Vector3d centroid(0.25, 0.25, 0.25);
        for (size_t i = 0; i < 4; ++i) CHECK(p.normals[i].dot(p.positions[i] - centroid) > 0.4);
    }
}

TEST_CASE("points: computed normals do not depend on the model's scale" * doctest::test_suite("unit")) {
    for (const char* scale : {"1e-9", "1", "1e120"}) {
        std::string s = scale;
        OrientedPoints p = obj("v 0 0 0\nv " + s + " 0 0\nv 0 " + s + " 0\nf 1 2 3\n");
        REQUIRE(p.positions.size() == 3);
        for (const Vector3d& n : p.normals) CHECK(near(n, {0, 0, 1}));
    }
    // Near the top of double's range a face's area vector is finite but its length is not (a fuzzing find:
    // the normals came out zero); the same for a normal given that long.
    OrientedPoints huge = obj("v 0 0 0\nv 1e308 1.5 0\nv 1e308 0 1.5\nf 1 2 3\n");
    REQUIRE(huge.positions.size() == 3);
    CHECK(allUnit(huge));
    for (const Vector3d& n : huge.normals) CHECK(near(n, Vector3d(0, -1, -1).normalized()));
    OrientedPoints given = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1.5e308 1.5e308 0\nf 1//1 2//1 3//1\n");
    CHECK(allUnit(given));
    CHECK(near(given.normals[0], Vector3d(1, 1, 0).normalized()));
    OrientedPoints cloud = parsePoints("1e308 0 0 1.5e308 1.5e308 0\n", "pts", "huge.pts");
    CHECK(allUnit(cloud));
    // A sliver next to a big triangle is still a real face, but a needle with no area is not.
    CHECK(obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 1e-5\nv 6 5 0\nv 5 6 0\nf 1 2 3\nf 4 5 6\n").positions.size() == 6);
    CHECK_THROWS_WITH_AS(
        obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 0\nv 6 5 0\nv 7 5 1e-300\nf 1 2 3\nf 4 5 6\n"),
        doctest::Contains(
            "vertex 4 (line 4): normal is zero (the faces around it have no area, or their windings cancel)"),
        Error);
}

TEST_CASE("points: obj polygons, negative indices, unreferenced vertices" * doctest::test_suite("unit")) {
    // A pentagon in the xy plane by relative indices, plus a vertex no face uses.
    OrientedPoints p =
        obj("v 9 9 9\n"
            "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 3 0\nv -1 1 0\n"
            "f -5 -4 -3 -2 -1\n");
    REQUIRE(p.positions.size() == 5);
    CHECK(near(p.positions[0], {0, 0, 0}));
    for (const Vector3d& n : p.normals) CHECK(near(n, {0, 0, 1}));

    // Mixed: relative and absolute, forward references, groups and materials tinyobjloader must skip.
    OrientedPoints q =
        obj("mtllib nowhere.mtl\no thing\ng part\nusemtl red\ns 1\n"
            "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nl 1 2\n");
    CHECK(q.positions.size() == 3);

    // Lines we ignore are ignored, however tinyobjloader would have read them (it refuses `p 0`, and a
    // `vw` weight out of int range was undefined behaviour in it: fuzzing, docs/robustness.md).
    CHECK(obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\np 0\nl 0 9\nvw 0 00 0 1e3080\nt x 1/1/1 a b\n").positions.size() ==
          3);
}

TEST_CASE("points: obj point cloud pairs v with vn in order" * doctest::test_suite("unit")) {
    OrientedPoints p = obj("v 0 0 0\nvn 0 0 3\nv 1 0 0 # a comment\nvn 1 0 0\n");
    REQUIRE(p.positions.size() == 2);
    CHECK(near(p.normals[0], {0, 0, 1}));
    CHECK(near(p.normals[1], {1, 0, 0}));
}

TEST_CASE("points: obj keeps double precision and accepts CRLF" * doctest::test_suite("unit")) {
    OrientedPoints p = obj("v 0.123456789012345 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n");
    REQUIRE(p.positions.size() == 3);
    CHECK(p.positions[0].x() == 0.123456789012345);
}

TEST_CASE("points: bad obj input" * doctest::test_suite("unit")) {
    auto bad = [](const std::string& text, const char* words) {
        CHECK_THROWS_WITH_AS(obj(text), doctest::Contains(words), Error);
    };
    bad("", "t.obj: no vertices");
    bad("# nothing\n", "no vertices");
    bad("v 0 0 0\nv 1 0 0\nvn 0 0 1\n", "do not pair up");
    bad("v 0 0 0\nv 1 abc 0\n", "t.obj: line 2: 'abc' is not a number");
    bad("v 0 0\n", "line 1: expected 3 to 7 numbers");
    bad("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: coordinate is not finite");
    bad("v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: coordinate is not finite");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
        "line 4: face vertex index 9 is out of range (the file has 3 vertices)");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4: face vertex index -4 reaches before the first vertex");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4: '0' is not a face vertex");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "'x' is not a face vertex");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n", "'1/' is not a face vertex");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", "is not a face vertex");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "line 4: face has 2 vertices; at least 3 are needed");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", "face normal index 1 is out of range");
    // A zero normal given gives way to the face's (test_readers.cpp), unless the face has no area either.
    bad("v 0 0 0\nv 1 0 0\nv 2 0 0\nvn 0 0 0\nf 1//1 2//1 3//1\n",
        "t.obj: every vertex the faces use has a zero normal in the file and faces without area");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 nan 1\nf 1//1 2//1 3//1\n", "t.obj: line 4: normal is not finite");
    bad("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "t.obj: vertex 1 (line 1): normal is zero");
    bad("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/3000000000 2 3\n",
        "line 4: face texture coordinate index 3000000000 is out of range");
    bad(std::string("v 0 0 0\nv 1\0 0 0\n", 16), "line 2: binary data");
    std::string huge = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
    for (int i = 0; i < 300; ++i) huge += " 1";
    bad(huge, "at most 255");
}

// --- PLY -------------------------------------------------------------------------------------------------

TEST_CASE("points: ply ascii with normals" * doctest::test_suite("unit")) {
    OrientedPoints p =
        ply("ply\nformat ascii 1.0\ncomment made by hand\nobj_info nothing\n"
            "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\nend_header\n"
            "0 0 0 0 0 5\n"
            "1 2 3 -1 0 0\n");
    REQUIRE(p.positions.size() == 2);
    CHECK(near(p.positions[1], {1, 2, 3}));
    CHECK(near(p.normals[0], {0, 0, 1}));
    CHECK(near(p.normals[1], {-1, 0, 0}));
}

TEST_CASE("points: ply ascii with faces only, extra property and extra element skipped" * doctest::test_suite("unit")) {
    OrientedPoints p =
        ply("ply\r\nformat ascii 1.0\r\n"
            "element vertex 5\r\nproperty double z\r\nproperty uchar red\r\nproperty double x\r\nproperty "
            "double y\r\n"
            "element edge 1\r\nproperty list uchar int pair\r\nproperty float weight\r\n"
            "element face 1\r\nproperty uchar flags\r\nproperty list uint8 int32 vertex_index\r\n"
            "end_header\r\n"
            "0 255 0 0\r\n0 0 1 0\r\n0 1 1 1\r\n0 2 0 1\r\n7 3 7 7\r\n"
            "2 0 1 0.5\r\n"
            "\r\n"
            "1 4 0 1 2 3\r\n");
    REQUIRE(p.positions.size() == 4);  // vertex 4 is in no face
    CHECK(near(p.positions[2], {1, 1, 0}));
    for (const Vector3d& n : p.normals) CHECK(near(n, {0, 0, 1}));
}

TEST_CASE("points: ply binary little endian, float, with normals" * doctest::test_suite("unit")) {
    std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
        "property float32 x\nproperty float32 y\nproperty float32 z\nproperty int16 extra\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "element face 1\nproperty list uchar uint vertex_indices\nend_header\n";
    Bytes b{false, header};
    b.put(1.5f).put(2.0f).put(-3.0f).put(int16_t(-7)).put(0.0f).put(3.0f).put(4.0f);
    b.put(0.0f).put(0.0f).put(0.0f).put(int16_t(9)).put(1.0f).put(0.0f).put(0.0f);
    b.put(uint8_t(3)).put(uint32_t(0)).put(uint32_t(1)).put(uint32_t(0));  // faces are ignored: normals win
    OrientedPoints p = ply(b.data);
    REQUIRE(p.positions.size() == 2);
    CHECK(near(p.positions[0], {1.5, 2, -3}));
    CHECK(near(p.normals[0], {0, 0.6, 0.8}));
    CHECK(near(p.normals[1], {1, 0, 0}));
}

TEST_CASE("points: ply binary big endian, double, faces only" * doctest::test_suite("unit")) {
    std::string header =
        "ply\nformat binary_big_endian 1.0\ncomment quad\nelement vertex 4\n"
        "property double x\nproperty double y\nproperty double z\nproperty list ushort char tags\n"
        "element face 1\nproperty list int uint16 vertex_indices\nproperty int8 flag\n"
        "element material 2\nproperty list uint32 float64 stuff\nend_header\n";
    Bytes b{true, header};
    double corners[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
    for (auto& c : corners) {
        b.put(c[0]).put(c[1]).put(c[2]);
        b.put(uint16_t(2)).put(int8_t(1)).put(int8_t(2));
    }
    b.put(int32_t(4)).put(uint16_t(3)).put(uint16_t(2)).put(uint16_t(1)).put(uint16_t(0)).put(int8_t(-1));
    b.put(uint32_t(1)).put(1.0).put(uint32_t(0));
    OrientedPoints p = ply(b.data);
    REQUIRE(p.positions.size() == 4);
    CHECK(near(p.positions[2], {2, 2, 0}));
    for (const Vector3d& n : p.normals) CHECK(near(n, {0, 0, -1}));  // clockwise seen from +z
}

namespace {

std::string binaryTriangleHeader(const char* format = "binary_little_endian", int vertices = 3) {
    return std::string("ply\nformat ") + format + " 1.0\nelement vertex " + std::to_string(vertices) +
           "\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

const char* kAsciiNormalsHeader =
    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\nend_header\n";

}  // namespace

TEST_CASE("points: bad ply input" * doctest::test_suite("unit")) {
    auto bad = [](const std::string& bytes, const char* words) {
        CHECK_THROWS_WITH_AS(ply(bytes), doctest::Contains(words), Error);
    };
    SUBCASE("header") {
        bad("", "not a PLY file");
        bad("plyx\n", "not a PLY file");
        bad("ply\nformat ascii 2.0\nend_header\n", "header line 2: bad format line");
        bad("ply\nformat binary_middle_endian 1.0\nend_header\n", "bad format line");
        bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "header has no end_header line");
        bad("ply\nelement vertex 1\nend_header\n", "header has no format line");
        bad("ply\nformat ascii 1.0\nelement vertex 4000000000\nend_header\n",
            "header line 3: element 'vertex' claims 4000000000 entries; the limit is 100000000");
        bad("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "bad element line");
        bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", "bad property line");
        bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n", "bad property line");
        bad("ply\nformat ascii 1.0\nproperty float x\nend_header\n", "property before any element");
        bad("ply\nformat ascii 1.0\n3 bogus\nend_header\n", "header line 3: unknown header keyword '3'");
        bad("ply\nformat ascii 1.0\nelement face 1\nend_header\n", "has no 'element vertex'");
        bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n",
            "lacks x, y or z");
        bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nend_header\n0 0 0 1\n",
            "some of nx, ny, nz");
        bad("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\nend_header\n",
            "t.ply: no vertices");
    }
    SUBCASE("absurd counts are refused before allocating") {
        bad(binaryTriangleHeader("binary_little_endian", 50000000) + std::string(100, '\0'),
            "truncated: expected 50000000 vertices, file ends in vertex 8");
        bad("ply\nformat ascii 1.0\nelement vertex 90000000\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n",
            "truncated: the header declares 90000000 vertices but only 6 bytes are left");
    }
    SUBCASE("truncated binary body") {
        Bytes b{false, binaryTriangleHeader()};
        b.put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(0.0f);
        bad(b.data, "t.ply: truncated: expected 3 vertices, file ends in vertex 1");
        Bytes c{false, binaryTriangleHeader()};
        for (int i = 0; i < 9; ++i) c.put(float(i == 3 || i == 7));
        c.put(uint8_t(3)).put(int32_t(0)).put(int32_t(1));
        bad(c.data, "truncated: expected 1 'face' entries, file ends in face 0");
    }
    SUBCASE("body values") {
        bad(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n0 0 zero 0 0 1\n",
            "t.ply: line 12 (vertex 1): 'zero' is not a number");
        bad(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n0 0 0 0 1\n", "line 12 (vertex 1): fewer values");
        bad(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n0 0 0 0 1 1 1\n", "line 12 (vertex 1): 1 more values");
        bad(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n",
            "truncated: expected 2 vertices, file ends in vertex 1");
        bad(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n0 nan 0 0 0 1\n",
            "t.ply: vertex 1: coordinate is not finite");
        bad(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n0 0 0 0 inf 1\n", "vertex 1: normal is not finite");

        Bytes b{false, binaryTriangleHeader()};
        for (int i = 0; i < 9; ++i) b.put(float(i == 3 || i == 7));
        b.put(uint8_t(3)).put(int32_t(0)).put(int32_t(3)).put(int32_t(1));
        bad(b.data, "t.ply: face 0: vertex index 3 is out of range (the file has 3 vertices)");

        Bytes n{true, binaryTriangleHeader("binary_big_endian")};
        for (int i = 0; i < 9; ++i) n.put(float(i == 3 || i == 7));
        n.put(uint8_t(3)).put(int32_t(0)).put(int32_t(-1)).put(int32_t(1));
        bad(n.data, "face 0: vertex index -1 is out of range");

        Bytes d{false, binaryTriangleHeader()};
        for (int i = 0; i < 9; ++i) d.put(i == 4 ? std::nanf("") : float(i == 3 || i == 7));
        d.put(uint8_t(3)).put(int32_t(0)).put(int32_t(1)).put(int32_t(2));
        bad(d.data, "t.ply: vertex 1: coordinate is not finite");

        Bytes z{false, binaryTriangleHeader()};
        for (int i = 0; i < 9; ++i) z.put(float(i == 3 || i == 6));  // three points on a line
        z.put(uint8_t(3)).put(int32_t(0)).put(int32_t(1)).put(int32_t(2));
        bad(z.data, "t.ply: vertex 0: normal is zero (the faces around it have no area, or their windings cancel)");

        Bytes s{false, binaryTriangleHeader()};
        for (int i = 0; i < 9; ++i) s.put(float(i == 3 || i == 7));
        s.put(uint8_t(2)).put(int32_t(0)).put(int32_t(1));
        bad(s.data, "face 0: has 2 vertices; at least 3 are needed");

        bad("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n9 0 1 "
            "2\n",
            "line 13 (face 0): list 'vertex_indices' claims 9 items but the line has 3 more values");
        bad("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 "
            "1.5 2\n",
            "'1.5' is not an integer");
    }
}

// --- Oriented point text ---------------------------------------------------------------------------------

TEST_CASE("points: oriented point text with comments and blank lines" * doctest::test_suite("unit")) {
    OrientedPoints p =
        pts("# x y z nx ny nz\n"
            "\n"
            "1 2 3 0 0 2   # trailing comment\n"
            "  \t\n"
            "-1e-3 +4 5.5\t1 1 0\r\n"
            "7 8 9 0 -3 0");
    REQUIRE(p.positions.size() == 3);
    CHECK(near(p.positions[1], {-1e-3, 4, 5.5}));
    CHECK(near(p.normals[0], {0, 0, 1}));
    CHECK(near(p.normals[1], Vector3d(1, 1, 0).normalized()));
    CHECK(near(p.normals[2], {0, -1, 0}));
}

TEST_CASE("points: a point cloud without normals, or with zero ones, is read with those normals zero" *
          doctest::test_suite("unit")) {
    // The fit estimates them (estimateNormals); a mesh's vertex still needs one (its faces' where the file's is zero).
    const auto zeroAt = [](const OrientedPoints& p, std::vector<size_t> zero) {
        REQUIRE(p.normals.size() == p.positions.size());
        CHECK(p.triangles.empty());
        for (size_t i = 0; i < p.normals.size(); ++i)
            CHECK(p.normals[i].squaredNorm() == doctest::Approx(std::find(zero.begin(), zero.end(), i) == zero.end()));
    };
    zeroAt(pts("1 2 3\n4 5 6\n# x y z\n7 8 9\n"), {0, 1, 2});
    CHECK(pts("1 2 3\n4 5 6\n").positions[1] == Vector3d(4, 5, 6));
    zeroAt(pts("1 2 3 0 0 1\n1 2 4 0 0 0\n"), {1});
    zeroAt(obj("v 0 0 0\nv 1 0 0\n"), {0, 1});
    zeroAt(ply("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
               "end_header\n0 0 0\n1 0 0\n"),
           {0, 1});
    zeroAt(ply(std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n0 0 0 0 0 0\n"), {1});
    zeroAt(parsePoints("OFF\n2 0 0\n0 0 0\n1 0 0\n", "off", "t.off"), {0, 1});
    zeroAt(parsePoints("3\n0 0 0\n1 0 0\n0 1 0\n", "xyz", "t.xyz"), {0, 1, 2});
}

TEST_CASE("points: bad oriented point text" * doctest::test_suite("unit")) {
    auto bad = [](const std::string& text, const char* words) {
        CHECK_THROWS_WITH_AS(pts(text), doctest::Contains(words), Error);
    };
    bad("", "t.pts: no vertices");
    bad("# only a comment\n\n", "no vertices");
    bad("1 2 3 0 0 1\n1 2 3 0 0\n", "t.pts: line 2: expected 6 numbers (x y z nx ny nz), found 5 fields");
    bad("1 2 3 0 0 1 7\n", "line 1: expected 6 numbers");
    bad("1 2 3 0 0 1\n\n1 2 three 0 0 1\n", "t.pts: line 3: 'three' is not a number");
    bad("1 2 3\n1 2 3 0 0 1\n", "t.pts: line 2: expected 3 numbers (x y z, as the first point), found 6 fields");
    bad("1 2 3 0\n", "t.pts: line 1: expected 6 numbers (x y z nx ny nz) or 3 (x y z), found 4 fields");
    bad("1 2 3 0 0 1\n1 2 inf 0 0 1\n", "line 2: coordinate is not finite");
    bad("1 2 3 0 0 1\n1 2 3 nan 0 1\n", "line 2: normal is not finite");
    bad(std::string("1 2 3 0 0 1\n\0\n", 14), "line 2: binary data");
}

TEST_CASE("points: parsePoints refuses an unknown format" * doctest::test_suite("unit")) {
    CHECK_THROWS_WITH_AS(parsePoints("", "3ds", "x.3ds"), doctest::Contains("unknown point format '3ds'"), Error);
}

TEST_CASE("points: garbage input only ever throws ink::Error" * doctest::test_suite("unit")) {
    std::mt19937 rng(12345);
    std::string valid = binaryTriangleHeader();
    Bytes b{false, valid};
    for (int i = 0; i < 9; ++i) b.put(float(i == 3 || i == 7));
    b.put(uint8_t(3)).put(int32_t(0)).put(int32_t(1)).put(int32_t(2));
    std::string asciiPly = std::string(kAsciiNormalsHeader) + "0 0 0 0 0 1\n1 2 3 1 0 0\n";
    const std::string seeds[] = {b.data, asciiPly, kCube, "1 2 3 0 0 1\n4 5 6 1 0 0\n"};
    const char* formats[] = {"ply", "obj", "pts"};
    int parsed = 0, refused = 0;
    for (int round = 0; round < 3000; ++round) {
        std::string bytes;
        if (round % 3 == 0) {
            bytes.resize(rng() % 300);
            for (char& c : bytes) c = char(rng());
        } else {
            bytes = seeds[rng() % 4];
            int edits = 1 + int(rng() % 4);
            for (int e = 0; e < edits && !bytes.empty(); ++e) {
                size_t at = rng() % bytes.size();
                switch (rng() % 3) {
                    case 0:
                        bytes[at] = char(rng());
                        break;
                    case 1:
                        bytes.erase(at, 1 + rng() % 8);
                        break;
                    default:
                        bytes.resize(at);
                        break;
                }
            }
        }
        for (const char* format : formats) {
            try {
                OrientedPoints p = parsePoints(bytes, format, "g");
                CHECK(unitOrCloudZero(p));
                ++parsed;
            } catch (const Error&) {
                ++refused;
            }
        }
    }
    CHECK(refused > 0);
    CHECK(parsed > 0);
}

// --- Cleaning and sampling -------------------------------------------------------------------------------

namespace {

OrientedPoints cloud(std::vector<Vector3d> positions) {
    OrientedPoints p;
    for (size_t i = 0; i < positions.size(); ++i) p.normals.emplace_back(double(i), 0, 0);
    p.positions = std::move(positions);
    return p;
}

}  // namespace

TEST_CASE("points: mergeDuplicates keeps the first of each cluster, in order" * doctest::test_suite("unit")) {
    SUBCASE("exact duplicates") {
        OrientedPoints p = cloud({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {-0.0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1e-15, 0}});
        CHECK(ink::mergeDuplicates(p, 0) == 3);
        REQUIRE(p.positions.size() == 4);
        CHECK(p.positions[0] == Vector3d(0, 0, 0));
        CHECK(p.positions[1] == Vector3d(1, 0, 0));
        CHECK(p.positions[2] == Vector3d(2, 0, 0));
        CHECK(p.positions[3] == Vector3d(1, 1e-15, 0));
        CHECK(p.normals[1].x() == 1);  // the normal travels with its point
        CHECK(p.normals[2].x() == 5);
        CHECK(p.normals[3].x() == 6);
    }
    SUBCASE("within a tolerance, across cell borders") {
        OrientedPoints p = cloud({{0.5, 0.5, 0.5},
                                  {0.99, 0, 0},
                                  {1.01, 0, 0},
                                  {0.5, 0.5, 0.5 + 5e-3},
                                  {3, 3, 3},
                                  {3, 3, 3.02},
                                  {3, 3, 3.04}});
        CHECK(ink::mergeDuplicates(p, 0.021) == 3);
        // 3.04 is within tolerance of 3.02, which was dropped, but not of 3, which was kept: it stays.
        REQUIRE(p.positions.size() == 4);
        CHECK(p.positions[1] == Vector3d(0.99, 0, 0));
        CHECK(p.positions[3] == Vector3d(3, 3, 3.04));
        CHECK(p.normals[3].x() == 6);
    }
    SUBCASE("no duplicates, negative coordinates, deterministic") {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-10, 10);
        std::vector<Vector3d> v;
        for (int i = 0; i < 2000; ++i) v.emplace_back(u(rng), u(rng), u(rng));
        OrientedPoints a = cloud(v), b = cloud(v);
        size_t merged = ink::mergeDuplicates(a, 0.5);
        CHECK(ink::mergeDuplicates(b, 0.5) == merged);
        CHECK(a.positions == b.positions);
        // Brute force: every kept point is farther than the tolerance from every other kept point.
        bool separated = true;
        for (size_t i = 0; i < a.positions.size(); ++i)
            for (size_t j = i + 1; j < a.positions.size(); ++j)
                separated &= (a.positions[i] - a.positions[j]).norm() > 0.5;
        CHECK(separated);
        CHECK(a.positions.size() + merged == 2000);
        OrientedPoints c = cloud(v);
        CHECK(ink::mergeDuplicates(c, 1e-9) == 0);
        CHECK(c.positions == v);
    }
    SUBCASE("empty and huge coordinates") {
        OrientedPoints e;
        CHECK(ink::mergeDuplicates(e, 1) == 0);
        OrientedPoints h = cloud({{1e300, 0, 0}, {1e300, 0, 0}, {-1e300, 1e-300, 0}});
        CHECK(ink::mergeDuplicates(h, 1e-300) == 1);
        CHECK(h.positions.size() == 2);
    }
}

TEST_CASE("points: farthestPointSample" * doctest::test_suite("unit")) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vector3d> v;
    for (int i = 0; i < 500; ++i) v.emplace_back(u(rng), u(rng), u(rng));
    v.emplace_back(-1.5, 0.3, 0.2);  // the lexicographic minimum
    v.emplace_back(-1.5, 0.3, 0.2);  // a tie: the lower index wins

    std::vector<size_t> s = ink::farthestPointSample(v, 20);
    REQUIRE(s.size() == 20);
    CHECK(s == ink::farthestPointSample(v, 20));
    CHECK(s[0] == 500);
    double farthest = 0;
    for (const Vector3d& p : v) farthest = std::max(farthest, (p - v[500]).norm());
    CHECK((v[s[1]] - v[500]).norm() == farthest);
    std::vector<size_t> sorted = s;
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    // A prefix of a longer run is the shorter run.
    std::vector<size_t> longer = ink::farthestPointSample(v, 40);
    CHECK(std::equal(s.begin(), s.end(), longer.begin()));

    std::vector<size_t> all = ink::farthestPointSample(v, 1000);
    REQUIRE(all.size() == v.size());
    for (size_t i = 0; i < all.size(); ++i) CHECK(all[i] == i);
    CHECK(ink::farthestPointSample(v, 0).empty());
    CHECK(ink::farthestPointSample({}, 3).empty());
    // All points equal: still distinct indices, lowest first.
    std::vector<size_t> same = ink::farthestPointSample(std::vector<Vector3d>(5, Vector3d(1, 1, 1)), 3);
    CHECK(same == std::vector<size_t>{0, 1, 2});
}

// The definition, every distance updated at every pick, against the pruned tree the function uses: the same
// picks in the same order, on spread points, on a grid (many exact ties) and on clusters of duplicates.
TEST_CASE("points: farthestPointSample picks what the definition picks" * doctest::test_suite("unit")) {
    auto definition = [](const std::vector<Vector3d>& v, size_t count, const std::vector<Vector3d>* n = nullptr) {
        size_t first = 0;
        for (size_t i = 1; i < v.size(); ++i)
            if (std::tie(v[i].x(), v[i].y(), v[i].z()) < std::tie(v[first].x(), v[first].y(), v[first].z())) first = i;
        std::vector<double> d(v.size(), std::numeric_limits<double>::infinity());
        std::vector<size_t> picked{first};
        d[first] = -1;
        while (picked.size() < count) {
            size_t best = 0;
            double far = -1;
            for (size_t i = 0; i < v.size(); ++i) {
                if (d[i] < 0) continue;
                if (!n || (*n)[i].cast<float>().dot((*n)[picked.back()].cast<float>()) >= float(ink::kOtherSide))
                    d[i] = std::min(d[i], (v[i] - v[picked.back()]).squaredNorm());
                if (d[i] > far) far = d[i], best = i;
            }
            picked.push_back(best);
            d[best] = -1;
        }
        return picked;
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vector3d> spread, grid, clusters;
    for (int i = 0; i < 3000; ++i) spread.emplace_back(u(rng), 0.2 * u(rng), u(rng));
    for (int x = 0; x < 12; ++x)
        for (int y = 0; y < 12; ++y)
            for (int z = 0; z < 12; ++z) grid.emplace_back(x, y, 0.5 * z);
    std::shuffle(grid.begin(), grid.end(), rng);
    for (int c = 0; c < 40; ++c) {
        Vector3d centre(u(rng), u(rng), u(rng));
        for (int k = 0; k < 60; ++k)
            clusters.push_back(k % 3 ? centre : centre + 1e-3 * Vector3d(u(rng), u(rng), u(rng)));
    }
    std::vector<Vector3d> large;  // a deep tree, its first picks
    for (int i = 0; i < 70000; ++i) large.emplace_back(u(rng), u(rng), u(rng));
    large.push_back(large[123]);  // a tie
    CHECK(ink::farthestPointSample(large, 40) == definition(large, 40));
    for (const auto* v : {&spread, &grid, &clusters})
        for (size_t count : {size_t(2), size_t(97), size_t(700), v->size() - 1}) {
            CAPTURE(v->size());
            CAPTURE(count);
            CHECK(ink::farthestPointSample(*v, count) == definition(*v, count));
        }
    // With normals: random ones on the spread points, and the two sides of a thin plate.
    std::vector<Vector3d> normals, plate, plateNormals;
    for (size_t i = 0; i < spread.size(); ++i) normals.push_back(Vector3d(u(rng), u(rng), u(rng)).normalized());
    for (int x = 0; x < 30; ++x)
        for (int y = 0; y < 30; ++y)
            for (int side : {0, 1}) {
                plate.emplace_back(x / 29.0 + 1e-3 * u(rng), y / 29.0 + 1e-3 * u(rng), 0.01 * side);
                plateNormals.emplace_back(0, 0, side ? 1 : -1);
            }
    for (size_t count : {size_t(2), size_t(97), size_t(700)}) {
        CAPTURE(count);
        CHECK(ink::farthestPointSample(spread, count, &normals) == definition(spread, count, &normals));
        CHECK(ink::farthestPointSample(plate, count, &plateNormals) == definition(plate, count, &plateNormals));
    }
}

TEST_CASE("points: farthestPointSample with normals spreads each side of a thin plate on its own" *
          doctest::test_suite("unit")) {
    // A unit plate a hundredth thick, its two sides sampled on a jittered grid. By distance alone a pick on one
    // side stands for the other too: each side gets picks only where the other has none. With the normals, each
    // side's points are as near a pick of their own side as one side's alone would be.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vector3d> plate, normals;
    for (int x = 0; x < 40; ++x)
        for (int y = 0; y < 40; ++y)
            for (int side : {0, 1}) {
                plate.emplace_back(x / 39.0 + 2e-3 * u(rng), y / 39.0 + 2e-3 * u(rng), 0.01 * side);
                normals.emplace_back(0, 0, side ? 1 : -1);
            }
    // The farthest any point lies from a pick on its own side, and how many picks each side got.
    auto gap = [&](const std::vector<size_t>& picks, std::array<int, 2>* perSide) {
        double worst = 0;
        *perSide = {0, 0};
        for (size_t p : picks) ++(*perSide)[normals[p].z() > 0];
        for (size_t i = 0; i < plate.size(); ++i) {
            double nearest = INFINITY;
            for (size_t p : picks)
                if (normals[p].dot(normals[i]) > 0) nearest = std::min(nearest, (plate[p] - plate[i]).norm());
            worst = std::max(worst, nearest);
        }
        return worst;
    };
    std::array<int, 2> blind, sided;
    const double blindGap = gap(ink::farthestPointSample(plate, 64), &blind);
    const double sidedGap = gap(ink::farthestPointSample(plate, 64, &normals), &sided);
    INFO("by distance: worst gap " << blindGap << ", picks " << blind[0] << " + " << blind[1]
                                   << "; with normals: " << sidedGap << ", " << sided[0] << " + " << sided[1]);
    // One side alone, 32 picks: how near its points come to one.
    std::vector<Vector3d> top;
    for (size_t i = 0; i < plate.size(); ++i)
        if (normals[i].z() > 0) top.push_back(plate[i]);
    double alone = 0;
    const std::vector<size_t> topPicks = ink::farthestPointSample(top, 32);
    for (const Vector3d& p : top) {
        double nearest = INFINITY;
        for (size_t k : topPicks) nearest = std::min(nearest, (top[k] - p).norm());
        alone = std::max(alone, nearest);
    }
    INFO("one side alone: " << alone);
    CHECK(std::abs(sided[0] - sided[1]) <= 2);
    CHECK(sidedGap < 1.15 * alone);
    CHECK(blindGap > 1.4 * alone);
    CHECK_THROWS_WITH_AS(ink::farthestPointSample(std::vector<Vector3d>(3), 1, &normals),
                         "farthestPointSample: one normal a position", ink::Error);
}

// --- Files -----------------------------------------------------------------------------------------------

TEST_CASE("points: loadPoints" * doctest::test_suite("unit")) {
    SUBCASE("missing file") {
        CHECK_THROWS_WITH_AS(ink::loadPoints("/nonexistent/dir/x.obj"),
                             doctest::Contains("cannot open '/nonexistent/dir/x.obj': No such file or directory"),
                             Error);
    }
    SUBCASE("unsupported extension") {
        CHECK_THROWS_WITH_AS(ink::loadPoints("model.3ds"),
                             doctest::Contains("model.3ds: unsupported file extension '.3ds'; supported: .obj .ply "
                                               ".pts .xyzn .txt .xyz .pwn .off .stl .gltf .glb"),
                             Error);
        CHECK_THROWS_WITH_AS(ink::loadPoints("model"), doctest::Contains("no file extension"), Error);
    }
    SUBCASE("a file, case-insensitive extension, and a directory") {
        TempDir tmp;
        std::string path = tmp / "points.XYZN";
        std::FILE* f = std::fopen(path.c_str(), "wb");
        REQUIRE(f);
        std::fputs("0 0 0 0 0 1\n", f);
        std::fclose(f);
        OrientedPoints p = ink::loadPoints(path);
        std::remove(path.c_str());
        CHECK(p.positions.size() == 1);
        std::string dir = path.substr(0, path.size() - 5) + "_dir.ply";
        std::filesystem::create_directory(dir);
        CHECK_THROWS_WITH_AS(ink::loadPoints(dir), doctest::Contains("Is a directory"), Error);
        std::filesystem::remove(dir);
    }
    SUBCASE("the bundled bunny") {
        OrientedPoints p = ink::loadPoints(INKWELL_SOURCE_DIR "/assets/bunny.obj");
        CHECK(p.positions.size() == 1839);  // every vertex is used by a face
        CHECK(allUnit(p));
        Vector3d centroid = Vector3d::Zero();
        for (const Vector3d& x : p.positions) centroid += x;
        centroid /= double(p.positions.size());
        double outward = 0;
        for (size_t i = 0; i < p.positions.size(); ++i) outward += p.normals[i].dot(p.positions[i] - centroid);
        CHECK(outward / double(p.positions.size()) > 0);
    }
}
