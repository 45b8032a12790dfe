// Area-weighted vertex normals for meshes read without normals.
#include "io/normals.h"

#include "base/common.h"

#include <Eigen/Geometry>
#include <bit>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace ink::io {

using Eigen::Vector3d;

void addAreaNormals(const std::vector<Vector3d>& positions, const Polygons& polygons, std::vector<Vector3d>& sums,
                    std::vector<char>& used) {
    size_t offset = 0;
    for (uint32_t size : polygons.sizes) {
        const uint32_t* idx = polygons.indices.data() + offset;
        offset += size;
        const Vector3d& p0 = positions[idx[0]];
        Vector3d area = Vector3d::Zero();
        for (uint32_t k = 1; k + 1 < size; ++k) area += (positions[idx[k]] - p0).cross(positions[idx[k + 1]] - p0);
        for (uint32_t k = 0; k < size; ++k) {
            sums[idx[k]] += area;
            used[idx[k]] = 1;
        }
    }
}

void appendTriangles(const Polygons& polygons, const std::vector<uint32_t>& renumber, uint32_t offset,
                     std::vector<Triangle>& out) {
    size_t at = 0;
    for (uint32_t size : polygons.sizes) {
        const uint32_t* idx = polygons.indices.data() + at;
        at += size;
        auto index = [&](uint32_t k) { return renumber.empty() ? idx[k] : renumber[idx[k]]; };
        for (uint32_t k = 1; k + 1 < size; ++k) {
            Triangle t{index(0), index(k), index(k + 1)};
            if (t[0] == kDropped || t[1] == kDropped || t[2] == kDropped) continue;
            out.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        }
    }
}

double safeNorm(const Vector3d& v) {
    double big = v.cwiseAbs().maxCoeff();
    return big > 0 && std::isfinite(big) ? big * (v / big).norm() : big;
}

Vector3d safeNormalized(const Vector3d& v) {
    const double length = safeNorm(v);
    if (std::isfinite(length)) return length > 0 ? Vector3d(v / length) : v;
    const double big = v.cwiseAbs().maxCoeff();
    if (!std::isfinite(big)) return v;
    const Vector3d scaled = v / big;  // the length overflows, the components do not
    return scaled / scaled.norm();
}

std::string zeroNormalsNote(const std::string& name, size_t count, const char* also, const char* whose) {
    return name + ": " + std::to_string(count) + (count == 1 ? " vertex" : " vertices") +
           " with a zero normal in the file" + also + (count == 1 ? " takes its " : " take their ") + whose + " normal";
}

size_t replaceZeroNormals(OrientedPoints& points, const std::string& name) {
    const size_t n = points.positions.size();
    std::vector<char> zero(n, 0), used(n, 0);
    bool any = false;
    for (size_t i = 0; i < n; ++i)
        if (points.normals[i].allFinite() && !(safeNorm(points.normals[i]) > kZeroNormal)) zero[i] = 1, any = true;
    if (!any) return 0;
    std::vector<Vector3d> sums(n, Vector3d::Zero());
    for (const Triangle& t : points.triangles) {
        const Vector3d& p0 = points.positions[t[0]];
        const Vector3d area = (points.positions[t[1]] - p0).cross(points.positions[t[2]] - p0);
        for (uint32_t v : t) {
            used[v] = 1;
            if (zero[v]) sums[v] += area;
        }
    }
    const double diagonal = usedDiagonal(points.positions, used);
    size_t replaced = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!zero[i] || !used[i]) continue;
        if (!sums[i].allFinite() || zeroArea(sums[i], diagonal)) continue;
        points.normals[i] = safeNormalized(sums[i]);
        ++replaced;
    }
    if (replaced > 0) note(zeroNormalsNote(name, replaced, "", "faces'"));
    return replaced;
}

double usedDiagonal(const std::vector<Vector3d>& positions, const std::vector<char>& used) {
    Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (size_t i = 0; i < positions.size(); ++i) {
        if (!used[i]) continue;
        lo = lo.cwiseMin(positions[i]);
        hi = hi.cwiseMax(positions[i]);
    }
    return safeNorm(hi - lo);
}

namespace {
struct Key {
    uint64_t bits[3];
    bool operator==(const Key& o) const { return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2]; }
};
struct KeyHash {
    size_t operator()(const Key& k) const {
        uint64_t h = 0x9e3779b97f4a7c15ull;
        for (uint64_t b : k.bits) h = (h ^ b) * 0x100000001b3ull + (h >> 29);
        return size_t(h);
    }
};
}  // namespace

std::vector<uint32_t> weld(const std::vector<Vector3d>& positions, std::vector<Vector3d>& unique) {
    std::unordered_map<Key, uint32_t, KeyHash> index;
    index.reserve(positions.size() / 4 + 1);
    std::vector<uint32_t> out(positions.size());
    unique.clear();
    for (size_t i = 0; i < positions.size(); ++i) {
        Key key;
        for (int k = 0; k < 3; ++k) key.bits[k] = std::bit_cast<uint64_t>(positions[i][k] + 0.0);  // -0 -> +0
        auto [it, added] = index.try_emplace(key, uint32_t(unique.size()));
        if (added) unique.push_back(positions[i]);
        out[i] = it->second;
    }
    return out;
}

OrientedPoints areaNormalPoints(const std::vector<Vector3d>& positions, const Polygons& polygons,
                                std::vector<size_t>& kept, size_t& degenerate) {
    std::vector<Vector3d> sums(positions.size(), Vector3d::Zero());
    std::vector<char> used(positions.size(), 0);
    addAreaNormals(positions, polygons, sums, used);
    double diagonal = usedDiagonal(positions, used);
    OrientedPoints out;
    kept.clear();
    degenerate = 0;
    std::vector<uint32_t> renumber(positions.size(), kDropped);
    for (size_t i = 0; i < positions.size(); ++i) {
        if (!used[i]) continue;
        Vector3d n = sums[i];
        double length = safeNorm(n);
        if (std::isfinite(length) &&
            (length == 0 || (std::isfinite(diagonal) && length / diagonal / diagonal <= 1e-12))) {
            ++degenerate;
            continue;
        }
        n = safeNormalized(n);  // a non-finite one finish() reports
        renumber[i] = uint32_t(kept.size());
        kept.push_back(i);
        out.positions.push_back(positions[i]);
        out.normals.push_back(n);
    }
    appendTriangles(polygons, renumber, 0, out.triangles);
    return out;
}

}  // namespace ink::io
