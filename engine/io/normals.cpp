// Area-weighted vertex normals for meshes read without normals.
#include "normals.h"

#include <Eigen/Geometry>
#include <limits>

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

double safeNorm(const Vector3d& v) {
    double big = v.cwiseAbs().maxCoeff();
    return big > 0 && std::isfinite(big) ? big * (v / big).norm() : big;
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

}  // namespace ink::io
