// Inkwell: pen-and-ink drawings (stipples, hatch-like lines of dots) of Hermite RBF implicit surfaces, fitted on
// the CPU to meshes or oriented points and refined, selected and drawn on a Vulkan 1.3 device. This header is
// the public API with error.h, ranges.h (the one table of limits), files.h (the output layer) and diagnostics.h
// (the self-check and benchmarks); the inkwell program and its viewer use nothing else. docs/library.md shows it
// in use, examples/render.cpp renders a model in 40 lines.
//
//   Model     load or fit an HRBF (ψ = r³ plus a linear term) to a mesh or oriented points; save it as .hrbf
//   Device    a Vulkan device: one Inkwell makes, or one the application made and keeps (adopted)
//   Drawing   a model's point sets on a device: stipples selected with blue-noise spacing and ranks, or the
//             report's refined points, or direction sampling; the points can be read back or written as PLY
//   Samples   a model's refined points read back without a Drawing, from a device or the CPU reference
//   Renderer  draws a Drawing into an image of its own and reads it back (headless use)
//   FrameRecorder  records the drawing of a frame into the application's command buffer and colour image
//   Page, Plot  a physical page and pen, and a frame's marks laid out on it: SVG or PDF for pen plotters and print
//
// Objects own their Vulkan resources and free them when destroyed; a Drawing must outlive its renderers and a
// Device its drawings. Errors are thrown as inkwell::Error (error.h) with a one-line message; the library
// prints nothing (notes and progress go to a Reporter). Coordinates are in the input's units unless said;
// the camera orbits the model's bounding-box centre in units of its diagonal.
#pragma once

#include "inkwell/error.h"
#include "inkwell/version.h"

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace inkwell {

using Vec3 = std::array<double, 3>;
using Color = std::array<float, 4>;  // RGBA, 0..1

// ---- Model --------------------------------------------------------------------------------------------

enum class FitMethod {
    PartitionOfUnity,  // local HRBFs blended by a partition of unity: any size, float on the device (default)
    Global,            // the report's single dense HRBF: O(m³), at most 4000 points, double on the device
};

struct ModelOptions {
    // Chosen by farthest-point sampling; 0: every point (PartitionOfUnity) or up to 1000 of them (Global).
    size_t controlPoints = 0;
    FitMethod method = FitMethod::PartitionOfUnity;
    // A mesh's crease lines are the edges whose faces turn by more than this, degrees in (0, 180); the fitted
    // surface stays sharp across them and rounds the others (a low-poly CAD part wants less, docs/fitting.md).
    double creaseAngleDeg = 60;
    // Drops what the input does not support: the fit's caps over an open scan's holes, and its stray sheets away
    // from the data where its far field takes over (docs/lines.md).
    bool trim = true;
    // Leaves out a point cloud's outliers: points that stand alone, off the surface their neighbours sample (a scan's
    // stray returns), each of which the fit would otherwise draw as a floating blob (docs/file-formats.md).
    bool removeOutliers = true;
    // Smooths a noisy point cloud before it is fitted (its noise over 0.15 of its point spacing): each point
    // moved onto the quadric of its 64 nearest, twice (docs/fitting.md). Off: every point fitted as it is.
    bool smoothNoise = true;
    // Looks for a point cloud's crease lines (Drawing::creases; a 10⁶-point scan's take 2 s): off where none will
    // be drawn. A mesh's crease and boundary lines, one pass over its edges, are always found.
    bool features = true;
    // Builds what trims a drawing (with `trim`: the support, a point cloud's rims): off for a model that is only
    // saved, as the .hrbf keeps neither (a 10⁶-point scan's fit 2.9 s faster); the fitted surface is the same.
    bool support = true;
};

struct FitReport {
    size_t inputPoints = 0;       // read from the file (0 for a .hrbf model)
    size_t mergedDuplicates = 0;  // input points dropped as duplicates
    size_t flippedNormals = 0;    // a point cloud's normals turned to agree with their neighbours'
    size_t estimatedNormals =
        0;  // a point cloud's points without a normal in the file, given one from their neighbours
    // Its back is drawn where it shows through an opening: a mesh with an open part (a rim, a hole), and every point
    // cloud and .hrbf model, whose rims are not known (docs/usage.md, Open surfaces).
    bool twoSided = true;
    size_t controlPoints = 0;      // the HRBF's centres
    double seconds = 0;            // fitting time (0 for a .hrbf model)
    double maxDistance = 0;        // max |f|/‖∇f‖ at the centres, in bounding-box diagonals
    double maxNormalAngleDeg = 0;  // max angle between ∇f and the given normal at the centres
    // The error at every input point (not only the control points), evaluated as the device evaluates.
    double inputMaxDistance = 0, inputMaxAngleDeg = 0;
    size_t patches = 0;      // PartitionOfUnity: the local HRBFs
    size_t faceSamples = 0;  // a mesh's: points sampled on its faces besides its vertices
    double loadSeconds = 0;  // reading the file
};

// A .hrbf file: the binary version 3 (float patches, compact, fast to load) or text (versions 1 and 2, for
// interchange; 17 digits, exact). docs/hrbf-format.md.
enum class HrbfFormat { Binary, Text };

// Throws the Error Model::load and Model::fit would for these options (a crease angle outside (0, 180), more
// control points than the fit takes), before any work.
void checkModelOptions(const ModelOptions& options);

// An HRBF implicit surface f = 0, fitted so that f(p_i) = 0 and ∇f(p_i) = n_i at the control points. Cheap to
// copy (shared, immutable).
class Model {
public:
    // Reads a mesh (.obj, .ply) or oriented points (.pts/.xyzn/.txt: x y z nx ny nz a line) and fits it, or
    // reads a fitted .hrbf file. Cost: the partition of unity fits 10⁵ points in a few seconds on 2 cores; the
    // global fit is O(m³) in the control points (0.2 s at 684).
    static Model load(const std::string& path, const ModelOptions& options = {}, const Reporter& reporter = {});
    // Fits oriented points (normals need not be unit; they must not be zero).
    static Model fit(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                     const ModelOptions& options = {}, const Reporter& reporter = {});
    // Writes the fitted model as .hrbf (docs/hrbf-format.md), atomically.
    void save(const std::string& path, HrbfFormat format = HrbfFormat::Binary) const;

    FitReport report() const;
    // The fit's figures as one JSON object: method, seconds, residual and errors, the time of each phase, the
    // patches and their seams (docs/usage.md, "Stats JSON": `fit`).
    std::string statsJson() const;
    // f and ∇f at x, in the input's units (f is negative inside, for closed surfaces with outward normals).
    double value(const Vec3& x) const;
    Vec3 gradient(const Vec3& x) const;

private:
    struct Impl;
    friend class Drawing;
    friend struct Access;  // the library's own code beside this API (diagnostics.h)
    explicit Model(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
};

// How closely points follow a mesh: coverage, the share of a dense, even sampling of the mesh's surface with a
// point within the tolerance (holes, lost parts), and accuracy, the share of the points within the tolerance of
// the surface (stray sheets, blobs). Distances in bounding-box diagonals of the mesh.
struct Fidelity {
    double tolerance = 0;  // in diagonals
    size_t surfaceSamples = 0, points = 0;
    double coverage = 0, coverageP99 = 0, coverageMax = 0;  // surface sample → nearest point
    double accuracy = 0, accuracyP99 = 0, accuracyMax = 0;  // point → nearest triangle
};

// Measures `points` (in the mesh's units: a Drawing's with Distribution::Refinement, say) against the faces of the
// mesh in `meshPath` (.obj .ply .off .stl .gltf .glb). A file without faces is refused. The coverage's reference
// samples lie on the triangles' curved patches as a fit with `creaseAngleDeg` (ModelOptions::creaseAngleDeg)
// samples them. Cost: about a second for 10⁵ points against 10⁵ triangles (a k-d tree of the points, a grid of the
// triangles).
Fidelity measureFidelity(const std::string& meshPath, const std::vector<Vec3>& points, double tolerance = 0.01,
                         const Reporter& reporter = {}, double creaseAngleDeg = 60);

// The same in two steps: the mesh read (and a file without faces refused) before any other work, the points
// measured against it later, as often as wanted.
class FidelityMesh {
public:
    explicit FidelityMesh(const std::string& meshPath, const Reporter& reporter = {});
    Fidelity measure(const std::vector<Vec3>& points, double tolerance = 0.01, const Reporter& reporter = {},
                     double creaseAngleDeg = 60) const;

private:
    struct Impl;
    std::shared_ptr<const Impl> impl_;
};

// ---- Device -------------------------------------------------------------------------------------------

struct DeviceOptions {
    bool validation = false;    // Vulkan validation with synchronization validation (vulkan-validationlayers)
    std::string device;         // "": a GPU if there is one, else lavapipe; or an index, or part of a name
    bool presentation = false;  // enable VK_KHR_swapchain
    std::vector<const char*> instanceExtensions;  // extra instance extensions (a window system's)
    // Called with each validation error (true) or warning (false).
    std::function<void(bool error, const std::string& message)> validationMessage;
};

// A device the application made and keeps. It must be Vulkan 1.3 with synchronization2, dynamicRendering and
// maintenance4 enabled (and shaderFloat64 for FitMethod::Global models, bufferDeviceAddress for models whose patch
// nodes outgrow a storage buffer), and subgroup
// basic/vote/ballot/arithmetic/shuffle operations in compute; the queue's family must do graphics and compute. Inkwell
// makes only its own command pool, buffers and pipelines on it, and waits for the queue when the Device goes.
struct AdoptedDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    // Whether the device was created with shaderFloat64 and shaderUniformBufferArrayDynamicIndexing: only
    // models fitted with FitMethod::Global need them.
    bool shaderFloat64 = false;
    // Whether it was created with bufferDeviceAddress (Vulkan 1.2's feature, which every 1.3 device has): only
    // models whose patch nodes outgrow one storage buffer's range (maxStorageBufferRange) need it.
    bool bufferDeviceAddress = false;
};

class Device {
public:
    // The Vulkan devices there are, in the order DeviceOptions::device's index counts them.
    static std::vector<std::string> list();

    explicit Device(const DeviceOptions& options = {});
    explicit Device(const AdoptedDevice& device);
    ~Device();
    Device(Device&&) noexcept;
    Device& operator=(Device&&) noexcept;

    std::string name() const;    // "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string driver() const;  // the driver's version: "Mesa 22.3.6 (LLVM 15.0.6)"
    // With DeviceOptions::validation: the messages counted since creation, and the first error's text.
    uint32_t validationErrors() const;
    uint32_t validationWarnings() const;
    std::string firstValidationError() const;
    // The Vulkan objects it made or adopted, for an application that draws beside it (its swapchain, its UI).
    // Inkwell submits to the queue from its own calls: the application keeps its submissions out of them (Vulkan
    // wants a queue externally synchronized).
    AdoptedDevice handles() const;
    // Throws the Error a Renderer of this size would, before any work: an image (supersample times larger)
    // beyond the device's limits.
    void checkImageSize(uint32_t width, uint32_t height, uint32_t supersample = 1) const;

private:
    struct Impl;
    friend class Drawing;
    friend struct Access;
    std::unique_ptr<Impl> impl_;
};

// ---- Drawing ------------------------------------------------------------------------------------------

enum class Style {
    Stipple,    // dots
    Direction,  // hatch-like lines of dots along a direction field
    Both,       // both sets, drawn together
};
const char* styleName(Style style);  // "stipple", "direction", "both"

enum class Distribution {
    BlueNoise,   // stipples selected from the refined points, evenly spaced, with progressive ranks (default)
    Refinement,  // every refined point, with a random tone value (the report's look)
};

// The field Style::Direction's lines of dots follow.
enum class DirectionField {
    Axis,          // across DrawingOptions::axis
    CurvatureMin,  // the principal directions
    CurvatureMax,
};

// Where a piece of work runs: Auto picks the device where it is a GPU, else the CPU (docs/lines.md).
enum class Where { Auto, Cpu, Device };

struct DrawingOptions {
    Style style = Style::Stipple;  // the dots (Look::dots turns them off, e.g. for pen lines alone)
    // Pen lines (docs/lines.md): the occluding contour for each view a renderer draws (re-traced when the eye moves;
    // on the device where it is a GPU, else on the CPU: about 20–60 ms for the 684-point bunny on 2 cores), and
    // hatching strokes once, along the surface (their cross field solved on the device where it is a GPU).
    bool contours = false;
    bool hatching = false;
    // A model's crease lines (sharp edges: a mesh's, or a point cloud's where its normals turn sharply) and boundary
    // lines (a mesh's open edges and holes' rims, a point cloud's open rims), on pens of their own; a .hrbf model has
    // none. The command line draws boundaries and a mesh's creases in every style, a point cloud's creases with
    // contours or hatching.
    bool creases = false;
    bool boundaries = false;
    double hatchSpacing = 0.007;  // of the bounding-box diagonal, the finest level (the coarse one is twice this)
    uint32_t hatchFamilies = 3;   // 1; 2 to cross the first in dark tones; 3 with a diagonal one in the darkest
    Distribution distribution = Distribution::BlueNoise;
    uint32_t levels = 4;                // refinement levels after the seeds (each about 4× the points)
    float candidatesPerStipple = 4.0f;  // blue noise: keep about one refined point in this many (2..16)
    uint32_t seed = 1;
    // The refinement (docs/algorithm.md): independent sets of children of the seeds (0: 1 for blue-noise
    // stipples, else the report's 2); ρ₀, a fraction of the diagonal in (0, 1] (0: half the seed spacing); ρ of
    // a level over the next's in [1.5, 4] (0: 2 for blue-noise stipples, else the report's 3); the seeds, the
    // control points or a jittered grid of `grid` cells along the longest side (2..512) projected onto the
    // surface; every level kept, or only the last.
    uint32_t passes = 0;
    double rho = 0;
    double rhoDivisor = 0;
    bool gridSeeds = false;
    uint32_t grid = 32;
    bool keepAllLevels = true;
    DirectionField direction = DirectionField::Axis;
    Vec3 axis{0, 1, 0};  // DirectionField::Axis: in the input's coordinates, not zero
    // Where each view's contour is traced and the hatching's cross field solved (the device only for a
    // partition-of-unity fit).
    Where contourTracer = Where::Auto;
    Where hatchField = Where::Auto;

    bool operator==(const DrawingOptions&) const = default;
};

// A point as drawn: on the surface, in the input's units.
struct Point {
    Vec3 position;
    Vec3 normal;     // unit
    float rank;      // a stipple's rank: the points with rank < t are an evenly spaced subset, for any t
    uint32_t level;  // the refinement level that made it
};

struct Camera;     // below
struct FirstView;  // below

// A stroke of the pen: a polyline on the surface, in the input's units.
struct Polyline {
    std::vector<Vec3> points;
    bool closed = false;    // the last point joins the first
    uint32_t family = 0;    // hatching: 0 along the field, 1 across it (dark tones), 2 diagonal (the darkest)
    uint32_t level = 0;     // hatching: 0 the coarse spacing, 1 filled in between (darker tones)
    bool occluded = false;  // contours: a piece its own surface hides (concave along the view), drawn as hidden
};

// A model's point sets on a device: one for Stipple or Direction, two for Both. Made on the device in one
// submission a set, waited for (0.9 s for the 684-point bunny on lavapipe), then the hatching traced.
enum class Up;  // below

class Drawing {
public:
    Drawing(Device& device, const Model& model, const DrawingOptions& options = {}, const Reporter& reporter = {});
    ~Drawing();
    Drawing(Drawing&&) noexcept;
    Drawing& operator=(Drawing&&) noexcept;

    // Replaces the sets (another style, more levels); waits for the device to be idle. Renderers and frame
    // recorders of this drawing stay valid: each draws the new sets from its next render() or record() (a
    // FrameRecorder's command buffers recorded before refine() must be recorded again, not resubmitted).
    void refine(const DrawingOptions& options, const Reporter& reporter = {});
    // refine() in two halves, for an application that keeps its window responsive meanwhile: prepare() makes the
    // new sets and traces their pen lines without touching the current ones (only the pen lines, where the
    // options change nothing else; nothing at all, where they change only which lines are drawn). It may run on
    // another thread than the frames if the application records and submits nothing on the device's queue until
    // it returns. apply() waits for the device to be idle and puts the result in place; a prepare() that threw
    // left the drawing as it was.
    class Pending {
    public:
        Pending();
        ~Pending();
        Pending(Pending&&) noexcept;
        Pending& operator=(Pending&&) noexcept;
        bool refined() const;         // new point sets (else new or the same pen lines over the current ones)
        double seconds() const;       // making the sets
        bool traced() const;          // the pen lines traced again (their seeds, and the hatching where it is drawn)
        double traceSeconds() const;  // tracing the pen lines
        size_t hatchStrokes() const;

    private:
        friend class Drawing;
        struct Impl;
        std::unique_ptr<Impl> impl_;
    };
    // What prepare(options) has to do, decided without doing it (an application shows "refining" or "tracing",
    // or applies at once what costs nothing).
    enum class Work {
        None,   // only which lines are drawn changes (or nothing)
        Lines,  // the pen lines traced again over the current sets
        Sets,   // new point sets, and their pen lines
    };
    Work work(const DrawingOptions& options) const;
    // A Pending holds device buffers: apply it, or let it go, before the Device goes. apply() refuses one
    // prepared for another drawing or before this one changed.
    Pending prepare(const DrawingOptions& options, const Reporter& reporter = {}) const;
    void apply(Pending&& pending);
    // The options of the sets and lines in place (the constructor's, or the last refine() or apply()).
    DrawingOptions options() const;
    // How long the last trace of the contour took (for a view a renderer or recorder drew), wall clock, seconds:
    // 0 before any. The CPU's tracer takes 35–45 ms for the 684-point bunny on lavapipe, the device's a few ms
    // on a GPU.
    double contourSeconds() const;
    size_t sets() const;
    // The points set `set` draws (reads them back), and the same written as binary PLY with rank and level.
    std::vector<Point> points(size_t set = 0) const;
    void writePly(const std::string& path, size_t set = 0) const;
    // The hatching strokes (empty without DrawingOptions::hatching), and the occluding contour seen from `camera`
    // (traced for it; empty without DrawingOptions::contours), in pieces that end at its cusps.
    std::vector<Polyline> hatching() const;
    std::vector<Polyline> contours(const Camera& camera) const;
    // The first picture (docs/library.md), what `inkwell render` shows without --camera and --up: the up axis
    // (a glTF file's +y, else from the shape of the first set's points), and about it the view with the largest
    // viewpoint entropy at 15° or 30° above the horizon, framed so the model fills 85% of an image `aspect`
    // (width / height, 1/16384 to 16384) wide. A few milliseconds on the CPU besides reading the points back.
    Up firstUp(std::string* reason = nullptr) const;  // `reason`: why ("the glTF convention", "flat: ...")
    Camera firstView(float aspect = 1.0f) const;
    Camera firstView(Up up, float aspect = 1.0f) const;
    // The same with the reasons: why this up axis, and the view's viewpoint entropy.
    FirstView firstViewReport(float aspect = 1.0f) const;
    FirstView firstViewReport(Up up, float aspect = 1.0f) const;
    // The model's crease and boundary lines, along its edges beside the fitted surface (all of them, whatever
    // DrawingOptions asks drawn).
    std::vector<Polyline> creases() const;
    std::vector<Polyline> boundaries() const;
    // The points of all sets, and the refinement's and the pen lines' figures as one JSON object: `refine`
    // (seconds, points, each set's levels: candidates, kept, dropped by reason, device ms; the host's ms) and
    // `lines` (hatching, creases, boundaries, the last contour traced) (docs/usage.md, "Stats JSON").
    uint64_t pointCount() const;
    std::string statsJson() const;

private:
    struct Impl;
    friend class Renderer;
    friend class FrameRecorder;
    friend struct Access;
    std::unique_ptr<Impl> impl_;
};

// A model's refined points read back without drawing them (`inkwell sample`): made on `device`, or with none on
// the CPU (the multi-threaded reference, no Vulkan), as a Drawing of DrawingOptions::style Stipple or Direction
// makes its one set (no pen lines, no trimming).
class Samples {
public:
    // `keepRefined`: keep every refined point too, for refined() (a copy of them all).
    Samples(Device* device, const Model& model, const DrawingOptions& options, bool keepRefined = false,
            const Reporter& reporter = {});
    ~Samples();
    Samples(Samples&&) noexcept;
    Samples& operator=(Samples&&) noexcept;

    // The points as drawn: the stipples selected, or every refined point where nothing is selected.
    size_t size() const;
    std::vector<Point> points() const;
    // Every refined point before the selection, in the input's units (what a fidelity measure wants); only
    // when made with keepRefined.
    std::vector<Vec3> refined() const;
    // The points as drawn, binary PLY with rank and level (Drawing::writePly's format), atomically.
    void writePly(const std::string& path) const;
    // `refine` (seconds, points, levels), `select` (candidates, radius, area, each stage's stipples, seconds or
    // device ms), `device` and `driver` (or "cpu"), and with `spacing` the nearest-neighbour spacing of the points
    // and their rank prefixes (docs/usage.md, "Stats JSON").
    std::string statsJson(bool spacing = false) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// ---- Drawing it ---------------------------------------------------------------------------------------

// The model's up axis (scans and CAD models are often Z).
enum class Up { X, NegX, Y, NegY, Z, NegZ };
// "x", "-x", "y", "-y", "z", "-z" (and "+x", ...); throws naming the text.
Up parseUp(const std::string& name);
const char* upName(Up up);

// An orbit camera around the model's centre. Its defaults are a fixed three-quarter view; Drawing::firstView
// chooses one for the model (what `inkwell render` shows by default).
struct Camera {
    Up up = Up::Y;               // the axis it orbits; a light fixed to the model is given about it too
    float azimuthDeg = 30.0f;    // around the up axis
    float elevationDeg = 15.0f;  // above the horizon, within ±89 (any, with freeOrbit)
    float distance = 1.6f;       // from the centre, in bounding-box diagonals
    float fovyDeg = 40.0f;
    // The point it orbits and looks at, in bounding-box diagonals from the centre (firstView centres the
    // model's projection with it).
    std::array<float, 3> target{0.0f, 0.0f, 0.0f};
    // false: a turntable, the up axis stays up. true: a free orbit that tumbles over the poles, the view's up
    // following the orbit (the viewer's "free" camera).
    bool freeOrbit = false;

    // Where the eye is, in bounding-box diagonals from the centre (two cameras with the same eye see the same
    // contour).
    std::array<float, 3> eye() const;
    // Moves the target in the view plane by a mouse movement of (dx, dy) pixels in a view `height` pixels
    // high: the point under the cursor follows it at the target's depth.
    void pan(double dx, double dy, uint32_t height);
};

// Drawing::firstViewReport: the first picture's camera and why.
struct FirstView {
    Camera camera;
    std::string upReason;  // "the glTF convention", "flat: its thinnest axis", ... ("given" for a given axis)
    double entropyBits = 0;
    float frontDeg = -1;  // the azimuth the model faces, where its shape says (else -1)
};

// How the points become ink. Renderer, FrameRecorder and setLook check every value against the range given
// here (the command line's) and throw an inkwell::Error naming the field and its range.
struct Look {
    Color ink{0, 0, 0, 1};  // components in [0, 1]
    Color paper{1, 1, 1, 1};
    float dotSize = 2.0f;         // diameter in output pixels, (0, 64]
    float silhouetteSize = 2.4f;  // silhouette dots (|n·v| < tau), (0, 64]
    float tau = 0.1f;          // [0, 1); none with the contour drawn (DrawingOptions::contours: the pen is the outline)
    float toneGamma = 1.5f;    // tone curve exponent, [0, 16]; 0 draws every front dot
    float inkDensity = 1.0f;   // scales how many dots the tone draws, [0, 100]
    bool hiddenLines = false;  // occluded silhouettes and contours drawn faint
    bool dots = true;          // off: only pen lines are drawn (the dots still hide what is behind the surface)
    // The tone's stipples spaced evenly on the page, larger where the points cannot supply the tone's count (docs/
    // algorithm.md §4); off: the surface's ranked prefix, which crowds where the surface turns away.
    bool screenSpacing = true;
    float penWidth = 2.0f;       // contour pen width in output pixels, (0, 32]
    float hatchWidth = 1.0f;     // hatching pen width, tapering at the strokes' ends, (0, 32]
    float creaseWidth = 1.5f;    // crease lines' pen width, (0, 32]
    float boundaryWidth = 2.0f;  // boundary lines' pen width, (0, 32]
    float halo = 4.0f;           // paper kept clear each side of an interior contour (Brazil et al. 2011), [0, 32]
    // With hiddenLines: the hidden silhouette dots' diameter (0, 64] and the hidden contours' pen width (0, 32] in
    // output pixels, and how much of the ink they take over the paper, [0, 1] (0.45: a grey; --hidden-dot-size,
    // --hidden-contour-width, --hidden-opacity).
    float hiddenDotSize = 1.4f;
    float hiddenPenWidth = 1.2f;
    float hiddenOpacity = 0.45f;
    // Towards the key light, x right, y up, z to the viewer: the upper left. It follows the camera (the lit side
    // stays towards the eye as it orbits); with lightFollowsCamera false it is fixed to the model, given as seen
    // from the default Camera (azimuth 30°, elevation 15°). Finite and not zero.
    std::array<float, 3> light{-0.5f, 0.6f, 0.65f};
    bool lightFollowsCamera = true;
    uint32_t supersample = 2;  // Renderer only: draw this many times larger and filter down, 1 to 4
    bool occlusion = true;     // off: no depth pre-pass, the dots behind the surface show
};

struct Image {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;                      // rows top to bottom
    void writePng(const std::string& path) const;   // atomically
    static Image readPng(const std::string& path);  // any PNG, as RGBA; throws naming the file
};

// Two images compared pixel by pixel (regression checks: `inkwell compare`): a pixel differs when a channel
// differs by more than `threshold`.
struct ImageDifference {
    uint32_t maxAbsDiff = 0;  // the largest channel difference (255 for images of different sizes)
    size_t differingPixels = 0, pixels = 0;
    double differingFraction = 0;
    bool sameSize = true;
    std::string text;  // "max abs diff 40, 0.018% pixels differ (12 of 65536)"
};
constexpr uint32_t kCompareThreshold = 8;
constexpr double kCompareMaxFraction = 0.0025;  // the share of pixels that may differ in a match
// `threshold` in [0, 255]; each image's rgba must hold width × height × 4 bytes.
ImageDifference compareImages(const Image& a, const Image& b, uint32_t threshold = kCompareThreshold);
// The differing pixels marked (red over a faded `a`).
Image differenceImage(const Image& a, const Image& b, uint32_t threshold = kCompareThreshold);

// ---- Vector output (pen plotters, print) ----------------------------------------------------------------

enum class DotStyle {
    Circle,  // a small closed circle whose stroke covers the dot
    Tick,    // a short 45° stroke
};
enum class Orientation { Auto, Portrait, Landscape };  // Auto: landscape when the image is wider than tall

// The page a frame's marks are laid out on: the image scaled to fit within the margins and centred.
struct Page {
    double widthMm = 210, heightMm = 297;  // A4 (portrait; Orientation turns it)
    Orientation orientation = Orientation::Auto;
    double marginMm = 15;
    double penWidthMm = 0.3;  // every path's stroke width
    DotStyle dotStyle = DotStyle::Circle;
    bool orderPaths = true;  // order each pen's paths for short pen-up travel (else the points' order)
    // Pen lines before they are written, as fractions of the pen width: simplified to `simplify`, stretches
    // within `retrace` of one already drawn dropped, ends within `merge` joined (with orderPaths only).
    double simplify = 0.05, retrace = 0.25, merge = 0.5;
    // The plot-time estimate: pen-down and pen-up speeds, mm/s, and the time of one lift.
    double drawSpeed = 25, travelSpeed = 75, liftSeconds = 0.15;
    // "A3", "A4", "A5", "letter" or "WxHmm"; throws naming the text.
    static Page named(const std::string& size);
};

// One pen's layer as written: its paths and their pen-up travel (from the page's top-left corner) in the
// points' order and as written, and the pen-down length, in mm.
struct PenLayer {
    uint32_t pen = 0;  // 1, 2, ... bottom layer first
    std::string name;  // "hidden", "stipple", "direction"
    size_t paths = 0;
    double travelBeforeMm = 0, travelAfterMm = 0, penDownMm = 0;
    size_t lifts = 0;        // pen lifts, one a path
    double plotSeconds = 0;  // estimated by the page's time model (25 mm/s pen down, 75 up, 0.15 s a lift)
    size_t pathsGiven = 0;   // the paths as the frame gave them, before merging and clipping
};

// A frame's marks laid out on a page (Renderer::plot): written as often as wanted, to SVG or PDF.
class Plot {
public:
    // The same bytes for the same frame and page; SVG or PDF by the extension (.svg, .pdf), atomically.
    void write(const std::string& path) const;
    std::vector<PenLayer> layers() const;
    // The layers' figures (paths and vertices before and after simplifying and merging, travel, lifts, time)
    // and the page's as one JSON object (docs/usage.md, "Stats JSON": `vector`).
    std::string statsJson() const;
    // A path ending in .svg or .pdf (any case).
    static bool isVectorPath(const std::string& path);

private:
    struct Impl;
    friend class Renderer;
    friend class FrameRecorder;
    explicit Plot(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
};

// Draws into an image of its own and reads it back.
class Renderer {
public:
    Renderer(const Drawing& drawing, uint32_t width, uint32_t height, const Look& look = {});
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    void setLook(const Look& look);
    Image render(const Camera& camera);  // one submission, waited for
    uint32_t dotsDrawn() const;          // by the last render
    // The marks of the last render — the dots the device found visible, read back — laid out on `page` and
    // written as SVG (an Inkscape layer a pen) or PDF by the extension of `path` (.svg, .pdf), atomically.
    // The same frame and page give the same bytes. docs/file-formats.md describes the files.
    std::vector<PenLayer> writeVector(const std::string& path, const Page& page = {}) const;
    Plot plot(const Page& page = {}) const;
    // The last render's stipples on the page, one object a point set: the front dots drawn, how many larger,
    // the outline's, and their spacing in windows of 128 pixels (docs/usage.md, "Stats JSON": `stipples`).
    std::string statsJson() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A colour image of the application's that a frame is drawn into. Its contents are discarded (cleared to the
// paper); it ends in `finalLayout`, and whatever the application records after the frame may use it (for
// PRESENT_SRC_KHR, the submission's semaphore orders the presentation).
struct FrameTarget {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkExtent2D extent{};
    VkImageLayout finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    // The stages the frame's first use of the image must follow (where the application's semaphore waits).
    VkPipelineStageFlags2 previousStages = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    // Also copy the drawing into a buffer of the recorder's (FrameRecorder::captured); the image must have been
    // made with VK_IMAGE_USAGE_TRANSFER_SRC_BIT.
    bool capture = false;
};

// Records frames into the application's command buffers: compute passes (visibility, dot selection,
// stamping), then one dynamic-rendering pass over the target. Each of `framesInFlight` frame slots owns its
// buffers; the application waits for a slot's previous submission before recording it again.
class FrameRecorder {
public:
    // framesInFlight: 1 to 16.
    FrameRecorder(const Drawing& drawing, VkFormat colorFormat, uint32_t framesInFlight, const Look& look = {});
    ~FrameRecorder();
    FrameRecorder(FrameRecorder&&) noexcept;
    FrameRecorder& operator=(FrameRecorder&&) noexcept;

    // Takes effect in the next recorded frame (recorded into it, after the frames before have read the old one).
    void setLook(const Look& look);
    // With `traceContours` false the contour last traced is drawn instead of this view's (an application whose
    // trace takes longer than its frame budget, Drawing::contourSeconds, traces once the eye stops).
    void record(VkCommandBuffer cmd, const Camera& camera, const FrameTarget& target, uint32_t frame,
                bool traceContours = true);
    // The drawing of slot `frame`, recorded with FrameTarget::capture, as RGBA: call it once the application
    // waited for that frame's submission.
    Image captured(uint32_t frame) const;
    // Renderer::writeVector for the last frame recorded in slot `frame`, in the target's pixels; waits for the
    // device to be idle first (the frame must have been submitted).
    std::vector<PenLayer> writeVector(const std::string& path, uint32_t frame, const Page& page = {}) const;
    Plot plot(uint32_t frame, const Page& page = {}) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkwell
