// Points with unit normals: what the loaders produce, the cleaning trims and the fit interpolates. Meshes also
// keep their triangles, so that their faces can be sampled (surface_sampling.h) and measured against
// (fidelity.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace ink {

using Triangle = std::array<uint32_t, 3>;  // indices into OrientedPoints::positions

struct OrientedPoints {
    std::vector<Eigen::Vector3d> positions;
    // One per position: unit length, or zero where a point cloud's file gives none (or 0 0 0): the fit estimates
    // those (estimateNormals, surface/clean.h). A mesh's are all unit length.
    std::vector<Eigen::Vector3d> normals;
    // A mesh's faces, fan-triangulated, in the numbering of `positions` (after a reader's own dropping of
    // unused or degenerate vertices; faces that touched a dropped vertex are dropped). Empty for point formats.
    // Triangles may have zero area; their winding is the file's (or, for glTF, the world's after mirroring).
    std::vector<Triangle> triangles;
};

}  // namespace ink
