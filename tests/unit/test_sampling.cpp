// Meshes keep their triangles through every reader and the cleaning, and face sampling (surface_sampling.h)
// spreads oriented points over them: area-proportional, deterministic, on the faces, with interpolated normals.
#include "base/triangle.h"
#include "io/points.h"
#include "surface/clean.h"
#include "surface/model.h"
#include "surface/surface_sampling.h"

#include "glb_writer.h"

#include <doctest/doctest.h>

#include <map>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using Eigen::Vector3d;
using ink::OrientedPoints;
using ink::parsePoints;
using ink::Triangle;

namespace {

using Corners = std::array<Vector3d, 3>;

// A triangle's corners, turned so that the lexicographically smallest comes first (the winding kept), so that
// triangles compare by where they are whatever the numbering.
Corners canonical(Corners c) {
    auto less = [](const Vector3d& a, const Vector3d& b) {
        return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    };
    while (less(c[1], c[0]) || less(c[2], c[0])) std::rotate(c.begin(), c.begin() + 1, c.end());
    return c;
}

std::vector<Corners> sorted(std::vector<Corners> list) {
    for (Corners& c : list) c = canonical(c);
    std::sort(list.begin(), list.end(), [](const Corners& a, const Corners& b) {
        return std::lexicographical_compare(a[0].data(), a[0].data() + 9, b[0].data(), b[0].data() + 9);
    });
    return list;
}

// The mesh's triangles as positions; every index must be in range.
std::vector<Corners> trianglesOf(const OrientedPoints& p) {
    std::vector<Corners> out;
    for (const Triangle& t : p.triangles) {
        for (uint32_t i : t) REQUIRE(i < p.positions.size());
        out.push_back({p.positions[t[0]], p.positions[t[1]], p.positions[t[2]]});
    }
    return out;
}

void checkTriangles(const OrientedPoints& p, const std::vector<Corners>& expected, double eps = 1e-6) {
    std::vector<Corners> got = sorted(trianglesOf(p)), want = sorted(expected);
    REQUIRE(got.size() == want.size());
    for (size_t i = 0; i < got.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            INFO("triangle " << i << " corner " << k << ": " << got[i][k].transpose() << " vs "
                             << want[i][k].transpose());
            CHECK((got[i][k] - want[i][k]).norm() <= eps);
        }
}

Vector3d v(double x, double y, double z) { return Vector3d(x, y, z); }

// The closest triangle to p and its distance.
std::pair<size_t, double> nearestTriangle(const OrientedPoints& mesh, const Vector3d& p) {
    size_t best = 0;
    double bestDistance = INFINITY;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        double d =
            (ink::closestPointOnTriangle(p, mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]) - p)
                .norm();
        if (d < bestDistance) {
            bestDistance = d;
            best = t;
        }
    }
    return {best, bestDistance};
}

// An octahedron with its vertices' normals pointing out from the centre: smooth normals that differ by 90°.
OrientedPoints octahedron() {
    OrientedPoints m;
    for (int a = 0; a < 3; ++a)
        for (double s : {1.0, -1.0}) {
            Vector3d p = Vector3d::Zero();
            p[a] = s;
            m.positions.push_back(p);
            m.normals.push_back(p);
        }
    // +x 0, -x 1, +y 2, -y 3, +z 4, -z 5; counter-clockwise from outside.
    for (uint32_t x : {0u, 1u})
        for (uint32_t y : {2u, 3u})
            for (uint32_t z : {4u, 5u}) {
                bool flip = ((x == 1) != (y == 3)) != (z == 5);
                m.triangles.push_back(flip ? Triangle{x, z, y} : Triangle{x, y, z});
            }
    return m;
}

// Separate triangles of different areas, in the z = 0 plane, far apart: a sample belongs to one without doubt.
OrientedPoints separateTriangles(const std::vector<double>& scales) {
    OrientedPoints m;
    for (size_t i = 0; i < scales.size(); ++i) {
        Vector3d o(10.0 * double(i), 0, 0);
        uint32_t first = uint32_t(m.positions.size());
        for (Vector3d c : {v(0, 0, 0), v(1, 0, 0), v(0.3, 1, 0)}) {
            m.positions.push_back(o + scales[i] * c);
            m.normals.push_back(v(0, 0, 1));
        }
        m.triangles.push_back({first, first + 1, first + 2});
    }
    return m;
}

double angle(const Vector3d& a, const Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// An octagonal prism (circumradius 1, z in [-h, h], capped by fans) as an OBJ without normals.
std::string prismObj(double h) {
    std::string obj;
    for (double z : {h, -h})
        for (int i = 0; i < 8; ++i)
            obj += "v " + std::to_string(std::cos(M_PI * i / 4)) + " " + std::to_string(std::sin(M_PI * i / 4)) + " " +
                   std::to_string(z) + "\n";
    obj += "v 0 0 " + std::to_string(h) + "\nv 0 0 " + std::to_string(-h) + "\n";
    auto face = [&](int a, int b, int c) {
        obj += "f " + std::to_string(a + 1) + " " + std::to_string(b + 1) + " " + std::to_string(c + 1) + "\n";
    };
    for (int i = 0; i < 8; ++i) {
        const int j = (i + 1) % 8;
        face(i, 8 + i, 8 + j);  // the side, outward
        face(i, 8 + j, j);
        face(16, i, j);          // the top, +z
        face(17, 8 + j, 8 + i);  // the bottom, -z
    }
    return obj;
}

// Per triangle of `mesh`, the farthest its samples lie off its plane (0 for a triangle without samples).
std::vector<double> offPlanes(const OrientedPoints& mesh, const OrientedPoints& s, const std::vector<uint32_t>& of) {
    std::vector<double> off(mesh.triangles.size(), 0.0);
    for (size_t i = 0; i < s.positions.size(); ++i) {
        const Triangle& t = mesh.triangles[of[i]];
        const Vector3d &p0 = mesh.positions[t[0]], &p1 = mesh.positions[t[1]], &p2 = mesh.positions[t[2]];
        off[of[i]] = std::max(off[of[i]], std::abs((s.positions[i] - p0).dot((p1 - p0).cross(p2 - p0).normalized())));
    }
    return off;
}

}  // namespace

TEST_CASE("sampling: OBJ polygons are fan-triangulated in the numbering of the vertices kept" *
          doctest::test_suite("unit")) {
    // Vertex 1 is used by no face and dropped; a quad and a pentagon, one with a normal given.
    OrientedPoints p = parsePoints(R"(v 9 9 9
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 3 0.5 0
v 2 1 0
vn 0 0 1
f 2 3 4 5
f 3//1 6 7 8 4
)",
                                   "obj", "t.obj");
    REQUIRE(p.positions.size() == 7);
    checkTriangles(p, {{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)},
                       {v(0, 0, 0), v(1, 1, 0), v(0, 1, 0)},
                       {v(1, 0, 0), v(2, 0, 0), v(3, 0.5, 0)},
                       {v(1, 0, 0), v(3, 0.5, 0), v(2, 1, 0)},
                       {v(1, 0, 0), v(2, 1, 0), v(1, 1, 0)}});
    SUBCASE("a point cloud written as OBJ has none") {
        OrientedPoints cloud = parsePoints("v 0 0 0\nvn 0 0 1\nv 1 0 0\nvn 0 0 1\n", "obj", "t.obj");
        CHECK(cloud.triangles.empty());
    }
}

TEST_CASE("sampling: OFF and PLY faces, with and without normals, unused vertices dropped" *
          doctest::test_suite("unit")) {
    const std::vector<Corners> quad = {{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)}, {v(0, 0, 0), v(1, 1, 0), v(0, 1, 0)}};
    SUBCASE("OFF: vertex 0 unused") {
        checkTriangles(parsePoints("OFF\n5 1 0\n7 7 7\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 1 2 3 4\n", "off", "t.off"), quad);
    }
    SUBCASE("NOFF: every vertex kept, the indices as written") {
        OrientedPoints p =
            parsePoints("NOFF\n5 1 0\n7 7 7 0 0 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 1 2 3 4\n",
                        "off", "t.off");
        CHECK(p.positions.size() == 5);
        checkTriangles(p, quad);
    }
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    SUBCASE("PLY without normals: vertex 0 unused") {
        checkTriangles(parsePoints(header + faces + "7 7 7\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 1 2 3 4\n", "ply", "t.ply"),
                       quad);
    }
    SUBCASE("PLY with normals") {
        OrientedPoints p =
            parsePoints(header + "property float nx\nproperty float ny\nproperty float nz\n" + faces +
                            "7 7 7 0 0 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 1 2 3 4\n",
                        "ply", "t.ply");
        CHECK(p.positions.size() == 5);
        checkTriangles(p, quad);
    }
    SUBCASE("a PLY point cloud has none") {
        OrientedPoints p = parsePoints(
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n",
            "ply", "t.ply");
        CHECK(p.triangles.empty());
    }
}

TEST_CASE("sampling: STL triangles after welding; a vertex only zero-area triangles use goes with them" *
          doctest::test_suite("unit")) {
    // Two triangles of a square, and a sliver whose third corner lies on an edge and is used by nothing else.
    std::string stl = "solid t\n";
    auto facet = [&](const Corners& c) {
        stl += "facet normal 0 0 0\nouter loop\n";
        for (const Vector3d& p : c)
            stl += "vertex " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
        stl += "endloop\nendfacet\n";
    };
    const Corners a{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)}, b{v(0, 0, 0), v(1, 1, 0), v(0, 1, 0)};
    facet(a);
    facet(b);
    facet({v(0, 0, 0), v(1, 0, 0), v(0.5, 0, 0)});
    stl += "endsolid t\n";
    OrientedPoints p = parsePoints(stl, "stl", "t.stl");
    CHECK(p.positions.size() == 4);
    checkTriangles(p, {a, b});
}

namespace {}  // namespace

TEST_CASE("sampling: glTF triangles of meshes with and without normals, node transforms applied" *
          doctest::test_suite("unit")) {
    // Mesh 0: a quad with NORMAL (4 vertices, 6 indices), under a node that translates by (0, 0, 5) and mirrors x.
    // Mesh 1: a triangle without normals (3 vertices, no indices) instanced twice: scaled by 2, and translated.
    // Mesh 0 comes twice too (nodes 0 and 3), so the given part's offsets are exercised.
    std::string bin;
    for (Vector3d p : {v(0, 0, 0), v(1, 0, 0), v(1, 1, 0), v(0, 1, 0)})
        for (int k = 0; k < 3; ++k) put(bin, float(p[k]));  // 0..47
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) put(bin, float(k == 2));  // 48..95
    for (uint16_t i : {0, 1, 2, 0, 2, 3}) put(bin, i);        // 96..107
    for (Vector3d p : {v(0, 0, 0), v(1, 0, 0), v(0, 1, 0)})
        for (int k = 0; k < 3; ++k) put(bin, float(p[k]));  // 108..143
    std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],
"nodes": [{"mesh": 0, "translation": [0, 0, 5], "scale": [-1, 1, 1]}, {"mesh": 1, "scale": [2, 2, 2]},
          {"mesh": 1, "translation": [10, 0, 0]}, {"mesh": 0, "translation": [0, 0, -5]}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]},
           {"primitives": [{"attributes": {"POSITION": 3}}]}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
              {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
              {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
              {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3"}],
"bufferViews": [{"buffer": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 12},
                {"buffer": 0, "byteOffset": 108, "byteLength": 36}],
"buffers": [{"byteLength": 144}]})";
    OrientedPoints p = parsePoints(glb(json, bin), "glb", "t.glb");
    CHECK(p.positions.size() == 4 + 4 + 3 + 3);
    // The mirrored quad's winding is turned round, so that it still faces its normals' way (here -z stays +z
    // under an x mirror: the normal matrix keeps z, and the turned winding agrees with it).
    checkTriangles(p, {{v(0, 0, 5), v(0, 1, 5), v(-1, 1, 5)},
                       {v(0, 0, 5), v(-1, 1, 5), v(-1, 0, 5)},
                       {v(0, 0, -5), v(1, 0, -5), v(1, 1, -5)},
                       {v(0, 0, -5), v(1, 1, -5), v(0, 1, -5)},
                       {v(0, 0, 0), v(2, 0, 0), v(0, 2, 0)},
                       {v(10, 0, 0), v(11, 0, 0), v(10, 1, 0)}});
    // Every triangle faces the way its vertices' normals do.
    for (const Triangle& t : p.triangles) {
        Vector3d face = (p.positions[t[1]] - p.positions[t[0]]).cross(p.positions[t[2]] - p.positions[t[0]]);
        for (uint32_t i : t) CHECK(face.dot(p.normals[i]) > 0);
    }
}

TEST_CASE("sampling: merging duplicates renumbers the triangles and drops the collapsed ones" *
          doctest::test_suite("unit")) {
    OrientedPoints m;
    for (Vector3d p : {v(0, 0, 0), v(1, 0, 0), v(1, 1, 0), v(1, 0, 0), v(0, 1, 0), v(1e-12, 1, 0)}) {
        m.positions.push_back(p);
        m.normals.push_back(v(0, 0, 1));
    }
    m.triangles = {{0, 1, 2}, {0, 2, 4}, {3, 2, 0}, {4, 5, 0}};
    SUBCASE("exact duplicates") {
        CHECK(ink::mergeDuplicates(m, 0) == 1);
        REQUIRE(m.positions.size() == 5);
        checkTriangles(m, {{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)},
                           {v(0, 0, 0), v(1, 1, 0), v(0, 1, 0)},
                           {v(1, 0, 0), v(1, 1, 0), v(0, 0, 0)},
                           {v(0, 1, 0), v(1e-12, 1, 0), v(0, 0, 0)}});
    }
    SUBCASE("within a tolerance: the sliver loses a corner and goes") {
        CHECK(ink::mergeDuplicates(m, 1e-9) == 2);
        REQUIRE(m.positions.size() == 4);
        checkTriangles(m, {{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)},
                           {v(0, 0, 0), v(1, 1, 0), v(0, 1, 0)},
                           {v(1, 0, 0), v(1, 1, 0), v(0, 0, 0)}});
    }
    SUBCASE("near points: merged clusters renumbered, cancelling ones dropped with their triangles") {
        m.normals[5] = v(0, 0, -1);  // cancels vertex 4's normal
        ink::NearMerge near = ink::mergeNearPoints(m, 1e-6);
        CHECK(near.merged == 1);
        CHECK(near.dropped == 2);
        checkTriangles(m, {{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)}, {v(1, 0, 0), v(1, 1, 0), v(0, 0, 0)}});
    }
}

TEST_CASE("sampling: the count asked for, on the faces, deterministic for a seed" * doctest::test_suite("unit")) {
    OrientedPoints m = octahedron();
    for (size_t count : {size_t(1), size_t(7), size_t(1000), size_t(12345)}) {
        OrientedPoints s = ink::sampleFaces(m, count, 1);
        CHECK(s.positions.size() == count);
        CHECK(s.normals.size() == count);
        CHECK(s.triangles.empty());
    }
    OrientedPoints a = ink::sampleFaces(m, 5000, 7), b = ink::sampleFaces(m, 5000, 7), c = ink::sampleFaces(m, 5000, 8);
    CHECK(a.positions == b.positions);
    CHECK(a.normals == b.normals);
    size_t same = 0;
    for (size_t i = 0; i < a.positions.size(); ++i) same += a.positions[i] == c.positions[i];
    CHECK(same < 50);
    CHECK(ink::sampleFaces(m, 0, 1).positions.empty());

    // The octahedron's corner normals are 54.7° from each face's: creases, so every face stays flat, its samples
    // on it with the face's normal.
    double worstDistance = 0;
    for (size_t i = 0; i < a.positions.size(); ++i) {
        auto [t, distance] = nearestTriangle(m, a.positions[i]);
        worstDistance = std::max(worstDistance, distance);
        CHECK(std::abs(a.normals[i].norm() - 1) < 1e-12);
        const ink::Triangle& tri = m.triangles[t];
        Vector3d face = (m.positions[tri[1]] - m.positions[tri[0]]).cross(m.positions[tri[2]] - m.positions[tri[0]]);
        CHECK(angle(a.normals[i], face) < 1e-9);
    }
    CHECK(worstDistance < 1e-12);
}

TEST_CASE("sampling: on a smooth mesh the samples lie on the curved PN patch, where the corners' normals say" *
          doctest::test_suite("unit")) {
    // The octahedron subdivided three times onto the unit sphere (512 triangles, normals the positions): a
    // sample on the flat triangle is up to the sagitta inside the sphere with a normal that disagrees with its
    // position; on the PN patch it is nearly on the sphere, with nearly the sphere's normal.
    OrientedPoints m = octahedron();
    for (int level = 0; level < 3; ++level) {
        std::vector<ink::Triangle> next;
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mids;
        auto mid = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto [it, added] = mids.try_emplace({key.first, key.second}, uint32_t(m.positions.size()));
            if (added) {
                m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
                m.normals.push_back(m.positions.back());
            }
            return it->second;
        };
        for (const ink::Triangle& t : m.triangles) {
            uint32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({ab, t[1], bc});
            next.push_back({ca, bc, t[2]});
            next.push_back({ab, bc, ca});
        }
        m.triangles = next;
    }
    OrientedPoints s = ink::sampleFaces(m, 20000, 3);
    double worstRadius = 0, worstAngle = 0;
    for (size_t i = 0; i < s.positions.size(); ++i) {
        worstRadius = std::max(worstRadius, std::abs(s.positions[i].norm() - 1));
        worstAngle = std::max(worstAngle, angle(s.normals[i], s.positions[i]));
    }
    // The flat triangles reach 1 − cos(edge/2) ≈ 0.0096 inside the sphere (edges of about 0.39); measured on the
    // patches: 4.4e-4 and 0.43° (with corner normals averaged from the faces instead of the given ones: 3.2e-3, 2.7°).
    INFO("radius " << worstRadius << ", angle " << worstAngle * 180 / M_PI << " deg");
    CHECK(worstRadius < 0.001);
    CHECK(worstAngle * 180 / M_PI < 1.0);
}

TEST_CASE("sampling: a plate's flat faces stay flat beside a crease whose vertex normals lean little" *
          doctest::test_suite("unit")) {
    // A square plate with a round hole through it, read from an OBJ without normals: each top vertex's normal is the
    // area-weighted mean of its faces', and at the hole's rim the long top triangles outweigh the short wall ones,
    // so the rim's normals lean only 19.6° off the top. Taken as the corners' normals (within 20° of the top), they
    // bulged the long top triangles by 5% of their length: a ridge on the fitted top face along each, drawn as
    // contour lenses on a flat face. A corner beside a crease whose lean would bulge the patch by more than 0.5% of
    // the diagonal takes its faces' side's normal.
    // tests/models/plate-with-hole.obj: the square [-1, 1]² × [-h, h], a hole of radius r, 48 segments.
    const double r = 0.4, h = 0.3;
    const OrientedPoints mesh = ink::loadPoints(INKWELL_SOURCE_DIR "/tests/models/plate-with-hole.obj");
    const OrientedPoints s = ink::sampleFaces(mesh, 20000, 1);
    size_t onTop = 0;
    double highest = 0, tilt = 0;
    for (size_t i = 0; i < s.positions.size(); ++i) {
        if (s.normals[i].z() < 0.5 || std::hypot(s.positions[i].x(), s.positions[i].y()) < r + 1e-3) continue;
        ++onTop;  // a top face's sample (the bottom's and the walls' normals point elsewhere)
        highest = std::max(highest, s.positions[i].z() - h);
        tilt = std::max(tilt, std::acos(std::min(1.0, s.normals[i].z())));
    }
    // Before: 0.050 above the top, normals tilted up to 60°.
    INFO("top samples " << onTop << ", highest " << highest << ", tilt " << tilt * 180 / M_PI << " deg");
    CHECK(onTop > 5000);
    CHECK(highest < 1e-6);
    CHECK(tilt * 180 / M_PI < 0.01);
}

TEST_CASE("sampling: a flat face's fan of slivers stays flat beside a chamfer" * doctest::test_suite("unit")) {
    // A CAD face as exporters triangulate it: a fan of 16 long thin triangles from one corner of the unit square
    // (z = 0) to its far edge, where a 45° chamfer (under the 60° crease angle) joins it, read from an OBJ without
    // normals. The far edge's corners lean towards the chamfer (their faces' mean), and each sliver's curved patch
    // bulged along its whole length (CGAL's anchor.off: 2.9% of the diagonal off its flat faces). A sliver with
    // other triangles in its plane around the corner takes their plane's normal there.
    const int n = 16;
    std::string obj = "v 0 0 0\n";
    for (int i = 0; i <= n; ++i) obj += "v " + std::to_string(double(i) / n) + " 1 0\n";
    for (int i = 0; i <= n; ++i) obj += "v " + std::to_string(double(i) / n) + " 1.3 0.3\n";
    auto face = [&](int a, int b, int c) {
        obj += "f " + std::to_string(a + 1) + " " + std::to_string(b + 1) + " " + std::to_string(c + 1) + "\n";
    };
    auto edge = [](int i) { return 1 + i; };
    auto top = [&](int i) { return 2 + n + i; };
    for (int i = 0; i < n; ++i) face(0, edge(i + 1), edge(i));  // the fan, normal +z
    for (int i = 0; i < n; ++i) {                               // the chamfer, normal (0, 1, 1)/√2
        face(edge(i), edge(i + 1), top(i + 1));
        face(edge(i), top(i + 1), top(i));
    }
    const OrientedPoints mesh = parsePoints(obj, "obj", "fan.obj");
    std::vector<uint32_t> triangle;
    const OrientedPoints s = ink::sampleFaces(mesh, 20000, 1, &triangle);
    size_t onFan = 0;
    double highest = 0;
    for (size_t i = 0; i < s.positions.size(); ++i)
        if (triangle[i] < uint32_t(n)) {
            ++onFan;
            highest = std::max(highest, std::abs(s.positions[i].z()));
        }
    INFO("fan samples " << onFan << ", farthest off its plane " << highest);
    CHECK(onFan > 10000);
    CHECK(highest < 1e-9);
    // Well-shaped triangles keep their curved patches, planar quads among them: every triangle of a UV hemisphere
    // leaves its flat facet (by its sagitta). So do slivers whose corners lean across them: a tall octagonal
    // prism's sides (quads 0.77 by 4.6 split in two, 45° apart) stay rounded at the default crease angle.
    const OrientedPoints hemisphere = ink::loadPoints(INKWELL_SOURCE_DIR "/tests/models/hemisphere.obj");
    std::vector<uint32_t> of;
    const std::vector<double> curved = offPlanes(hemisphere, ink::sampleFaces(hemisphere, 5000, 1, &of), of);
    CHECK(std::count_if(curved.begin(), curved.end(), [](double d) { return d > 1e-3; }) == long(curved.size()));
    const OrientedPoints tall = parsePoints(prismObj(2.3), "obj", "tall.obj");
    const std::vector<double> sides = offPlanes(tall, ink::sampleFaces(tall, 20000, 1, &of), of);
    for (int i = 0; i < 8; ++i) {
        INFO("side " << i << ": " << sides[4 * i] << ", " << sides[4 * i + 1]);
        CHECK(sides[4 * i] > 0.01);
        CHECK(sides[4 * i + 1] > 0.01);
    }
}

TEST_CASE("sampling: a mesh's edges past the crease angle stay sharp, the fit's --crease-angle among them" *
          doctest::test_suite("unit")) {
    // An octagonal prism (circumradius 1, z in [-1, 1], capped by fans) from an OBJ without normals: its sides meet
    // at 45°, under the default crease angle (60°), so they are one smoothing group and each side's patches curve
    // towards its neighbours'; with --crease-angle 30 every edge is a crease and every face stays flat (CGAL's
    // tripod.off, whose faces meet at 30-60°: 93.77% of its refined points within 1% of the mesh by default, 100%
    // with 30).
    const OrientedPoints mesh = parsePoints(prismObj(1.0), "obj", "prism.obj");
    std::vector<uint32_t> of;
    std::vector<double> off = offPlanes(mesh, ink::sampleFaces(mesh, 20000, 1, &of), of);
    CHECK(*std::max_element(off.begin(), off.end()) > 0.02);
    off = offPlanes(mesh, ink::sampleFaces(mesh, 20000, 1, &of, 30.0), of);
    CHECK(*std::max_element(off.begin(), off.end()) < 1e-9);
    // The fit takes the angle from its options: its control points (the vertices and these samples) on the prism.
    ink::ModelOptions options;
    options.creaseAngleDeg = 30;
    const ink::Model model = ink::fitModel(mesh, options);
    double farthest = 0;
    for (const Vector3d& c : model.surface.centers) {
        const Vector3d x = model.surface.frame.toInput(c);
        double inside = std::abs(x.z()) - 1;  // the signed distance to the convex prism
        for (int i = 0; i < 8; ++i)
            inside = std::max(inside, x.x() * std::cos(M_PI * (i + 0.5) / 4) + x.y() * std::sin(M_PI * (i + 0.5) / 4) -
                                          std::cos(M_PI / 8));
        farthest = std::max(farthest, std::abs(inside));
    }
    CHECK(model.surface.centers.size() > 1000);
    CHECK(farthest < 1e-6);
}

TEST_CASE("sampling: each triangle gets its share of the area, spread evenly over it" * doctest::test_suite("unit")) {
    std::vector<double> scales = {1, 0.5, 3, 0.1, 2, 1.7, 0.01};
    OrientedPoints m = separateTriangles(scales);
    double total = 0;
    for (double s : scales) total += s * s;
    for (uint32_t seed : {1u, 2u, 99u}) {
        const size_t count = 10007;
        OrientedPoints s = ink::sampleFaces(m, count, seed);
        std::vector<size_t> per(scales.size(), 0);
        for (const Vector3d& p : s.positions) {
            auto [t, distance] = nearestTriangle(m, p);
            CHECK(distance < 1e-12);
            ++per[t];
        }
        for (size_t t = 0; t < scales.size(); ++t) {
            double expected = double(count) * scales[t] * scales[t] / total;
            INFO("triangle " << t << ": " << per[t] << " samples, " << expected << " expected");
            CHECK(double(per[t]) >= std::floor(expected));
            CHECK(double(per[t]) <= std::ceil(expected));
        }
    }
    // Inside one triangle: its four midpoint sub-triangles get a quarter each, and a 1/16 one a sixteenth, to 2%.
    OrientedPoints one = separateTriangles({1});
    OrientedPoints s = ink::sampleFaces(one, 16000, 3);
    const Vector3d a = one.positions[0], b = one.positions[1], c = one.positions[2];
    // Barycentric coordinates in the plane z = 0.
    Eigen::Matrix2d basis;
    basis << (b - a).head<2>(), (c - a).head<2>();
    std::array<size_t, 4> quarter{};
    size_t corner16 = 0;
    for (const Vector3d& p : s.positions) {
        Eigen::Vector2d uv = basis.inverse() * (p - a).head<2>();
        double u = uv.x(), w = uv.y(), z = 1 - u - w;
        ++quarter[u > 0.5 ? 1 : w > 0.5 ? 2 : z > 0.5 ? 0 : 3];
        corner16 += u > 0.75;
    }
    for (size_t q : quarter) CHECK(std::abs(double(q) - 4000) < 80);
    CHECK(std::abs(double(corner16) - 1000) < 20);
}

TEST_CASE("sampling: zero-area triangles get nothing; vertex normals that cancel give the face normal" *
          doctest::test_suite("unit")) {
    OrientedPoints m = separateTriangles({1, 1});
    // Triangle 1 collapsed onto a line, and a third with two corners in one place.
    m.positions[5] = 0.5 * (m.positions[3] + m.positions[4]);
    m.triangles.push_back({0, 0, 1});
    OrientedPoints s = ink::sampleFaces(m, 1000, 5);
    REQUIRE(s.positions.size() == 1000);
    for (const Vector3d& p : s.positions) CHECK(nearestTriangle(separateTriangles({1}), p).second < 1e-12);

    OrientedPoints flat;
    flat.positions = {v(0, 0, 0), v(1, 0, 0), v(2, 0, 0)};
    flat.normals = {v(0, 0, 1), v(0, 0, 1), v(0, 0, 1)};
    flat.triangles = {{0, 1, 2}};
    CHECK(ink::sampleFaces(flat, 100, 1).positions.empty());
    CHECK(ink::faceSampleCount(flat) == 0);
    CHECK(ink::faceSampleCount(OrientedPoints{}) == 0);

    // Corners 0 and 2 face +x, corner 1 -x: normals in the triangle's plane, 90° from its face, say nothing of the
    // smooth surface through it: every corner takes the face's normal, so every sample lies on the flat triangle
    // with it. The face is the z = 0 plane, wound counter-clockwise from +z, and the corners' sum (+x) says
    // nothing about its side: the winding's +z.
    OrientedPoints sheet;
    sheet.positions = {v(0, 0, 0), v(1, 0, 0), v(0, 1, 0)};
    sheet.normals = {v(1, 0, 0), v(-1, 0, 0), v(1, 0, 0)};
    sheet.triangles = {{0, 1, 2}};
    OrientedPoints t = ink::sampleFaces(sheet, 20000, 1);
    REQUIRE(t.positions.size() == 20000);
    for (size_t i = 0; i < t.positions.size(); ++i) {
        CHECK(std::abs(t.positions[i].z()) < 1e-12);
        CHECK((t.normals[i] - v(0, 0, 1)).norm() < 1e-12);
    }
}

TEST_CASE("sampling: the count follows the area and the long thin triangles, within the cap" *
          doctest::test_suite("unit")) {
    // The unit cube (area 6, diagonal √3): a spacing of 1% of the diagonal over the area.
    OrientedPoints cube;
    for (int i = 0; i < 8; ++i) {
        cube.positions.push_back(v(i & 1, (i >> 1) & 1, (i >> 2) & 1));
        cube.normals.push_back((cube.positions.back() - v(0.5, 0.5, 0.5)).normalized());
    }
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        cube.triangles.push_back({f[0], f[1], f[2]});
        cube.triangles.push_back({f[0], f[2], f[3]});
    }
    const double spacing = ink::kFaceSpacing * std::sqrt(3.0);
    CHECK(ink::faceSampleCount(cube) == size_t(std::ceil(6 / (spacing * spacing))));

    // A long thin box (a spider's leg): 1 long, 0.004 wide, far thinner than the spacing. Each long triangle
    // must get about one sample a spacing along it: its share of the count reaches length / spacing.
    OrientedPoints leg = cube;
    for (Vector3d& p : leg.positions) p = p.cwiseProduct(v(1, 0.004, 0.004));
    const size_t count = ink::faceSampleCount(leg);
    const double legSpacing = ink::kFaceSpacing * v(1, 0.004, 0.004).norm();
    double total = 1 * 0.004 * 4 + 0.004 * 0.004 * 2;
    CHECK(double(count) * (0.5 * 0.004) / total >= 1 / legSpacing);
    CHECK(count <= ink::kMaxSampledPoints - 8);
    OrientedPoints s = ink::sampleFaces(leg, count, 1);
    // No gap along the leg longer than 2 spacings.
    std::vector<double> x;
    for (const Vector3d& p : s.positions) x.push_back(p.x());
    std::sort(x.begin(), x.end());
    double gap = x.front();
    for (size_t i = 1; i < x.size(); ++i) gap = std::max(gap, x[i] - x[i - 1]);
    gap = std::max(gap, 1 - x.back());
    CHECK(gap < 2 * legSpacing);

    // A sliver between well-shaped triangles asks for nothing more than the area does; left at the mesh's
    // border, with nothing beside its long edge, it does.
    OrientedPoints sliver;
    for (Vector3d p : {v(0, 0, 0), v(1, 0, 0), v(0.5, 0.001, 0), v(0.5, -1, 0), v(0.5, 1, 0)}) {
        sliver.positions.push_back(p);
        sliver.normals.push_back(v(0, 0, 1));
    }
    sliver.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 4}, {2, 1, 4}};
    auto uniform = [](const OrientedPoints& m) {
        double area = 0, spacing = ink::kFaceSpacing * v(1, 2, 0).norm();
        for (double a : ink::triangleAreas(m)) area += a;
        return size_t(std::ceil(area / (spacing * spacing)));
    };
    CHECK(ink::faceSampleCount(sliver) == uniform(sliver));
    sliver.triangles.erase(sliver.triangles.begin() + 1);
    CHECK(ink::faceSampleCount(sliver) > 10 * uniform(sliver));

    // The cap: vertices and samples together stay within it.
    OrientedPoints many = cube;
    many.positions.resize(ink::kMaxSampledPoints - 10, v(0.5, 0.5, 0.5));
    many.normals.resize(many.positions.size(), v(0, 0, 1));
    CHECK(ink::faceSampleCount(many) == 10);
    many.positions.resize(ink::kMaxSampledPoints + 10, v(0.5, 0.5, 0.5));
    CHECK(ink::faceSampleCount(many) == 0);
}
