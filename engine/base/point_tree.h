// A k-d tree over points in double precision: Debian's header-only nanoflann (libnanoflann-dev), through the
// adaptor it asks for. Used by the fidelity measure and the cross field's neighbourhoods. No Vulkan here.
#pragma once

#include <Eigen/Core>
#include <nanoflann.hpp>
#include <vector>

namespace ink {

// nanoflann's view of the points (they must outlive the tree).
struct PointCloud {
    const std::vector<Eigen::Vector3d>& points;
    size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(size_t i, size_t k) const { return points[i][Eigen::Index(k)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};

using PointTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>, PointCloud, 3>;

}  // namespace ink
