// Scene (scene.h): the model's point sets, made and replaced as one.
#include "scene.h"

#include <chrono>

namespace ink {

const char* drawStyleName(DrawStyle s) {
    return s == DrawStyle::Stipple ? "stipple" : s == DrawStyle::Direction ? "direction" : "both";
}

Scene::Scene(Context& c, Model m, DrawStyle style, const RefineOptions& options, const LineOptions& l)
    : ctx(c), model(std::move(m)) {
    refine(style, options, l);
}

void Scene::refine(DrawStyle style, const RefineOptions& options, const LineOptions& l) {
    vkDeviceWaitIdle(ctx.device);
    sets.clear();  // before the new ones are made: the device holds one scene's points at a time
    auto start = std::chrono::steady_clock::now();
    Sets made = build(style, options);
    replace(std::move(made), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), l);
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
    }
    return made;
}

void Scene::replace(Sets newSets, double seconds, const LineOptions& l) {
    vkDeviceWaitIdle(ctx.device);  // a frame in flight may still read the old sets
    sets = std::move(newSets);
    refineSeconds = seconds;
    setLines(traceLines(sets, l));
}

void Scene::replace(Sets newSets, double seconds, TracedLines traced) {
    vkDeviceWaitIdle(ctx.device);
    sets = std::move(newSets);
    refineSeconds = seconds;
    setLines(std::move(traced));
}

Scene::TracedLines Scene::traceLines(const Sets& from, const LineOptions& l) const {
    TracedLines t;
    t.options = l;
    if (!l.any() || from.empty()) return t;
    auto start = std::chrono::steady_clock::now();
    for (const PointRecord& p : readDrawnPoints(ctx, from.front()->gpu()))
        t.samples.push_back({Eigen::Vector3d(p.position[0], p.position[1], p.position[2]),
                             Eigen::Vector3d(p.normal[0], p.normal[1], p.normal[2])});
    if (l.hatching) t.hatching = traceHatching(model.surface, t.samples, l.hatch, &t.hatchStats);
    t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return t;
}

void Scene::setLines(TracedLines traced) {
    vkDeviceWaitIdle(ctx.device);  // a frame in flight may still read the old strokes
    lines = traced.options;
    samples = std::move(traced.samples);
    hatching = std::move(traced.hatching);
    hatchStats = traced.hatchStats;
    contours.clear();
    if (!lines.any()) {
        strokes.reset();
        hatchSeconds = 0;
        return;
    }
    auto start = std::chrono::steady_clock::now();
    if (!strokes) strokes = std::make_unique<StrokeBuffers>(ctx);
    strokes->set(StrokeBuffers::Hatching, hatching);
    strokes->set(StrokeBuffers::Contours, {});
    hatchSeconds = traced.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Scene::traceContours(const Camera& camera) {
    if (!strokes || !lines.contours) return;
    glm::vec3 eye = camera.eye();
    contours =
        ink::traceContours(model.surface, Eigen::Vector3d(eye.x, eye.y, eye.z), samples, lines.contour, &contourStats);
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
