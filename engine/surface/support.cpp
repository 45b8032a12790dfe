#include "surface/support.h"

#include "base/parallel.h"
#include "base/triangle.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

namespace ink {

Support::Cell Support::cellOf(const Eigen::Vector3d& x) const {
    return {int(std::floor(x.x() / cell_)), int(std::floor(x.y() / cell_)), int(std::floor(x.z() / cell_))};
}

namespace {

// The way across a gap of over kRimGap in point p's neighbours within 1.5 of its reach (cloudRims, feature_lines.h;
// within one, CGAL's hippo1 range scan's rim lines came out 13% shorter, missing stretches), unit and in its tangent
// plane; zero where they surround it, or where an input point lies across the gap from ¾ to 1.6
// reaches away (a closed scan's uneven sampling: the surface goes on there). Copies of the point, and the back of
// a thin part (normals over 120° apart), are not neighbours. A neighbour more across the plane than along it (past
// a crease: the other face) is seen the way the surface turns towards it, its normal's tangential part (ahead past
// a convex edge, behind past a concave one). `points`, `normals`: the positions and unit normals of the points
// around p (p's own among them), gathered once a cell.
Eigen::Vector3f acrossGap(const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                          const std::vector<Eigen::Vector3f>& points, const std::vector<Eigen::Vector3f>& normals,
                          float reach2, float copy2) {
    const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
    std::array<float, 64> angles;
    size_t count = 0;
    for (size_t j = 0; j < points.size(); ++j) {
        const Eigen::Vector3f d = points[j] - p;
        const float d2 = d.squaredNorm();
        if (d2 <= copy2 || d2 > 2.25f * reach2 || normals[j].dot(n) < -0.5f) continue;  // (p itself: d2 = 0)
        const float h = d.dot(n);
        Eigen::Vector3f t = d - h * n;
        if (t.norm() < std::abs(h)) {
            t = (normals[j] - normals[j].dot(n) * n) * (h > 0 ? -1.0f : 1.0f);
            if (t.norm() < 0.3f) continue;
        }
        angles[count++] = std::atan2(t.dot(v), t.dot(u));
        if (count == angles.size()) break;
    }
    if (count < 3) return Eigen::Vector3f::Zero();
    std::sort(angles.begin(), angles.begin() + long(count));
    float gap = angles[0] + float(2 * M_PI) - angles[count - 1], middle = angles[count - 1] + 0.5f * gap;
    for (size_t k = 1; k < count; ++k)
        if (angles[k] - angles[k - 1] > gap) gap = angles[k] - angles[k - 1], middle = angles[k - 1] + 0.5f * gap;
    if (!(gap > float(kRimGap))) return Eigen::Vector3f::Zero();
    const Eigen::Vector3f out = std::cos(middle) * u + std::sin(middle) * v;
    const float cosHalf = std::cos(0.3f * gap), near2 = 0.5625f * reach2, far2 = 2.56f * reach2;
    for (size_t j = 0; j < points.size(); ++j) {
        const Eigen::Vector3f d = points[j] - p;
        const float d2 = d.squaredNorm();
        if (d2 < near2 || d2 > far2 || normals[j].dot(n) < -0.5f) continue;
        const Eigen::Vector3f t = d - d.dot(n) * n;
        if (t.dot(out) > cosHalf * t.norm() && t.norm() > std::abs(d.dot(n))) return Eigen::Vector3f::Zero();
    }
    return out;
}

}  // namespace

Support::Support(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) {
    if (points.size() < 2) return;
    // The typical spacing, as if the points covered about half the faces of their box (model.cpp's estimate);
    // a point's local spacing is capped at twice that (a mesh's dense vertices beside its big faces' sparser
    // samples), and the grid's cells are kSupportReach caps wide, so that a reach stays within a cell's
    // neighbours.
    Eigen::Vector3d lo = points.front(), hi = points.front();
    for (const Eigen::Vector3d& p : points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Eigen::Vector3d d = hi - lo;
    const double typical = std::sqrt((d.x() * d.y() + d.y() * d.z() + d.z() * d.x()) / double(points.size()));
    if (!(typical > 0) || !std::isfinite(typical)) return;
    const double cap = 2 * typical;
    const float nearCopy2 = float(kNearCopy * typical * kNearCopy * typical);
    cell_ = kSupportReach * cap;
    points_.reserve(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) {
        points_.push_back(points[i].cast<float>());
        grid_[cellOf(points[i])].push_back(i);
    }
    reach2_.resize(points.size());
    const bool gaps = normals.size() == points.size();
    std::vector<Eigen::Vector3f> unit;
    if (gaps) {
        across_.assign(points.size(), Eigen::Vector3f::Zero());
        unit.reserve(normals.size());
        for (const Eigen::Vector3d& n : normals) unit.push_back(n.normalized().cast<float>());
    }
    // Cell by cell on all threads (a scan of 10⁶ points took 6 s on one of 16 cores, 27 look-ups a point): the
    // points of the 27 cells around are gathered once for every point of the cell; each point writes its reach.
    std::vector<const std::pair<const Cell, std::vector<uint32_t>>*> cells;
    cells.reserve(grid_.size());
    for (const auto& cell : grid_) cells.push_back(&cell);
    parallelChunks(cells.size(), 256, [&](size_t begin, size_t end, size_t) {
        std::vector<Eigen::Vector3f> around, aroundNormals;  // the positions (and unit normals) of the 27 cells' points
        for (size_t k = begin; k < end; ++k) {
            const Cell c = cells[k]->first;
            around.clear();
            aroundNormals.clear();
            anyAround(grid_, c, [&](uint32_t j) {
                around.push_back(points_[j]);
                if (gaps) aroundNormals.push_back(unit[j]);
                return false;
            });
            for (uint32_t i : cells[k]->second) {
                // The kSupportNeighbours nearest others around (farther ones are past the cap anyway), not counting
                // near copies of the point (within kNearCopy typical spacings: a duplicate, a scan registered over
                // another): seven copies of each point of a sphere left every reach at their jitter, and 100,360
                // of its 100,848 stipple points were trimmed.
                std::array<float, kSupportNeighbours> nearest;
                nearest.fill(float(cap * cap));
                for (const Eigen::Vector3f& q : around) {
                    const float d2 = (q - points_[i]).squaredNorm();
                    if (d2 <= nearCopy2 || d2 >= nearest.back()) continue;
                    nearest.back() = d2;
                    std::sort(nearest.begin(), nearest.end());
                }
                reach2_[i] = float(kSupportReach * kSupportReach) * nearest.back();
                if (gaps && unit[i].allFinite())
                    across_[i] = acrossGap(points_[i], unit[i], around, aroundNormals, reach2_[i], nearCopy2);
            }
        }
    });
}

namespace {

// The squared distance from p to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
float distance2(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                const Eigen::Vector3f& c) {
    const Eigen::Vector3f ab = b - a, ac = c - a, ap = p - a;
    const float d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
    const Eigen::Vector3f bp = p - b;
    const float d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (ap - ab * (d1 / (d1 - d3))).squaredNorm();
    const Eigen::Vector3f cp = p - c;
    const float d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (ap - ac * (d2 / (d2 - d6))).squaredNorm();
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
        return (bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))).squaredNorm();
    const float denom = 1.0f / (va + vb + vc);
    return (ap - ab * (vb * denom) - ac * (vc * denom)).squaredNorm();
}

}  // namespace

Support::Support(const OrientedPoints& mesh, double slack) {
    if (mesh.triangles.empty()) return;
    // Cells of 2% of the diagonal: a triangle goes into every cell its box, grown by the tolerance, touches.
    cell_ = 0.02;
    for (const Eigen::Vector3d& p : mesh.positions) points_.push_back(p.cast<float>());
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        if (!((b - a).cross(c - a).norm() > 0) || !a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
        double offset = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                offset =
                    std::max(offset, std::abs((mesh.positions[t[j]] - mesh.positions[t[i]]).dot(mesh.normals[t[i]])));
        const double reach = std::min(std::max({kMeshSupport, 0.5 * offset, slack}), kMaxMeshSupport);
        if (!std::isfinite(reach)) continue;
        const Eigen::Vector3d grow = Eigen::Vector3d::Constant(reach);
        const Cell lo = cellOf(a.cwiseMin(b).cwiseMin(c) - grow), hi = cellOf(a.cwiseMax(b).cwiseMax(c) + grow);
        const uint32_t index = uint32_t(triangles_.size());
        triangles_.push_back(t);
        reach2_.push_back(float(reach * reach));
        rims_.push_back(0);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) grid_[{x, y, z}].push_back(index);
    }
    if (triangles_.empty()) points_.clear();
    // The open rim: edges of one face among those kept.
    std::unordered_map<uint64_t, uint32_t> uses;
    for (const Triangle& t : triangles_)
        for (int k = 0; k < 3; ++k) ++uses[edgeKey(t[k], t[(k + 1) % 3])];
    for (size_t j = 0; j < triangles_.size(); ++j)
        for (int k = 0; k < 3; ++k)
            if (uses[edgeKey(triangles_[j][k], triangles_[j][(k + 1) % 3])] == 1) rims_[j] |= uint8_t(1u << k);
    for (const auto& [cell, list] : grid_)
        for (uint32_t j : list)
            if (rims_[j]) {
                rimCells_[cell] = 1;
                break;
            }
}

bool Support::supports(const Eigen::Vector3d& x) const {
    if (points_.empty()) return true;
    const Cell c = cellOf(x);
    const Eigen::Vector3f xf = x.cast<float>();
    if (!triangles_.empty()) {
        auto it = grid_.find(c);
        if (it == grid_.end()) return false;
        if (!rimCells_.count(c)) {  // no rim here: any triangle in reach
            for (uint32_t j : it->second) {
                const Triangle& t = triangles_[j];
                if (distance2(xf, points_[t[0]], points_[t[1]], points_[t[2]]) <= reach2_[j]) return true;
            }
            return false;
        }
        // The nearest triangles within reach (ties: past a rim vertex every triangle round it is as near); past the
        // rim edge's line of any of them (in its plane), not supported.
        std::vector<std::pair<float, uint32_t>> near;
        float best = INFINITY;
        for (uint32_t j : it->second) {
            const Triangle& t = triangles_[j];
            const float d2 = distance2(xf, points_[t[0]], points_[t[1]], points_[t[2]]);
            if (d2 <= reach2_[j]) near.push_back({d2, j}), best = std::min(best, d2);
        }
        if (near.empty()) return false;
        for (const auto& [d2, j] : near) {
            if (rims_[j] == 0 || d2 > best * 1.0001f + 1e-12f) continue;
            const Triangle& t = triangles_[j];
            const Eigen::Vector3f normal = (points_[t[1]] - points_[t[0]]).cross(points_[t[2]] - points_[t[0]]);
            for (int k = 0; k < 3; ++k) {
                if (!(rims_[j] >> k & 1)) continue;
                const Eigen::Vector3f &p = points_[t[k]], &q = points_[t[(k + 1) % 3]], &r = points_[t[(k + 2) % 3]];
                Eigen::Vector3f out = (q - p).cross(normal);
                if (out.dot(r - p) > 0) out = -out;
                const float length = out.norm();
                if (length > 0 && (xf - p).dot(out) > float(kRimSlack) * length) return false;
            }
        }
        return true;
    }
    const bool held = anyAround(grid_, c, [&](uint32_t j) { return (points_[j] - xf).squaredNorm() <= reach2_[j]; });
    if (!held || !rimCells_.count(c)) return held;
    // Near a rim line: the nearest of its samples in reach decides.
    float best = INFINITY;
    const RimSample* nearest = nullptr;
    anyAround(rimGrid_, c, [&](uint32_t j) {
        const RimSample& r = rimSamples_[j];
        const float d2 = (r.p - xf).squaredNorm();
        if (d2 <= r.reach * r.reach && d2 < best) best = d2, nearest = &r;
        return false;
    });
    return !nearest || !((xf - nearest->p).dot(nearest->out) > float(kRimSlack));
}

bool Support::inputBeyond(const RimSample& r) const {
    if (!triangles_.empty() || points_.empty()) return false;
    const Cell c = cellOf(r.p.cast<double>());
    const float reach2 = r.reach * r.reach, past = 0.5f * r.reach;
    return anyAround(grid_, c, [&](uint32_t j) {
        const Eigen::Vector3f d = points_[j] - r.p;
        return d.squaredNorm() <= reach2 && d.dot(r.out) > past;
    });
}

void Support::setRims(std::vector<RimSample> samples) {
    if (!triangles_.empty() || points_.empty()) return;
    rimSamples_ = std::move(samples);
    rimGrid_.clear();
    rimCells_.clear();
    for (uint32_t j = 0; j < rimSamples_.size(); ++j) {
        RimSample& r = rimSamples_[j];
        r.reach = std::min(1.5f * r.reach, float(cell_));  // within the 27 cells around
        const Cell c = cellOf(r.p.cast<double>());
        rimGrid_[c].push_back(j);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) rimCells_[{c.x + dx, c.y + dy, c.z + dz}] = 1;
    }
}

std::vector<PenStroke> trimStrokes(const std::vector<PenStroke>& strokes, const Support& support, size_t* dropped) {
    if (support.empty()) return strokes;
    return keepRuns(
        strokes, [&](size_t s, size_t i) { return support.supports(strokes[s].points[i].cast<double>()); }, dropped);
}

}  // namespace ink
