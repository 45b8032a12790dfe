// inkwell::Drawing (include/inkwell/inkwell.h): a model's point sets and pen lines on a device, refined at once
// or in two halves (prepare, apply), read back, and its first view.
#include "api/impl.h"
#include "api/stats_json.h"
#include "inkwell/ranges.h"

#include "base/common.h"
#include "draw/scene.h"
#include "io/export.h"
#include "surface/viewpoint.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>

namespace inkwell {

using api::toEigen;
using api::toVec3;

// ---- Drawing

ink::LineOptions api::toLines(const DrawingOptions& o) {
    ranges::hatchSpacing.check(o.hatchSpacing, "hatchSpacing");
    if (!ranges::hatchFamilies.contains(o.hatchFamilies)) throw Error("hatchFamilies must be 1, 2 or 3");
    ink::LineOptions l;
    l.contours = o.contours;
    l.hatching = o.hatching;
    l.creases = o.creases;
    l.boundaries = o.boundaries;
    l.hatch.spacing = o.hatchSpacing;
    l.hatch.families = o.hatchFamilies;
    l.contourTracer = ink::LineOptions::ContourTracer(int(o.contourTracer));  // the same order
    l.fieldSolver = ink::LineOptions::FieldSolver(int(o.hatchField));
    return l;
}

std::vector<Polyline> toPolylines(const std::vector<ink::PenStroke>& strokes, const ink::Frame& frame) {
    std::vector<Polyline> out;
    for (const ink::PenStroke& s : strokes) {
        Polyline p;
        p.closed = s.closed;
        p.family = s.family;
        p.level = s.level;
        p.occluded = s.occluded;
        for (const Eigen::Vector3f& x : s.points) p.points.push_back(toVec3(frame.toInput(x.cast<double>())));
        out.push_back(std::move(p));
    }
    return out;
}

namespace {
std::atomic<uint64_t> gDrawings{0};  // drawings made in this process: each Drawing::Impl's id
}  // namespace

Drawing::Impl::Impl(ink::Context& ctx, std::shared_ptr<const ink::Model> model, const DrawingOptions& o)
    : scene(ctx, std::move(model), api::toDrawStyle(o.style), api::toRefine(o), api::toLines(o)), id(++gDrawings) {}

Drawing::Drawing(Device& device, const Model& model, const DrawingOptions& options, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    // The model's fit shared, not copied (the aliasing constructor: the Model's own count keeps it alive).
    impl_ = std::make_unique<Impl>(device.impl_->ctx,
                                   std::shared_ptr<const ink::Model>(model.impl_, &model.impl_->model), options);
    impl_->convention = model.impl_->convention;
    impl_->reporter = reporter;
    impl_->options = options;
}

namespace {

// 1 / 16384 to 16384: any image the command line makes (1 to 8192 pixels a side), with room; wider ones would
// frame the model in a subnormal sliver.
void checkAspect(float aspect) {
    if (!(aspect >= 1.0f / 16384 && aspect <= 16384))
        throw Error("firstView: aspect (width / height) must be in [1/16384, 16384]");
}

// The first set's points as the first view samples them (at most 20,000, read back once).
ink::ViewSamples firstSamples(ink::Scene& scene) {
    if (scene.sets.empty()) return {};
    ink::ViewSamples samples = ink::viewSamples(ink::readPoints(scene.ctx, scene.sets[0]->gpu()));
    samples.twoSided = scene.model.twoSided;
    return samples;
}

Up upOf(const std::optional<ink::UpAxis>& convention, const std::optional<ink::UpAxis>& base,
        const ink::ViewSamples& samples, bool empty, std::string* reason) {
    std::string why;
    Up up = Up::Y;
    if (convention) {
        why = "the glTF convention";
        up = Up(int(*convention));
    } else if (base) {
        why = "its open edges at one end";
        up = Up(int(*base));
    } else if (empty) {
        why = "no points";
    } else {
        const ink::UpChoice choice = ink::detectUpAxis(samples);
        why = choice.reason;
        up = Up(int(choice.up));
    }
    if (reason) *reason = why;
    return up;
}

FirstView viewOf(const ink::ViewSamples& samples, Up up, float aspect) {
    ink::Camera c;
    c.up = ink::UpAxis(int(up));
    const ink::ViewChoice view = ink::chooseView(samples, c.up);
    c.azimuthDeg = view.azimuthDeg;
    c.elevationDeg = view.elevationDeg;
    ink::frameSamples(c, samples, aspect);
    FirstView out;
    out.camera.up = up;
    out.camera.azimuthDeg = c.azimuthDeg;
    out.camera.elevationDeg = c.elevationDeg;
    out.camera.distance = c.distance;
    out.camera.fovyDeg = c.fovyDeg;
    out.camera.target = {c.target.x, c.target.y, c.target.z};
    out.upReason = "given";
    out.entropyBits = view.score;
    out.frontDeg = view.frontDeg;
    return out;
}

}  // namespace

Up Drawing::firstUp(std::string* reason) const {
    ink::Scene& scene = impl_->scene;
    const bool given = impl_->convention || scene.model.baseUp;
    const ink::ViewSamples samples = given ? ink::ViewSamples{} : firstSamples(scene);
    return upOf(impl_->convention, scene.model.baseUp, samples, scene.sets.empty(), reason);
}

Camera Drawing::firstView(float aspect) const { return firstViewReport(aspect).camera; }

Camera Drawing::firstView(Up up, float aspect) const { return firstViewReport(up, aspect).camera; }

FirstView Drawing::firstViewReport(float aspect) const {
    checkAspect(aspect);
    ink::Scene& scene = impl_->scene;
    const ink::ViewSamples samples = firstSamples(scene);
    std::string reason;
    FirstView v =
        viewOf(samples, upOf(impl_->convention, scene.model.baseUp, samples, scene.sets.empty(), &reason), aspect);
    v.upReason = reason;
    return v;
}

FirstView Drawing::firstViewReport(Up up, float aspect) const { return viewOf(firstSamples(impl_->scene), up, aspect); }

uint64_t Drawing::pointCount() const { return impl_->scene.points(); }

std::string Drawing::statsJson() const {
    ink::Scene& scene = impl_->scene;
    api::json levels = api::json::array();
    ink::HostMs hostMs;
    for (auto& set : scene.sets) {
        levels.push_back(api::levelsJson(ink::readLevelStats(scene.ctx, set->gpu())));
        hostMs += set->gpu().hostMs;
    }
    return api::json{{"refine",
                      {{"seconds", scene.refineSeconds},
                       {"points", scene.points()},
                       {"passes", scene.sets.empty() ? 0u : scene.sets.front()->gpu().plan.passes},
                       {"sets", levels},
                       {"host_ms", api::hostMsJson(hostMs)}}},
                     {"lines", api::linesJson(scene)}}
        .dump();
}

Drawing::~Drawing() = default;
Drawing::Drawing(Drawing&&) noexcept = default;
Drawing& Drawing::operator=(Drawing&&) noexcept = default;

void Drawing::refine(const DrawingOptions& options, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    impl_->scene.refine(api::toDrawStyle(options.style), api::toRefine(options), api::toLines(options));
    impl_->tracedEye = glm::vec3(NAN);
    impl_->reporter = reporter;
    impl_->options = options;
    ++impl_->generation;
}

struct Drawing::Pending::Impl {
    uint64_t drawing = 0, generation = 0;  // prepared for this drawing (its id), at this generation
    DrawingOptions options;
    bool refine = false, traced = false;
    ink::Scene::Sets sets;
    double seconds = 0;
    ink::Scene::TracedLines lines;
};

Drawing::Pending::Pending() = default;
Drawing::Pending::~Pending() = default;
Drawing::Pending::Pending(Pending&&) noexcept = default;
Drawing::Pending& Drawing::Pending::operator=(Pending&&) noexcept = default;
bool Drawing::Pending::refined() const { return impl_ && impl_->refine; }
double Drawing::Pending::seconds() const { return impl_ ? impl_->seconds : 0; }
bool Drawing::Pending::traced() const { return impl_ && impl_->traced; }
double Drawing::Pending::traceSeconds() const { return impl_ ? impl_->lines.seconds : 0; }
size_t Drawing::Pending::hatchStrokes() const { return impl_ ? impl_->lines.hatching.size() : 0; }

namespace {

// Whether two options make the same point sets.
bool sameSets(const DrawingOptions& a, const DrawingOptions& b) {
    return a.style == b.style && a.levels == b.levels && a.passes == b.passes && a.direction == b.direction &&
           a.axis == b.axis && a.distribution == b.distribution && a.candidatesPerStipple == b.candidatesPerStipple &&
           a.seed == b.seed && a.rho == b.rho && a.rhoDivisor == b.rhoDivisor && a.gridSeeds == b.gridSeeds &&
           a.grid == b.grid && a.keepAllLevels == b.keepAllLevels;
}

// Whether two options trace the same hatching (and the same seeds for the contour).
bool sameHatching(const DrawingOptions& a, const DrawingOptions& b) {
    return a.hatching == b.hatching &&
           (!a.hatching ||
            (a.hatchSpacing == b.hatchSpacing && a.hatchFamilies == b.hatchFamilies && a.hatchField == b.hatchField));
}

}  // namespace

Drawing::Work Drawing::work(const DrawingOptions& options) const {
    if (!sameSets(options, impl_->options)) return Work::Sets;
    const bool lines = impl_->scene.drawable(api::toLines(options)).any();
    return sameHatching(options, impl_->options) && (impl_->scene.lines.any() || !lines) ? Work::None : Work::Lines;
}

Drawing::Pending Drawing::prepare(const DrawingOptions& options, const Reporter& reporter) const {
    ink::ScopedReporter reporting(reporter);
    const ink::RefineOptions refine = api::toRefine(options);
    const ink::LineOptions lines = api::toLines(options);
    const ink::Scene& scene = impl_->scene;
    Pending pending;
    pending.impl_ = std::make_unique<Pending::Impl>();
    Pending::Impl& p = *pending.impl_;
    p.drawing = impl_->id;
    p.generation = impl_->generation;
    p.options = options;
    const Work work = this->work(options);
    p.refine = work == Work::Sets;
    if (work == Work::None) {
        p.lines = {scene.drawable(lines), scene.samples, scene.hatching, scene.hatchStats,
                   scene.hatchSeconds};  // which lines only
        return pending;
    }
    if (p.refine) {
        const auto start = std::chrono::steady_clock::now();
        p.sets = scene.build(api::toDrawStyle(options.style), refine);
        p.seconds = ink::secondsSince(start);
    }
    p.traced = true;
    p.lines = scene.traceLines(p.refine ? p.sets : scene.sets, lines);
    return pending;
}

void Drawing::apply(Pending&& pending) {
    if (!pending.impl_) throw Error("Drawing::apply: nothing prepared");
    Pending::Impl& p = *pending.impl_;
    if (p.drawing != impl_->id || p.generation != impl_->generation)
        throw Error("Drawing::apply: prepared for another drawing, or before this one changed (prepare it again)");
    ink::Scene& scene = impl_->scene;
    if (p.refine)
        scene.replace(std::move(p.sets), p.seconds, std::move(p.lines));
    else
        scene.setLines(std::move(p.lines));
    impl_->options = p.options;
    impl_->tracedEye = glm::vec3(NAN);
    ++impl_->generation;
    pending = Pending();
}

DrawingOptions Drawing::options() const { return impl_->options; }

double Drawing::contourSeconds() const { return impl_->traceSeconds; }

std::vector<Polyline> Drawing::hatching() const {
    return toPolylines(impl_->scene.hatching, impl_->scene.model.surface.frame);
}

std::vector<Polyline> Drawing::contours(const Camera& camera) const {
    impl_->traceFor(api::toCamera(camera));
    return toPolylines(impl_->scene.contours, impl_->scene.model.surface.frame);
}

std::vector<Polyline> Drawing::creases() const {
    return toPolylines(impl_->scene.model.features.creases, impl_->scene.model.surface.frame);
}

std::vector<Polyline> Drawing::boundaries() const {
    return toPolylines(impl_->scene.model.features.boundaries, impl_->scene.model.surface.frame);
}

size_t Drawing::sets() const { return impl_->scene.sets.size(); }

std::vector<Point> Drawing::points(size_t set) const {
    ink::Scene& scene = impl_->scene;
    if (set >= scene.sets.size()) throw Error("no point set " + std::to_string(set));
    const ink::Frame& frame = scene.model.surface.frame;
    std::vector<Point> out;
    for (const ink::PointRecord& p : ink::readDrawnPoints(scene.ctx, scene.sets[set]->gpu())) {
        Eigen::Vector3d x(p.position[0], p.position[1], p.position[2]);
        out.push_back({toVec3(frame.toInput(x)), {p.normal[0], p.normal[1], p.normal[2]}, p.tone, p.level});
    }
    return out;
}

void Drawing::writePly(const std::string& path, size_t set) const {
    ink::Scene& scene = impl_->scene;
    if (set >= scene.sets.size()) throw Error("no point set " + std::to_string(set));
    ink::writePointsPly(path, ink::readDrawnPoints(scene.ctx, scene.sets[set]->gpu()), scene.model.surface.frame);
}

}  // namespace inkwell
