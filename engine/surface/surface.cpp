#include "surface/surface.h"

#include "surface/clean.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>

namespace ink {

void chooseSeeds(Surface& surface) {
    surface.seeds.clear();
    const bool sided = surface.normals.size() == surface.centers.size();
    for (size_t i : farthestPointSample(surface.centers, std::min(surface.centers.size(), kMaxSeeds),
                                        sided ? &surface.normals : nullptr))
        surface.seeds.push_back(surface.centers[i]);
}

FitStats measureFit(const Surface& surface) {
    if (surface.method == FitMethod::Global) return measureFit(surface.global);
    return measureFit(surface, PuFloat(surface.pu).evalMany(surface.centers));
}

FitStats measureFit(const Surface& surface, const std::vector<Eigen::Vector4f>& values) {
    FitStats stats;
    stats.controlPoints = surface.size();
    for (size_t i = 0; i < surface.size(); ++i) {
        double f = values[i].w();
        Eigen::Vector3d g = values[i].head<3>().cast<double>();
        double gn = g.norm();
        stats.maxDistance = std::max(stats.maxDistance, gn > 0 ? std::abs(f) / gn : INFINITY);
        if (i < surface.normals.size()) {
            const Eigen::Vector3d& n = surface.normals[i];
            double angle = std::atan2(g.cross(n).norm(), g.dot(n));
            stats.maxNormalAngleDeg = std::max(stats.maxNormalAngleDeg, angle * 180.0 / M_PI);
        }
    }
    return stats;
}

}  // namespace ink
