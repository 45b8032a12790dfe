// Pen lines on the HRBF surface, traced on the CPU in object space (docs/lines.md): the strokes every kind of line
// is made of, and the occluding contour as polylines (Bremer & Hughes 1998); hatching is in hatching.h. The device
// decides each frame which pieces show (lines.comp). No Vulkan here.
#pragma once

#include "base/point_hash.h"
#include "surface/surface.h"

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

namespace ink {

// A point on f = 0 and its unit normal: what the tracing is seeded from (the refined or selected points).
struct SurfaceSample {
    Eigen::Vector3d position, normal;
};

// A polyline on the surface, in normalized coordinates.
struct PenStroke {
    std::vector<Eigen::Vector3f> points;
    // Unit ∇f at each point; a crease's: the mean of the unit normals of the two faces it divides (its length
    // cos(α/2), α the angle they turn by), so that the device can tell whether either faces the eye.
    std::vector<Eigen::Vector3f> normals;
    bool closed = false;  // the last point joins the first
    uint32_t curve = 0;   // contours: the traced closed curve it is a piece of (pieces end at cusps)
    uint32_t family = 0;  // hatching: 0 along the field, 1 across it (dark tones), 2 diagonal to both (the darkest)
    uint32_t level = 0;   // hatching: 0 traced at twice the spacing, 1 filled in between (darker tones)
    // Contours: a piece its own surface hides, concave along the view (markOccluded): hidden whatever the depth test.
    bool occluded = false;
    // Creases: of a closed part (a point cloud's, or a mesh's without open edges), whose faces hide it where both turn
    // away from the eye; an open part is seen from both sides.
    bool faced = false;
    // Crease and boundary lines, a value a point (else empty): how far it lies behind the surface the eye sees there
    // (normalized units): inside the fit where the fit fills a concave crease, plus how far it was drawn back from the
    // edge towards the fit. The depth test allows for it (lines.comp), so that the fixed allowance stays small.
    std::vector<float> standoff;
    double length() const;
};

// Strokes cut where keep(stroke index, point index) is false: the runs of kept points, each kept when it has two or
// more; a closed stroke cut open starts after its first cut, so that its run across the start stays whole.
// `dropped` (when given) counts the points removed.
std::vector<PenStroke> keepRuns(const std::vector<PenStroke>& strokes, const std::function<bool(size_t, size_t)>& keep,
                                size_t* dropped = nullptr);

// ---- Occluding contour ------------------------------------------------------------------------------------
// The curve where f = 0 and g = ∇f·(p − eye) = 0, traced by predictor–corrector steps: a step of `step` along
// t = ∇f × ∇g (∇g = H (p − eye) + ∇f, H the Hessian of f), then Newton steps onto both equations (the
// minimum-norm correction Δ = −Jᵀ(JJᵀ)⁻¹(f, g), J = [∇f; ∇g]). Each curve is traced until it closes, and split
// at its cusps (where its image reverses: the tangent's component along n × v changes sign).
struct ContourOptions {
    // Predictor step, normalized units (the diagonal is 1): about 2.6 pixels at the default 1024² view; twice this
    // where the curve runs straight, down to a sixteenth where it turns.
    double step = 0.003;
    double seedBand = 0.12;         // samples with |n·v| below this (v the unit view vector) seed curves
    uint32_t maxVertices = 100000;  // per curve
    // All curves together: past this the tracing stops with an ink::Error (a smooth model's contour at 1024² has a
    // few thousand, a detailed CAD assembly a few hundred thousand: assimp's 2CylinderEngine.glb 380,000 in 3.6 s,
    // refused at 300,000 before; millions mean a surface too rough to draw lines on).
    size_t maxTotalVertices = 1000000;
    double maxSeconds = 30;  // likewise past this much tracing time
    // Closed curves shorter than this (normalized units; about 10 pixels at the default view) are dropped: the
    // contour of a bump too small to read, which the pen would draw as a blot.
    double minLoopLength = 0.012;
    // Closed curves whose image is smaller than this, as the view angle along them (radians; about 20 pixels of
    // perimeter at the default 1024² view: a loop under 6 pixels across), are dropped too: a lips loop, long along
    // the view but thin in the image, which the pen draws as a dash or a blot (the bunny beside its front foot).
    double minLoopAngle = 0.015;
    // A pair of cusps whose retrograde piece spans less than this view angle (radians; about 4 pixels, two widths
    // of the default contour pen, at the default 1024² view) is a swallowtail too small to see, made by a ripple
    // of the surface's normals: both go and the pieces either side join.
    double minSwallowtail = 0.003;
};

struct ContourStats {
    size_t seedsTried = 0, curves = 0, closedCurves = 0, pieces = 0, cusps = 0, vertices = 0;
    size_t smallLoops = 0;    // closed curves under minLoopLength or minLoopAngle, dropped
    size_t swallowtails = 0;  // cusp pairs under minSwallowtail, merged away (not in `cusps`)
    size_t occluded = 0;      // pieces their own surface hides (markOccluded)
    double seconds = 0;
    // Traced on the device (contour_device.h): the kernels' time (timestamps; 0 on the CPU), and the marches that
    // ended without meeting the next node (stuck at a singular point, or too long) and so end a curve.
    double deviceMs = 0;
    double devicePassMs[4] = {};  // of it: the seeds, their projection, the first marches, the later rounds
    size_t openMarches = 0;
    size_t lost = 0;         // seeds or nodes whose grid cell found no slot within its probes (0 but on a full table)
    size_t evaluations = 0;  // of the surface with its Hessian, on the device
    size_t extended = 0, extendedVertices = 0;  // open ends traced on on the CPU, and the vertices that added
    bool onDevice = false;
};

// `eye` in normalized coordinates. Pieces come out in tracing order; a closed curve without cusps is one
// closed stroke. Throws ink::Error when the curves pass maxTotalVertices. Reports progress over the seeds.
std::vector<PenStroke> traceContours(const Surface& hrbf, const Eigen::Vector3d& eye,
                                     const std::vector<SurfaceSample>& seeds, const ContourOptions& options = {},
                                     ContourStats* stats = nullptr);

// What both tracers do with a traced curve (its points in order and their unit normals): find its cusps, merge the
// swallowtails too small to see (ContourOptions::minSwallowtail), and append its pieces between cusps to `pieces`
// as curve `curveId`; counts into `stats`.
void splitAtCusps(const std::vector<Eigen::Vector3d>& curve, const std::vector<Eigen::Vector3d>& normals, bool closed,
                  const Eigen::Vector3d& eye, const ContourOptions& options, uint32_t curveId,
                  std::vector<PenStroke>& pieces, ContourStats& stats);

// The view angle a polyline sweeps as seen from `eye` (the length of its image on the unit sphere about the eye),
// with the closing segment when `closed`.
double viewAngle(const std::vector<Eigen::Vector3d>& curve, const Eigen::Vector3d& eye, bool closed);

// Whether both tracers drop a traced curve: under 4 points, or closed and shorter than minLoopLength or than
// minLoopAngle in the image.
bool droppedLoop(const std::vector<Eigen::Vector3d>& curve, bool closed, const Eigen::Vector3d& eye,
                 const ContourOptions& options);

// Marks the pieces their own surface hides, and returns how many. Where the surface is concave along the view (its
// radial curvature κ_r = rᵀHr / |∇f| below zero, r the view ray's direction in the tangent plane), the contour
// lies behind the surface beside it (Koenderink 1984: the contour turns hidden at its cusps, where κ_r changes
// sign). The depth test, which passes what lies within a few splat radii of the surface in front, drew such
// pieces where they leave a visible line: the generator of a drilled hole's wall, a tick below each end of the
// rim. Each piece between cusps is judged by the sign at five points along it, the majority deciding (a ripple
// of the fit may flip one; a point where the surface is nearly flat along the view, |κ_r| under 0.5 a diagonal,
// abstains: the fit's noise would decide there, and a piece without votes is left to the depth test); pieces shorter
// than `minLength` are left to the depth test: where the fit ripples along a rounded crease its contour turns in and
// out in short pieces of both signs, which the depth test keeps as one line.
constexpr double kOccludedSteps = 8;  // the tracers' minLength: eight predictor steps (ContourOptions::step)
size_t markOccluded(const Surface& hrbf, const Eigen::Vector3d& eye, double minLength, std::vector<PenStroke>& pieces);

// Goes on tracing the contour from `start` (on it) in `direction` (double, on the CPU), until it comes within half
// a step of a point of `traced` (normals within ~70°) other than those of `curve` within six steps of where it is
// along it (arcAtStart + arcSign × the arc gone: the stretch it leaves from), or cannot go on, or has made 4,096
// points. Its points join `traced` as it goes (so that it stops where it runs into itself). The new points, in order.
// The device tracer (contour_device.h) closes with it the gaps float left: where ∇g's tangential part nearly vanishes
// its corrector cannot converge in float.
std::vector<Eigen::Vector3d> extendContour(const Surface& hrbf, const Eigen::Vector3d& eye,
                                           const Eigen::Vector3d& start, const Eigen::Vector3d& direction,
                                           PointHash& traced, uint32_t curve, double arcAtStart, double arcSign,
                                           const ContourOptions& options);

// Corrects x onto the contour (f = 0, g = 0) by Newton steps; false when it does not converge.
bool projectToContour(const Surface& hrbf, const Eigen::Vector3d& eye, Eigen::Vector3d& x);

}  // namespace ink
