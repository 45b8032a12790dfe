// The refinement's plan and level rules (refine_plan.h).
#include "refine/refine_plan.h"

#include "base/common.h"
#include "base/random.h"
#include "surface/clean.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ink {

const char* dropReasonName(uint32_t reason) {
    static const char* names[] = {"gradient", "armijo", "iterations", "jump"};
    return reason < DropReasonCount ? names[reason] : "?";
}

double nearestSquaredDistance(const std::vector<Eigen::Vector3d>& points, size_t i) {
    double best = INFINITY;
    for (size_t j = 0; j < points.size(); ++j)
        if (j != i) best = std::min(best, (points[i] - points[j]).squaredNorm());
    return best;
}

// The seeds' spacing: the mean distance from a seed to its nearest other seed; at most 2000 seeds are measured,
// against all. Seeds at random (a sparse scan's points, which are the seeds when they are few) stand in pairs and
// clusters: their nearest is about half their spacing, ρ₀ came out half what it is for evenly spread seeds, and the
// children of four levels, reaching about 1.9 ρ₀, left the gaps between them bare (a random sphere of 1,000 points
// drew lace, blotches and holes). Their third nearest is about 0.9 of their spacing and 1.8 times their nearest; a
// mesh's vertices' or farthest-point samples' 1.2 to 1.3 times: where it is over kClustered times the nearest, the
// median third nearest is the spacing. (Taking it for every model moved the bunny's and the torus's page figures
// the wrong way: mean NN 0.760 → 0.750 and 0.759 → 0.742, clumping 0.071 → 0.120 and 0.026 → 0.043.)
constexpr double kClustered = 1.5;

// With normals, only the seeds that face a seed's way are its neighbours (clean.h, facesWay): across a thin wall
// the nearest seed is the other side's, and ρ₀ came out the wall's thickness.
static double meanSpacing(const std::vector<Eigen::Vector3d>& p, const std::vector<Eigen::Vector3d>& normals) {
    if (p.size() < 2) return 0.1;
    size_t stride = std::max<size_t>(1, p.size() / 2000);
    double sum = 0;
    size_t count = 0;
    std::vector<double> third;
    for (size_t i = 0; i < p.size(); i += stride, ++count) {
        std::array<double, 3> nearest;
        nearest.fill(INFINITY);
        for (size_t j = 0; j < p.size(); ++j) {
            const double d2 = (p[i] - p[j]).squaredNorm();
            if (j == i || !(d2 < nearest.back()) || !facesWay(normals[i], normals[j])) continue;
            nearest.back() = d2;
            std::sort(nearest.begin(), nearest.end());
        }
        sum += std::sqrt(nearest[0]);
        if (std::isfinite(nearest[2])) third.push_back(std::sqrt(nearest[2]));
    }
    const double mean = sum / double(count);
    if (third.empty()) return mean;
    std::nth_element(third.begin(), third.begin() + std::ptrdiff_t(third.size() / 2), third.end());
    const double median = third[third.size() / 2];
    return median > kClustered * mean ? median : mean;
}

// The seeds' unit normals, ∇f there (zero where it vanishes: then every seed is a neighbour).
static std::vector<Eigen::Vector3d> seedNormals(const Surface& hrbf, const std::vector<Eigen::Vector3d>& seeds) {
    std::vector<Eigen::Vector3d> normals(seeds.size());
    for (size_t i = 0; i < seeds.size(); ++i) {
        Eigen::Vector3d g;
        hrbf.eval(seeds[i], g);
        normals[i] = g.norm() > 0 && g.allFinite() ? g.normalized() : Eigen::Vector3d::Zero();
    }
    return normals;
}

RefinePlan planRefinement(const Surface& hrbf, const RefineOptions& o, uint64_t maxPoints) {
    if (o.levels >= kMaxLevels)  // written so that a huge --levels cannot overflow
        throw Error("--levels " + std::to_string(o.levels) + " is too many: at most " + std::to_string(kMaxLevels - 1) +
                    " refinement levels");
    if (o.passes > 64) throw Error("--passes must be between 1 and 64");
    if (!validRho(o.rho0)) throw Error("--rho must be in (0, 1]: a fraction of the bounding-box diagonal");
    if (!(o.eps1 > 0) || !(o.delta > 0 && o.delta < 1) || !(o.phi > 0 && o.phi < 0.5))
        throw Error("projection parameters out of range: need ε₁ > 0, δ in (0,1), φ in (0,½)");

    RefinePlan plan;
    plan.levelCount = o.levels + 1;
    plan.passes = o.passes > 0 ? o.passes : (o.selects() ? 1 : 2);
    std::vector<Eigen::Vector3d> base;
    if (o.seeds == SeedMode::ControlPoints) {
        base = hrbf.seeds;
        plan.seedJumpLimit = 1e-3f;  // control points already lie on f = 0
        for (const auto& c : hrbf.seeds) plan.seeds.push_back(c.cast<float>());
    } else {
        if (o.grid < 2 || o.grid > 512) throw Error("--grid must be between 2 and 512 cells");
        Eigen::Vector3d lo = hrbf.centers[0], hi = hrbf.centers[0];
        for (const auto& c : hrbf.centers) {
            lo = lo.cwiseMin(c);
            hi = hi.cwiseMax(c);
        }
        double cell = (hi - lo).maxCoeff() / o.grid;
        // Coincident centres (possible in a hand-made .hrbf file) give a zero cell, and
        // then a NaN cell count cast to an integer.
        if (!(cell > 0) || !std::isfinite(cell) || !std::isfinite(1.0 / cell))
            throw Error(
                "--seeds grid: the model's centres span no volume (their bounding box is degenerate); use "
                "--seeds control-points");
        lo.array() -= cell;
        Eigen::Vector3i n = ((hi - lo).array() / cell).ceil().cast<int>() + 1;
        uint64_t cells = uint64_t(n.x()) * uint64_t(n.y()) * uint64_t(n.z());
        if (cells > (uint64_t(1) << 27))
            throw Error("--grid " + std::to_string(o.grid) + " makes " + std::to_string(cells) +
                        " cells: use a coarser --grid");
        plan.seedJumpLimit = float(std::sqrt(3.0) * cell);  // the cell's neighbourhood
        plan.gridCell = cell;
        // Most cells are far from the surface. Their seeds would be dropped by the projection's jump limit
        // anyway; leaving out those whose first-order distance |f|/‖∇f‖ is over 1.25 times that limit keeps the
        // seeds (and the buffers sized for their children) to the cells near the surface.
        for (int z = 0; z < n.z(); ++z)
            for (int y = 0; y < n.y(); ++y)
                for (int x = 0; x < n.x(); ++x) {
                    uint32_t id = uint32_t((z * n.y() + y) * n.x() + x);
                    auto u = unitFloats(pcg4d({o.seed, 0xFFFF0000u, id, 0u}));
                    Eigen::Vector3d c = lo + cell * Eigen::Vector3d(x + u[0], y + u[1], z + u[2]), g;
                    double f = hrbf.eval(c, g);
                    if (!(std::abs(f) <= 1.25 * double(plan.seedJumpLimit) * g.norm())) continue;
                    plan.seeds.push_back(c.cast<float>());
                }
        if (plan.seeds.size() > maxPoints)
            throw Error("--grid " + std::to_string(o.grid) + " makes " + std::to_string(plan.seeds.size()) +
                        " seeds near the surface, more than fit (" + std::to_string(maxPoints) +
                        "): use a coarser --grid");
        if (plan.seeds.empty()) throw Error("--grid " + std::to_string(o.grid) + " finds no cell near the surface");
        // ρ₀ follows the grid: projected seeds are about one cell apart.
        base.clear();
    }
    double spacing = base.empty() ? (o.seeds == SeedMode::Grid ? double(plan.seedJumpLimit) / std::sqrt(3.0) : 0.1)
                                  : meanSpacing(base, seedNormals(hrbf, base));
    plan.rho0 = o.rho0 > 0 ? o.rho0 : 0.5 * spacing;
    plan.rhoDivisor = o.rhoDivisor > 0 ? o.rhoDivisor : (o.selects() ? 2.0 : 3.0);
    if (!(plan.rhoDivisor >= 1.5 && plan.rhoDivisor <= 4.0)) throw Error("--rho-divisor must be between 1.5 and 4");

    uint32_t children = o.style == SampleStyle::Stipple ? 4 : 2;
    uint64_t candidates = plan.seeds.size();
    // Passes are independent sets of children of the seeds: the seeds themselves are written once.
    for (uint32_t level = 0; level < plan.levelCount; ++level) {
        plan.childCount.push_back(level == 0 ? 1 : level == 1 ? children * plan.passes : children);
        if (level > 0) candidates *= plan.childCount[level];
        plan.maxCandidates.push_back(candidates);
        plan.maxPoints += candidates;
    }
    if (plan.maxPoints > maxPoints) {
        // Advice that helps: the levels that would fit, and what else sets the count (the seeds: control
        // points, or the grid's cells).
        uint32_t fitting = 0;
        for (uint64_t total = 0, n = plan.seeds.size(); fitting + 1 < plan.levelCount; ++fitting) {
            total += n;
            n *= plan.childCount[fitting + 1];
            if (total + n > maxPoints) break;
        }
        std::string advice = fitting > 0 ? "use --levels " + std::to_string(fitting) + " or fewer" : "use fewer levels";
        if (plan.passes > 1) advice += ", fewer passes";
        advice += o.seeds == SeedMode::Grid ? ", or a coarser --grid" : ", or fewer control points";
        throw Error("the refinement asks for up to " + std::to_string(plan.maxPoints) + " points (" +
                    std::to_string(plan.seeds.size()) + " seeds, " + std::to_string(o.levels) + " levels of " +
                    std::to_string(children) + " children, " + std::to_string(plan.passes) +
                    (plan.passes == 1 ? " pass" : " passes") + "), but at most " + std::to_string(maxPoints) +
                    " fit: " + advice);
    }
    return plan;
}

double levelRho(const RefinePlan& plan, uint32_t level) {
    return level == 0 ? 0.0 : plan.rho0 / std::pow(plan.rhoDivisor, double(level) - 1.0);
}

LevelParams levelParams(const RefinePlan& plan, const RefineOptions& o, uint32_t level) {
    LevelParams p{};
    Eigen::Vector3d axis = o.axis.norm() > 0 ? o.axis.normalized() : Eigen::Vector3d::UnitY();
    p.axis = gpu::vec4(float(axis.x()), float(axis.y()), float(axis.z()), 0.0f);
    double rho = levelRho(plan, level);
    p.rho = level == 0 ? 0.0f : float(rho);
    p.jumpLimit = level == 0 ? plan.seedJumpLimit : float(o.jumpFactor * rho);
    p.eps1 = float(o.eps1);
    p.eps2 = float(o.eps2);
    p.delta = float(o.delta);
    p.phi = float(o.phi);
    p.maxIterations = o.maxIterations;
    p.mode = level == 0 ? 0u : (o.style == SampleStyle::Stipple ? 1u : 2u);
    p.direction = uint32_t(o.direction);
    p.level = level;
    p.seed = o.seed;
    p.childCount = plan.childCount[level];
    p.passChildren = level == 0 ? 1u : (o.style == SampleStyle::Stipple ? 4u : 2u);
    p.nextChildCount = level + 1 < plan.levelCount ? plan.childCount[level + 1] : 0u;
    p.keepAll = o.keepAllLevels ? 1u : 0u;
    // Levels share [0,1) in proportion to their (worst-case) point counts, coarse first: tone thresholds then
    // draw whole coarse levels (spread out by construction) before the finer, clumpier ones.
    uint64_t before = 0, total = 0;
    for (uint32_t l = 0; l < plan.levelCount; ++l) {
        if (!o.keepAllLevels && l + 1 < plan.levelCount) continue;
        if (l < level) before += plan.maxCandidates[l];
        total += plan.maxCandidates[l];
    }
    bool drawn = o.keepAllLevels || level + 1 == plan.levelCount;
    p.toneOffset = drawn ? float(double(before) / double(total)) : 0.0f;
    p.toneScale = drawn ? float(double(plan.maxCandidates[level]) / double(total)) : 1.0f;
    return p;
}

}  // namespace ink
