// The stipple selection's plan (select.h): R₀ from the surface area and the candidate count, then the stages.
#include "select/select_plan.h"
#include "base/random.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace ink {

namespace {

// The surface area, from the HRBF centres: each centre stands for the patch around it, about κ·d² for its
// nearest-neighbour distance d. κ = 1.2 is the area per point of a well-spread set (farthest-point samples,
// a mesh's vertices) whose mean nearest-neighbour distance is 0.85 of the hexagonal spacing.
double estimateArea(const std::vector<Eigen::Vector3d>& centers) {
    if (centers.size() < 2) return 1.0;
    double sum = 0;
    for (size_t i = 0; i < centers.size(); ++i) sum += nearestSquaredDistance(centers, i);
    return 1.2 * sum;
}

uint32_t bucketsPerPhase(double points) {
    // About two pool points a bucket over the 8 phases; at least one.
    double perPhase = std::max(1.0, points / 16.0);
    return std::bit_ceil(uint32_t(std::min(perPhase, double(1u << 24))));
}

}  // namespace

SelectPlan planSelection(const Surface& hrbf, const RefinePlan& refine, const SelectOptions& o) {
    SelectPlan plan;
    plan.areaEstimate = estimateArea(hrbf.seeds);
    // Candidates expected: the worst case, except for grid seeds, where most cells find no surface: about
    // 2A/cell² of them project onto it.
    double candidates = double(refine.maxPoints);
    if (refine.gridCell > 0) {
        double seeds =
            std::min(double(refine.seeds.size()), 2.0 * plan.areaEstimate / (refine.gridCell * refine.gridCell));
        candidates *= seeds / double(std::max<size_t>(1, refine.seeds.size()));
    }
    // A maximal set of radius R on area A holds about 0.7·A/R² points (random sequential adsorption).
    const double kPacking = 0.7;
    double stipples = std::max(1.0, candidates / double(o.candidatesPerStipple));
    plan.radius0 = std::sqrt(kPacking * plan.areaEstimate / stipples);
    plan.poolSeed = pcg4d({o.seed, 0x5E1EC7FFu, 0u, 0u})[0];

    // The coarsest stage holds a handful of points; then each holds about g² times more.
    std::vector<double> radii{plan.radius0};
    while (radii.size() < kMaxSelectStages && kPacking * plan.areaEstimate / (radii.back() * radii.back()) > 16.0)
        radii.push_back(radii.back() * o.growth);
    std::reverse(radii.begin(), radii.end());
    double previous = 0;
    uint32_t previousThreshold = 0;
    for (uint32_t k = 0; k < radii.size(); ++k) {
        double radius = radii[k];
        SelectStage s;
        s.radius2 = float(radius * radius);
        s.previousRadius2 = float(previous);
        s.orderScale = k == 0 ? 0.0f : float(1.0 / (previous - double(s.radius2)));
        auto r = unitFloats(pcg4d({o.seed, 0x5E1EC700u + k, 0u, 0u}));
        for (int i = 0; i < 3; ++i) s.offset[i] = float(r[i] * radius);
        // Cells a little larger than R, beyond float rounding: cells of one phase stay more than R apart.
        s.cellScale = float(1.0 / (radius * (1.0 + 1e-3)));
        double held = kPacking * plan.areaEstimate / (radius * radius);
        double pool = k + 1 == radii.size() ? candidates : std::min(candidates, double(o.poolFactor) * held);
        // Pools only grow (nested), the last one takes every candidate.
        uint32_t threshold = uint32_t(std::min(4294967295.0, pool / candidates * 4294967296.0));
        s.poolThreshold = k + 1 == radii.size() ? UINT32_MAX : std::max(threshold, previousThreshold);
        previousThreshold = s.poolThreshold;
        s.bucketsPerPhase = bucketsPerPhase(pool);
        s.seed = pcg4d({o.seed, 0x5E1EC7FFu, k + 1, 0u})[0];
        plan.stages.push_back(s);
        previous = double(s.radius2);
    }
    return plan;
}

}  // namespace ink
