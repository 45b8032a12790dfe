// Where the input supports the fitted surface (docs/lines.md, Open surfaces). An implicit fit closes every hole:
// past an open scan's rim or across a mesh's hole it extrapolates a surface no data stands for. As screened
// Poisson reconstruction trims by sample density, a point of a point cloud's drawing is supported when it lies
// within kSupportReach local sample spacings of an input point; a mesh's, when it lies within kMeshSupport of one
// of its triangles. The refined points, the contours and the hatching beyond are dropped. No Vulkan here.
#pragma once

#include "io/oriented_points.h"
#include "lines/lines.h"

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ink {

// A point is supported within this many local spacings of an input point. The local spacing is an input point's
// distance to its kSupportNeighbours-th nearest neighbour: on a closed surface every point of the fit lies within
// about half a spacing of an input point, so the margin is wide (the bunny loses none of its refined points);
// across a hole it ends the surface about this far past the rim.
constexpr double kSupportReach = 2.0;
constexpr int kSupportNeighbours = 4;
// A gap of over this (radians) in a point cloud's point's neighbours, seen in its tangent plane, may be a rim (as
// PCL's boundary estimation): a point on a straight rim has one of 180°.
constexpr double kRimGap = 0.5 * M_PI;
// Neighbours nearer than this many typical spacings are copies of the point, not its neighbours (Support, and the
// fit's merging spacing, model.cpp's typicalSpacing).
constexpr double kNearCopy = 0.05;
// A mesh supports the points within this of a triangle (normalized units): three times the 0.1% of the
// diagonal within which the fit follows every face sample it was given (model.cpp), and less than the inradius of
// a hole of one missing triangle at the face samples' spacing (kFaceSpacing, 1%). A curved triangle reaches
// farther: the fit follows its curved patch (surface_sampling.h), which leaves the flat triangle by up to about
// half its largest corner offset |(p_j − p_i)·n_i| (n_i the vertex normals).
constexpr double kMeshSupport = 0.003;
// The most a mesh's triangle reaches (normalized units). A fit that misses the mesh by more than half this (few
// control points) is not trimmed: its surface lies away from the mesh everywhere, and the grid of reaches would
// grow with the cube of the miss (a 64-point fit of the bunny: 100 million cells, minutes).
constexpr double kMaxMeshSupport = 0.03;
// A mesh's open rim cuts its support: a point whose nearest triangle in reach has a boundary edge, and which lies
// past that edge's line in the triangle's plane by more than this (normalized units), is not supported, though
// within the triangle's reach (the fit carries on past an open rim, and its dots stood beyond the rim's line).
constexpr double kRimSlack = 0.001;

class Support {
public:
    Support() = default;  // supports everything
    // From the input's points (normalized coordinates): a mesh's vertices and face samples, or a point cloud; with
    // a point cloud's normals, the gaps in its points' neighbourhoods too (across).
    explicit Support(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals = {});
    // From a mesh (normalized coordinates); its triangles without area support nothing. `slack` widens every
    // triangle's reach: a fit of fewer control points than the mesh has (--control-points) leaves it by more.
    explicit Support(const OrientedPoints& mesh, double slack = 0);

    bool empty() const { return points_.empty(); }
    bool supports(const Eigen::Vector3d& x) const;
    // A point cloud's open rim, drawn as its boundary lines (rimLines, feature_lines.h): samples along the lines,
    // each with the unit direction out of the surface across it (in its tangent plane) and its rim points' reach.
    // A point whose nearest sample within 1.5 of that reach (an input point inside the rim reaches past it) has it
    // behind, by more than kRimSlack, is not supported: the surface ends at the line drawn for its rim.
    struct RimSample {
        Eigen::Vector3f p, out;
        float reach;
    };
    void setRims(std::vector<RimSample> samples);
    // Whether an input point lies beyond a rim sample: within its reach and past it, the way out, by over half of
    // that (about a spacing: the line runs through the rim's outermost points, smoothed).
    bool inputBeyond(const RimSample& sample) const;
    // The reach of input point i (a point cloud's): the distance within which it supports the surface.
    float reach(size_t i) const { return std::sqrt(reach2_[i]); }
    // The way across a gap of over kRimGap in input point i's neighbours within 1.5 of its reach, unit, in its tangent
    // plane: where it may stand on a rim (cloudRims); zero where its neighbours surround it, or without normals.
    Eigen::Vector3f across(size_t i) const { return i < across_.size() ? across_[i] : Eigen::Vector3f::Zero(); }

private:
    struct Cell {
        int x, y, z;
        bool operator==(const Cell&) const = default;
    };
    struct CellHash {
        size_t operator()(const Cell& c) const {
            return size_t(uint32_t(c.x) * 73856093u ^ uint32_t(c.y) * 19349663u ^ uint32_t(c.z) * 83492791u);
        }
    };
    Cell cellOf(const Eigen::Vector3d& x) const;
    // Calls visit(j) for the entries of `grid`'s 27 cells around c until it returns true; whether one did.
    template <class Grid, class Visit>
    static bool anyAround(const Grid& grid, const Cell& c, Visit&& visit) {
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    auto it = grid.find({c.x + dx, c.y + dy, c.z + dz});
                    if (it == grid.end()) continue;
                    for (uint32_t j : it->second)
                        if (visit(j)) return true;
                }
        return false;
    }

    std::vector<Eigen::Vector3f> points_;
    std::vector<Triangle> triangles_;  // a mesh's: points_ are its vertices, the grid holds triangles
    std::vector<uint8_t> rims_;        // per triangle, its edges (k: t[k] to t[k + 1]) that no other face shares
    std::vector<float> reach2_;        // squared reach of each point, or of each triangle of a mesh
    std::unordered_map<Cell, std::vector<uint32_t>, CellHash> grid_;
    std::unordered_map<Cell, char, CellHash>
        rimCells_;                         // the cells holding a triangle with a rim edge, or near a rim sample
    std::vector<Eigen::Vector3f> across_;  // a point cloud's, per point (across)
    std::vector<RimSample> rimSamples_;    // a point cloud's (setRims), in grid_'s cells:
    std::unordered_map<Cell, std::vector<uint32_t>, CellHash> rimGrid_;
    double cell_ = 1;
};

// Strokes cut where they leave the support: the runs of supported points, each kept when it has two or more.
// `dropped` (when given) counts the points removed.
std::vector<PenStroke> trimStrokes(const std::vector<PenStroke>& strokes, const Support& support,
                                   size_t* dropped = nullptr);

}  // namespace ink
