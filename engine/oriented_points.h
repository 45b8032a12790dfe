// Points with unit normals: what the loaders produce, the cleaning trims and the fit interpolates.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ink {

struct OrientedPoints {
    std::vector<Eigen::Vector3d> positions;
    std::vector<Eigen::Vector3d> normals;  // unit length, one per position
};

}  // namespace ink
