// Scene (scene.h): the model's point sets, made and replaced as one.
#include "draw/scene.h"

#include "lines/cross_field_device.h"
#include "lines/feature_lines.h"

#include "base/common.h"
#include "base/parallel.h"
#include "select/select.h"

#include <chrono>

namespace ink {

namespace {

// Where `auto` puts the pen lines' device passes (the contour, the cross field): on a GPU. On a CPU driver
// (lavapipe) their CPU twins are the faster (docs/lines.md).
bool autoOnDevice(const Context& ctx) { return ctx.properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU; }

// Drops the drawn points of `r` that `model` does not hold (Model::holds), keeping the others in order (a stipple
// keeps its rank); returns how many went, and how many there were in `total`.
size_t trimRefinement(Context& ctx, GpuRefinement& r, const Model& model, size_t& total) {
    total = 0;
    if (!model.trims()) return 0;
    const std::vector<PointRecord> points = readDrawnPoints(ctx, r);
    total = points.size();
    // Which are held, on all threads (a scan's 338,838 points, 27 cells a look-up), then kept in order.
    std::vector<char> held(points.size());
    parallelChunks(points.size(), 4096, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
            const PointRecord& p = points[i];
            held[i] = model.holds(Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
        }
    });
    std::vector<PointRecord> kept;
    kept.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i)
        if (held[i]) kept.push_back(points[i]);
    if (kept.size() == points.size()) return 0;
    uint32_t draw[4];
    downloadBuffer(ctx, r.indirect, r.drawOffset(), draw, sizeof(draw));
    const VkDeviceSize first = r.selection ? 0 : VkDeviceSize(draw[2]) * sizeof(PointRecord);
    uploadBufferAt(ctx, r.selection ? r.selection->stipples : r.points, first, kept.data(),
                   kept.size() * sizeof(PointRecord));
    draw[0] = uint32_t(kept.size());
    uploadBufferAt(ctx, r.indirect, r.drawOffset(), draw, sizeof(draw[0]));
    return points.size() - kept.size();
}

}  // namespace

const char* drawStyleName(DrawStyle s) {
    return s == DrawStyle::Stipple ? "stipple" : s == DrawStyle::Direction ? "direction" : "both";
}

Scene::Scene(Context& c, Model m, DrawStyle style, const RefineOptions& options, const LineOptions& l)
    : Scene(c, std::make_shared<const Model>(std::move(m)), style, options, l) {}

Scene::Scene(Context& c, std::shared_ptr<const Model> m, DrawStyle style, const RefineOptions& options,
             const LineOptions& l)
    : ctx(c), model_(std::move(m)), model(*model_) {
    refine(style, options, l);
}

void Scene::refine(DrawStyle style, const RefineOptions& options, const LineOptions& l) {
    vkDeviceWaitIdle(ctx.device);
    deviceContours_.reset();
    sets.clear();  // before the new ones are made: the device holds one scene's points at a time
    auto start = std::chrono::steady_clock::now();
    Sets made = build(style, options);
    replace(std::move(made), secondsSince(start), l);
}

Scene::Sets Scene::build(DrawStyle style, const RefineOptions& options) const {
    std::vector<SampleStyle> styles;
    if (style != DrawStyle::Direction) styles.push_back(SampleStyle::Stipple);
    if (style != DrawStyle::Stipple) styles.push_back(SampleStyle::Direction);
    Sets made;
    for (SampleStyle sampling : styles) {
        RefineOptions r = options;
        r.style = sampling;
        made.push_back(std::make_unique<Refinement>(ctx, model.surface, r));
        runRefinement(ctx, made.back()->gpu());
        size_t total = 0;
        if (const size_t trimmed = trimRefinement(ctx, made.back()->gpu(), model, total))
            note("trimmed " + std::to_string(trimmed) + " of " + std::to_string(total) + " " +
                 (sampling == SampleStyle::Stipple ? "stipple" : "direction") +
                 " points where the input has no points (an open surface's holes, the fit's stray sheets; --no-trim "
                 "keeps them)");
        made.back()->gpu().twoSided = model.twoSided;
    }
    return made;
}

void Scene::replace(Sets newSets, double seconds, const LineOptions& l) {
    vkDeviceWaitIdle(ctx.device);  // a frame in flight may still read the old sets
    deviceContours_.reset();
    sets = std::move(newSets);
    refineSeconds = seconds;
    setLines(traceLines(sets, l));
}

void Scene::replace(Sets newSets, double seconds, TracedLines traced) {
    vkDeviceWaitIdle(ctx.device);
    deviceContours_.reset();
    sets = std::move(newSets);
    refineSeconds = seconds;
    setLines(std::move(traced));
}

LineOptions Scene::drawable(LineOptions l) const {
    l.creases = l.creases && !model.features.creases.empty();
    l.boundaries = l.boundaries && !model.features.boundaries.empty();
    return l;
}

Scene::TracedLines Scene::traceLines(const Sets& from, const LineOptions& l) const {
    TracedLines t;
    t.options = drawable(l);
    if (!t.options.any() || from.empty()) return t;
    auto start = std::chrono::steady_clock::now();
    for (const PointRecord& p : readDrawnPoints(ctx, from.front()->gpu()))
        t.samples.push_back({Eigen::Vector3d(p.position[0], p.position[1], p.position[2]),
                             Eigen::Vector3d(p.normal[0], p.normal[1], p.normal[2])});
    if (l.hatching) {
        const GpuRefinement& first = from.front()->gpu();
        using Solver = LineOptions::FieldSolver;
        const bool device = (l.fieldSolver == Solver::Device || (l.fieldSolver == Solver::Auto && autoOnDevice(ctx))) &&
                            solvesCrossFieldOnDevice(first);
        if (l.fieldSolver == Solver::Device && !device && !notedCpuField_) {
            note(
                "the hatching's cross field is solved on the CPU: the device solves a partition-of-unity fit only "
                "(not --fit global)");
            notedCpuField_ = true;
        }
        // The graph on the host, the field solved where chosen; the comb and the look-up grid on the host.
        const auto fieldStart = std::chrono::steady_clock::now();
        const CrossFieldOptions& f = l.hatch.field;
        const CrossFieldGraph graph = buildCrossFieldGraph(t.samples, f.neighbours, f.threads);
        const double graphSeconds = secondsSince(fieldStart);
        const bool fits = !device || crossFieldFitsDevice(ctx, graph);
        if (!fits)
            note("the hatching's cross field is solved on the CPU: its " + std::to_string(t.samples.size()) +
                 " samples pass the device's largest storage buffer");
        double deviceMs = 0;
        CrossFieldSolution solved = device && fits ? solveCrossFieldOnDevice(ctx, first, t.samples, graph, f, &deviceMs)
                                                   : solveCrossField(model.surface, t.samples, graph, f);
        const CrossField field(t.samples, graph, std::move(solved), f.featureSize);
        const double fieldSeconds = secondsSince(fieldStart);
        t.hatching = trimStrokes(traceHatching(model.surface, field, l.hatch, &t.hatchStats), model);
        t.hatchStats.fieldSeconds = fieldSeconds;
        t.hatchStats.fieldGraphSeconds = graphSeconds;
        t.hatchStats.fieldOnDevice = device && fits;
        t.hatchStats.fieldDeviceMs = deviceMs;
        t.hatchStats.seconds += fieldSeconds;
    }
    t.seconds = secondsSince(start);
    return t;
}

void Scene::setLines(TracedLines traced) {
    vkDeviceWaitIdle(ctx.device);  // a frame in flight may still read the old strokes
    deviceContours_.reset();
    lines = traced.options;
    samples = std::move(traced.samples);
    hatching = std::move(traced.hatching);
    hatchStats = traced.hatchStats;
    contours.clear();
    snap_ = {};
    if (!lines.any()) {
        strokes.reset();
        hatchSeconds = 0;
        return;
    }
    auto start = std::chrono::steady_clock::now();
    if (!strokes) strokes = std::make_unique<StrokeBuffers>(ctx);
    strokes->set(StrokeBuffers::Hatching, hatching);
    strokes->set(StrokeBuffers::Contours, {});
    strokes->set(StrokeBuffers::Creases, lines.creases ? model.features.creases : std::vector<PenStroke>{});
    std::vector<PenStroke> drawn;  // the feature lines the contour is laid onto where it runs along them
    if (lines.creases) drawn = model.features.creases;
    if (lines.boundaries) drawn.insert(drawn.end(), model.features.boundaries.begin(), model.features.boundaries.end());
    snap_ = LineSnap(drawn, 2 * lines.contour.step);
    strokes->set(StrokeBuffers::Boundaries, lines.boundaries ? model.features.boundaries : std::vector<PenStroke>{});
    hatchSeconds = traced.seconds + secondsSince(start);
}

void Scene::traceContours(const Camera& camera) {
    if (!strokes || !lines.contours) return;
    const glm::vec3 e = camera.eye();
    const Eigen::Vector3d eye(e.x, e.y, e.z);
    const GpuRefinement* first = sets.empty() ? nullptr : &sets.front()->gpu();
    using Tracer = LineOptions::ContourTracer;
    const bool onDevice =
        lines.contourTracer == Tracer::Device || (lines.contourTracer == Tracer::Auto && autoOnDevice(ctx));
    if (onDevice && first && DeviceContours::supports(*first) && !samples.empty()) {
        if (!deviceContours_)
            deviceContours_ = std::make_unique<DeviceContours>(ctx, *first, uint32_t(samples.size()), lines.contour);
        contours = trimStrokes(deviceContours_->trace(model.surface, eye, &contourStats), model);
    } else {
        if (lines.contourTracer == Tracer::Device && first && !DeviceContours::supports(*first) && !notedCpuContours_) {
            note(
                "the contour is traced on the CPU: the device traces a partition-of-unity fit only (not --fit global)");
            notedCpuContours_ = true;
        }
        contours = trimStrokes(ink::traceContours(model.surface, eye, samples, lines.contour, &contourStats), model);
    }
    // A crease or boundary line drawn stands for its edge: the contour along it, within two steps, is laid onto it
    // (snapToLines, indexed in setLines), and the scraps the fit's ripple leaves between, under eight steps, bridged.
    contours = snap_.apply(contours, 8 * lines.contour.step);
    strokes->set(StrokeBuffers::Contours, contours);
}

std::vector<const GpuRefinement*> Scene::pointers() const {
    std::vector<const GpuRefinement*> p;
    for (const auto& s : sets) p.push_back(&s->gpu());
    return p;
}

uint64_t Scene::points() {
    uint64_t total = 0;
    for (auto& s : sets)
        for (const LevelStats& l : readLevelStats(ctx, s->gpu())) total += l.kept;
    return total;
}

}  // namespace ink
