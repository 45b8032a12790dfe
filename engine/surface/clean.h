// Cleaning oriented points before a fit: merging duplicates and picking well-spread control points.
#pragma once

#include "io/oriented_points.h"

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace ink {

// Merges points closer than `tolerance` (absolute, in the points' units; callers pass ~1e-9 of the
// bounding-box diagonal), keeping the first of each cluster. Returns how many were merged.
// Both merges renumber the triangles; a triangle that loses a corner, or two corners to one point, is dropped.
size_t mergeDuplicates(OrientedPoints& points, double tolerance);

// Points closer than `tolerance` but not equal make the fit ill-conditioned: two nearly equal rows of the
// system with different normal constraints (a mesh's split vertices at a crease, a seam). Each cluster of
// such points becomes its first point with the cluster's mean normal; a cluster whose normals cancel (the
// mean shorter than ½: the two sides of a sheet at one place) is dropped. Grid-based: any number of points.
struct NearMerge {
    size_t merged = 0;   // points folded into another
    size_t dropped = 0;  // points of clusters whose normals cancel
};
// Points whose normals oppose (n·n' < 0) join only within `opposedTolerance`: farther apart they are the two sides of
// a thin part (a plate, a coin a hundredth as thick as it is wide), which merging would drop.
NearMerge mergeNearPoints(OrientedPoints& points, double tolerance, double opposedTolerance);
inline NearMerge mergeNearPoints(OrientedPoints& points, double tolerance) {
    return mergeNearPoints(points, tolerance, tolerance);
}

// Points whose normals are not consistently oriented (a scan's normals estimated without a viewpoint: some point
// in, some out) give a fit that turns inside out in places. Neighbours along the surface are those of each point's
// 8 nearest that lie within 30° of both tangent planes, and not each behind the other's (the two sides of a thin
// part, the walls of a narrow gap: rightly opposed). When more
// than 5% of those pairs have normals opposed (a dot product under −½), the normals are oriented over them as Hoppe
// et al. (1992) do: from the extreme point along x, its normal
// turned outward (+x), along a minimum spanning tree of the neighbour graph weighted 1 − |nᵢ·nⱼ| (Prim's, ties by
// index: deterministic), each point's normal turned to agree with the one it is reached from; each connected
// part starts again from its own extreme point. Returns the normals flipped (0 when consistent already). Over
// 40,000 points, every (m / 20,000)-th point is screened first, and the full pass runs only where over 2.5% of
// its pairs are opposed.
// With `estimated` (a flag a point, from estimateNormals): where they are a tenth of the points or fewer, the given
// normals are oriented among themselves as above (the estimated points left out), and then a second tree grows from
// every given point (held as it is) into the estimated ones, over neighbours within 30° of both tangent planes
// whatever the normals' signs (an estimate has none), each turned to agree with the one it is reached from. Where
// more are estimated, the given ones are too sparse to hold together: that tree grows over every point from each
// part's extreme point along x (facing +x), and the whole is then turned to the side most given normals face. The
// given normals turned are counted; the estimated ones are not.
size_t orientNormals(const std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& normals,
                     const std::vector<char>& estimated = {});

// A point cloud's points without a normal (zero: the file gave none, or 0 0 0) get one estimated from their
// kNormalNeighbours nearest points, as Hoppe et al. (1992) do: the direction of least variance of their covariance
// about their centroid (the fitted tangent plane's normal, PCA). Its sign is arbitrary until orientNormals orients
// it. `estimated` gets a flag a point. Returns how many were estimated; throws ink::Error when some are missing
// and the cloud has fewer than kNormalNeighbours points to estimate them from. Pass normalized positions (the squares
// of a cloud at 1e200 overflow) without duplicates (a point repeated 16 times would be its own neighbourhood).
size_t estimateNormals(const std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& normals,
                       std::vector<char>& estimated);
constexpr size_t kNormalNeighbours = 16;

// A point cloud's outliers: points that stand alone, off the surface their neighbours sample (a scan's stray returns).
// Each point's spacing is its mean distance to its kOutlierNeighbours nearest; a point is an outlier where that is
// over kOutlierLocal times the median of its neighbours' spacings (it lies away from a surface they sample densely)
// or over kOutlierGlobal times the median spacing of the whole cloud (far from everything). Both follow the local
// density, so a sparsely scanned region keeps its points. Then clumps: a part of fewer than kOutlierClump points
// (linked by their nearest neighbours) with no other point within kClumpGap median spacings floats alone (a
// scan's floaters). Removes them (and their normals); returns how many.
// A mesh (points with triangles) is left alone.
size_t removeOutliers(OrientedPoints& points);
constexpr size_t kOutlierNeighbours = 8;
constexpr double kOutlierLocal = 4.0, kOutlierGlobal = 10.0;
// A clump is a part of fewer than kOutlierClump points with nothing within kClumpGap median spacings: at 10, a
// scanned fragment of CGAL's hippo2.ply (56 points across an unscanned gap) went too.
constexpr size_t kOutlierClump = 64;
constexpr double kClumpGap = 40.0;

// A point cloud's noise, as a fraction of its point spacing: over up to kNoiseSamples points spread through it, the
// median distance from a point to the quadric fitted (least squares, in the frame of their tangent plane) to its
// kNoiseNeighbours nearest without it, over its spacing (the mean distance to its 8 nearest). Neighbours whose
// oriented normal turns from the point's by more than 90° are the other side of a thin part, not noise: left out
// (here and in smoothScan). A quadric follows a
// smooth surface's curvature, which a plane's residual mistakes for noise (CGAL's half.xyz, 325 points of a
// hemisphere: 0.17 from a plane, 0.003 from a quadric): a cleanly sampled surface gives a few hundredths (CGAL's
// kitten.xyz 0.009, ball.ply 0.022, hippo1.ply 0.066, the sparse oni.ply 0.072, building.ply 0.084), a noisy scan
// more (a torus of 60,000 points with Gaussian noise of 0.15% of its diagonal 0.175, CGAL's
// fin90_with_PCA_normals.xyz 0.28, sphere_20k.xyz 0.56). Normalized positions.
double scanNoise(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Vector3d>& normals);
constexpr size_t kNoiseSamples = 5000, kNoiseNeighbours = 24;
// A cloud noisier than this is smoothed before it is fitted (ModelOptions::smoothNoise): the fit interpolates every
// point, and the noise became the surface's relief (fin90 drawn as cottage cheese, sphere_20k as a fuzzy blob, the
// noisy torus's contour as 942 cusps of scribble). Smoothed as well, the oni scan lost its horns and its face.
constexpr double kNoisy = 0.15;
// Moving-least-squares smoothing (after Levin 2003 and Alexa et al. 2003): each point moves onto the quadric fitted
// to its `neighbours` nearest, weighted by a Gaussian of their distance (exp(−2 d²/h²), h the farthest one's), in
// the frame of their weighted tangent plane, and takes the quadric's normal there, turned to its own side;
// kSmoothRounds rounds, each from the previous round's points (deterministic, on all threads). Returns the median
// distance a point moved. Normals estimated on the noise should be estimated again on the smoothed points (fitModel
// does): orienting them on the noise left opposed neighbours, which tore holes in CGAL's sphere_20k.xyz.
double smoothScan(std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& normals, size_t neighbours);
constexpr size_t kSmoothRounds = 2;
// The neighbourhood grows with the noise: 64 points up to 0.28 of the spacing (fin90 smooth), in proportion to 128
// at 0.56 (sphere_20k: with 64 its surface kept a grain of specks), at most 128.
size_t smoothNeighbours(double noise);

// Whether consistently oriented normals point into the shape (a mesh wound inside out, a scan's normals estimated
// facing inward): the points farthest along each of ±x, ±y, ±z (a 64th of them, 1 to kOutermost) vote, each by the sign
// of its normal along that direction where it leans along it (|n·d| > 0.3: a rim's or a flat sheet's edge says
// nothing), and inward wins by three to one. A closed shape's outermost points face outward; an open sheet's votes
// split (a terrain's lowest and highest points face the same way) and it stays as it is.
bool normalsPointInward(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Vector3d>& normals);
constexpr size_t kOutermost = 16;

// Deterministic farthest-point sampling: starts at the point with the smallest (x, y, z) in
// lexicographic order, then repeatedly takes the point farthest from those chosen (ties: lowest index).
// Returns indices into `positions`; count >= positions.size() returns all of them in input order.
// With `normals` (one a position), a point's distance counts only the chosen points that face its way (normals not
// turned past kOtherSide from its own): the two sides of a thin wall are each spread over on their own. By 3D distance
// alone a point on one side stood for the other side too, which got none near it: the walls of CGAL's rotor and
// spool, a hundredth of the diagonal thick, drew bare patches a seed spacing wide (refine_plan.cpp).
std::vector<size_t> farthestPointSample(const std::vector<Eigen::Vector3d>& positions, size_t count,
                                        const std::vector<Eigen::Vector3d>* normals = nullptr);
// Normals turned by more than about 143° (cos = −0.8): the other side of a thin wall. At 120° a sharp fold's
// faces counted as two sides too, and the bunny's seeds crowded at its ear tips (its closest same-side pair 0.35 →
// 0.19 in its units, the mean spacing 0.40; the walls' patches closed as much either way).
constexpr double kOtherSide = -0.8;
// Whether two normals face the same way (not turned past kOtherSide), in float as farthestPointSample's tree keeps
// them: the seeds' spacing (refine_plan.cpp) asks as the sampling does.
inline bool facesWay(const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return a.dot(b) >= float(kOtherSide); }
inline bool facesWay(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return facesWay(Eigen::Vector3f(a.cast<float>()), Eigen::Vector3f(b.cast<float>()));
}

}  // namespace ink
