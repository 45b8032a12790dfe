// The public API (include/inkwell/inkwell.h) over the engine: each public object owns the engine object it
// names, and long calls install the caller's Reporter for their duration.
#include "api/impl.h"
#include "inkwell/ranges.h"

#include "base/common.h"
#include "base/files.h"
#include "base/image.h"
#include "draw/renderer.h"
#include "draw/scene.h"
#include "gpu/context.h"
#include "io/export.h"
#include "io/hrbf_io.h"
#include "surface/fidelity.h"
#include "surface/model.h"
#include "surface/surface_sampling.h"
#include "surface/viewpoint.h"
#include "vector/vector.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace inkwell {

namespace api {

Eigen::Vector3d toEigen(const Vec3& v) { return {v[0], v[1], v[2]}; }
Vec3 toVec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

ink::Camera toCamera(const Camera& c) {
    ink::Camera camera;
    camera.up = ink::UpAxis(int(c.up));  // the same order
    camera.azimuthDeg = c.azimuthDeg;
    camera.elevationDeg = c.freeOrbit ? c.elevationDeg : std::clamp(c.elevationDeg, -89.0f, 89.0f);
    camera.distance = c.distance;
    camera.fovyDeg = c.fovyDeg;
    camera.freeOrbit = c.freeOrbit;
    camera.target = glm::vec3(c.target[0], c.target[1], c.target[2]);
    return camera;
}

// Every value of a Look against its range (the one table the command line checks too): one Error naming the
// field.
void checkLook(const Look& look) {
    for (const Color* c : {&look.ink, &look.paper})
        for (float v : *c)
            if (!(v >= 0 && v <= 1))
                throw Error(std::string(c == &look.ink ? "ink" : "paper") + " colour components must be in [0, 1]");
    ranges::dotSize.check(look.dotSize, "dotSize");
    ranges::dotSize.check(look.silhouetteSize, "silhouetteSize");
    ranges::tau.check(look.tau, "tau");
    ranges::toneGamma.check(look.toneGamma, "toneGamma");
    ranges::inkDensity.check(look.inkDensity, "inkDensity");
    ranges::hiddenOpacity.check(look.hiddenOpacity, "hiddenOpacity");
    ranges::dotSize.check(look.hiddenDotSize, "hiddenDotSize");
    for (float width : {look.penWidth, look.hatchWidth, look.hiddenPenWidth, look.creaseWidth, look.boundaryWidth})
        ranges::penWidth.check(width, "pen widths");
    ranges::halo.check(look.halo, "halo");
    const float light = std::hypot(look.light[0], look.light[1], look.light[2]);
    if (!(light > 0) || !std::isfinite(light)) throw Error("light must be a finite, non-zero vector");
    if (!ranges::supersample.contains(look.supersample)) throw Error("supersample must be 1 to 4");
}

ink::RenderStyle toStyle(const Look& look) {
    checkLook(look);
    ink::RenderStyle s;
    s.ink = {look.ink[0], look.ink[1], look.ink[2], look.ink[3]};
    s.paper = {look.paper[0], look.paper[1], look.paper[2], look.paper[3]};
    s.hiddenInk = glm::vec4(glm::vec3(s.ink), look.hiddenOpacity);
    s.hiddenSize = look.hiddenDotSize;
    s.frontSize = look.dotSize;
    s.silhouetteSize = look.silhouetteSize;
    s.tau = look.tau;
    s.toneGamma = look.toneGamma;
    s.inkDensity = look.inkDensity;
    s.hiddenLines = look.hiddenLines;
    s.light = {look.light[0], look.light[1], look.light[2]};
    s.lightFollowsCamera = look.lightFollowsCamera;
    s.supersample = look.supersample;
    s.drawDots = look.dots;
    s.screenSpacing = look.screenSpacing;
    s.penWidth = look.penWidth;
    s.hatchWidth = look.hatchWidth;
    s.hiddenPenWidth = look.hiddenPenWidth;
    s.haloWidth = look.halo;
    s.creaseWidth = look.creaseWidth;
    s.boundaryWidth = look.boundaryWidth;
    return s;
}

ink::RefineOptions toRefine(const DrawingOptions& o) {
    if (o.levels >= ink::kMaxLevels)
        throw Error("levels " + std::to_string(o.levels) + " is too many: at most " +
                    std::to_string(ink::kMaxLevels - 1));
    ranges::candidatesPerStipple.check(o.candidatesPerStipple, "candidatesPerStipple");
    ink::RefineOptions r;
    r.levels = o.levels;
    r.seed = o.seed;
    r.distribution =
        o.distribution == Distribution::BlueNoise ? ink::Distribution::BlueNoise : ink::Distribution::Refinement;
    r.candidatesPerStipple = o.candidatesPerStipple;
    return r;
}

ink::DrawStyle toDrawStyle(Style s) {
    return s == Style::Stipple     ? ink::DrawStyle::Stipple
           : s == Style::Direction ? ink::DrawStyle::Direction
                                   : ink::DrawStyle::Both;
}

static_assert(int(Up::NegZ) == int(ink::UpAxis::NegZ) && int(Up::Y) == int(ink::UpAxis::PosY));
static_assert(ranges::levels.hi == ink::kMaxLevels - 1, "ranges.h: levels follow the device's MAX_LEVELS");

}  // namespace api

using api::toEigen;
using api::toVec3;

// ---- Model

ink::ModelOptions api::toInk(const ModelOptions& o) {
    return {o.controlPoints, o.method == FitMethod::Global ? ink::FitMethod::Global : ink::FitMethod::PartitionOfUnity,
            o.creaseAngleDeg, o.trim};
}

Model Model::load(const std::string& path, const ModelOptions& options, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    ink::checkModelOptions(api::toInk(options));
    return Model(
        std::make_shared<const Impl>(Impl{ink::loadModel(path, api::toInk(options)), ink::formatUpAxis(path)}));
}

Model Model::fit(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals, const ModelOptions& options,
                 const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    ink::checkModelOptions(api::toInk(options));
    if (positions.size() != normals.size())
        throw Error(std::to_string(positions.size()) + " positions but " + std::to_string(normals.size()) +
                    " normals: give one normal a point");
    ink::OrientedPoints points;
    for (size_t i = 0; i < positions.size(); ++i) {
        Eigen::Vector3d n = toEigen(normals[i]);
        if (!toEigen(positions[i]).allFinite() || !n.allFinite() || !(n.norm() > 0))
            throw Error("point " + std::to_string(i) + " has a non-finite coordinate or a zero normal");
        points.positions.push_back(toEigen(positions[i]));
        points.normals.push_back(n.normalized());
    }
    return Model(std::make_shared<const Impl>(Impl{ink::fitModel(std::move(points), api::toInk(options))}));
}

void Model::save(const std::string& path) const { ink::saveHrbf(path, impl_->model.surface); }

FitReport Model::report() const {
    const ink::Model& m = impl_->model;
    FitReport r;
    r.inputPoints = m.inputPoints;
    r.mergedDuplicates = m.mergedDuplicates;
    r.flippedNormals = m.flippedNormals;
    r.controlPoints = m.fit.controlPoints;
    r.seconds = m.fit.seconds;
    r.maxDistance = m.fit.maxDistance;
    r.maxNormalAngleDeg = m.fit.maxNormalAngleDeg;
    r.inputMaxDistance = m.inputMaxDistance;
    r.inputMaxAngleDeg = m.inputMaxAngleDeg;
    r.patches = m.patches.patches;
    return r;
}

double Model::value(const Vec3& x) const {
    const ink::Surface& h = impl_->model.surface;
    return h.f(h.frame.toNormalized(toEigen(x)));
}

Vec3 Model::gradient(const Vec3& x) const {
    const ink::Surface& h = impl_->model.surface;
    Eigen::Vector3d g;
    h.eval(h.frame.toNormalized(toEigen(x)), g);
    return toVec3(g * h.frame.scale);  // d/dx_input = scale · d/dx_normalized
}

// ---- Fidelity

Fidelity measureFidelity(const std::string& meshPath, const std::vector<Vec3>& points, double tolerance,
                         const Reporter& reporter, double creaseAngleDeg) {
    ink::ScopedReporter reporting(reporter);
    if (!(tolerance > 0)) throw Error("the fidelity tolerance must be positive (it is in bounding-box diagonals)");
    if (!(creaseAngleDeg > 0 && creaseAngleDeg < 180)) throw Error("the crease angle must be in (0, 180) degrees");
    ink::OrientedPoints mesh = ink::loadPoints(meshPath);
    double area = 0;
    for (double a : ink::triangleAreas(mesh)) area += a;
    if (!(area > 0)) throw Error(meshPath + ": fidelity needs a mesh with faces; this file has none with area");
    std::vector<Eigen::Vector3d> at;
    at.reserve(points.size());
    for (const Vec3& p : points) at.push_back(toEigen(p));
    ink::Fidelity f = ink::measureFidelity(mesh, at, tolerance, 0, creaseAngleDeg);
    return {f.tolerance,   f.surfaceSamples, f.points,      f.coverage,   f.coverageP99,
            f.coverageMax, f.accuracy,       f.accuracyP99, f.accuracyMax};
}

// ---- Device

Device::Device(const DeviceOptions& options) : impl_(std::make_unique<Impl>()) {
    ink::ContextOptions o;
    o.validation = options.validation;
    o.device = options.device;
    o.presentation = options.presentation;
    o.instanceExtensions = options.instanceExtensions;
    o.validationMessage = options.validationMessage;
    ink::createContext(impl_->ctx, o);  // on a throw, ~Impl releases what was made
}

Device::Device(const AdoptedDevice& device) : impl_(std::make_unique<Impl>()) { ink::adoptContext(impl_->ctx, device); }

Device::~Device() = default;
Device::Device(Device&&) noexcept = default;
Device& Device::operator=(Device&&) noexcept = default;

std::string Device::name() const { return impl_->ctx.properties.deviceName; }
uint32_t Device::validationErrors() const { return impl_->ctx.validationErrors.load(); }
uint32_t Device::validationWarnings() const { return impl_->ctx.validationWarnings.load(); }
std::string Device::driver() const { return impl_->ctx.driverInfo; }
std::string Device::firstValidationError() const { return impl_->ctx.firstValidationMessage; }

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
    return l;
}

std::vector<Polyline> toPolylines(const std::vector<ink::PenStroke>& strokes, const ink::Frame& frame) {
    std::vector<Polyline> out;
    for (const ink::PenStroke& s : strokes) {
        Polyline p;
        p.closed = s.closed;
        p.family = s.family;
        p.level = s.level;
        for (const Eigen::Vector3f& x : s.points) p.points.push_back(toVec3(frame.toInput(x.cast<double>())));
        out.push_back(std::move(p));
    }
    return out;
}

Drawing::Impl::Impl(ink::Context& ctx, const ink::Model& model, const DrawingOptions& o)
    : scene(ctx, model, api::toDrawStyle(o.style), api::toRefine(o), api::toLines(o)) {}

Drawing::Drawing(Device& device, const Model& model, const DrawingOptions& options, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    impl_ = std::make_unique<Impl>(device.impl_->ctx, model.impl_->model, options);
    impl_->convention = model.impl_->convention;
}

Up Drawing::firstUp() const {
    if (impl_->convention) return Up(int(*impl_->convention));
    ink::Scene& scene = impl_->scene;
    if (scene.sets.empty()) return Up::Y;
    return Up(int(ink::detectUpAxis(ink::viewSamples(ink::readPoints(scene.ctx, scene.sets[0]->gpu()))).up));
}

Camera Drawing::firstView(float aspect) const { return firstView(firstUp(), aspect); }

Camera Drawing::firstView(Up up, float aspect) const {
    if (!(aspect >= 0.01f && aspect <= 100.0f)) throw Error("firstView: aspect must be in [0.01, 100]");
    ink::Scene& scene = impl_->scene;
    ink::ViewSamples samples;
    if (!scene.sets.empty()) samples = ink::viewSamples(ink::readPoints(scene.ctx, scene.sets[0]->gpu()));
    ink::Camera c;
    c.up = ink::UpAxis(int(up));
    const ink::ViewChoice view = ink::chooseView(samples, c.up);
    c.azimuthDeg = view.azimuthDeg;
    c.elevationDeg = view.elevationDeg;
    ink::frameSamples(c, samples, aspect);
    Camera out;
    out.up = up;
    out.azimuthDeg = c.azimuthDeg;
    out.elevationDeg = c.elevationDeg;
    out.distance = c.distance;
    out.fovyDeg = c.fovyDeg;
    out.target = {c.target.x, c.target.y, c.target.z};
    return out;
}

Drawing::~Drawing() = default;
Drawing::Drawing(Drawing&&) noexcept = default;
Drawing& Drawing::operator=(Drawing&&) noexcept = default;

void Drawing::refine(const DrawingOptions& options, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    impl_->scene.refine(api::toDrawStyle(options.style), api::toRefine(options), api::toLines(options));
    impl_->tracedEye = glm::vec3(NAN);
    ++impl_->generation;
}

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

// ---- Rendering

void Image::writePng(const std::string& path) const { ink::writePng(path, {width, height, rgba}); }

Page Page::named(const std::string& size) {
    glm::dvec2 mm = ink::parsePageSize(size);
    Page page;
    page.widthMm = mm.x;
    page.heightMm = mm.y;
    return page;
}

namespace {

std::vector<PenLayer> writeVectorDrawing(const std::string& path, const ink::VectorDrawing& marks, const Page& p) {
    if (!ink::isVectorPath(path)) throw Error("'" + path + "' is not an .svg or .pdf file");
    ink::PageOptions o;
    o.width = p.widthMm;
    o.height = p.heightMm;
    o.orientation = ink::Orientation(int(p.orientation));  // the same order
    o.margin = p.marginMm;
    o.penWidth = p.penWidthMm;
    o.dotStyle = p.dotStyle == DotStyle::Tick ? ink::DotStyle::Tick : ink::DotStyle::Circle;
    o.order = p.orderPaths;
    if (!(o.width >= 10 && o.height >= 10 && o.width <= 5000 && o.height <= 5000))
        throw Error("a page's sides must be 10 to 5000 mm");
    ink::Plot plot = ink::layoutPlot(marks, o);
    ink::writePlot(path, plot);
    std::vector<PenLayer> layers;
    for (const ink::PlotLayer& l : plot.layers)
        layers.push_back(
            {l.pen, l.name, l.paths.size(), l.travelBefore, l.travelAfter, l.penDown, l.lifts, l.plotSeconds});
    return layers;
}

}  // namespace

// A renderer's descriptors name the drawing's sets. Drawing::refine replaces those (after waiting for the
// device), so a renderer made before it is made again, for the new sets, before it next draws
// (VUID-vkCmdDispatch-None-02699 otherwise: descriptors of destroyed buffers).
struct Renderer::Impl {
    Drawing::Impl& drawing;
    uint32_t width, height;
    ink::RenderStyle style;
    uint64_t generation;
    std::unique_ptr<ink::OffscreenRenderer> renderer;
    bool rendered = false;  // a frame since the renderer was made for the drawing's sets
    Impl(Drawing::Impl& d, uint32_t w, uint32_t h, const ink::RenderStyle& s)
        : drawing(d), width(w), height(h), style(s), generation(d.generation), renderer(make()) {}
    std::unique_ptr<ink::OffscreenRenderer> make() const {
        return std::make_unique<ink::OffscreenRenderer>(drawing.scene.ctx, width, height, style,
                                                        drawing.scene.pointers(), drawing.scene.strokes.get());
    }
    // The renderer for the drawing's current sets.
    ink::OffscreenRenderer& current() {
        if (generation != drawing.generation) {
            renderer.reset();
            renderer = make();
            generation = drawing.generation;
            rendered = false;
        }
        return *renderer;
    }
};

Renderer::Renderer(const Drawing& drawing, uint32_t width, uint32_t height, const Look& look) {
    ink::Scene& scene = drawing.impl_->scene;
    ink::RenderStyle style = api::toStyle(look);
    ink::checkOffscreenSize(scene.ctx, width, height, style.supersample);
    impl_ = std::make_unique<Impl>(*drawing.impl_, width, height, style);
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::setLook(const Look& look) {
    ink::RenderStyle style = api::toStyle(look);
    if (style.supersample != impl_->style.supersample)
        throw Error("setLook cannot change supersample (" + std::to_string(impl_->style.supersample) + " to " +
                    std::to_string(style.supersample) + "): make a new Renderer");
    style.up = impl_->style.up;
    impl_->style = style;
    impl_->current().setStyle(impl_->style);
}

Image Renderer::render(const Camera& camera) {
    ink::OffscreenRenderer& renderer = impl_->current();
    if (impl_->style.up != ink::UpAxis(int(camera.up))) {  // the fixed light is given about the up axis
        impl_->style.up = ink::UpAxis(int(camera.up));
        renderer.setStyle(impl_->style);
    }
    impl_->drawing.traceFor(api::toCamera(camera));
    ink::RgbaImage image = renderer.render(api::toCamera(camera));
    impl_->rendered = true;
    return {image.width, image.height, std::move(image.pixels)};
}

uint32_t Renderer::dotsDrawn() const {
    ink::OffscreenRenderer& renderer = impl_->current();
    return impl_->rendered ? renderer.drawnDots() : 0;
}

std::vector<PenLayer> Renderer::writeVector(const std::string& path, const Page& page) const {
    ink::OffscreenRenderer& renderer = impl_->current();
    if (!impl_->rendered) throw Error("Renderer::writeVector: no frame of the drawing's points rendered yet");
    return writeVectorDrawing(path, renderer.vectorDrawing(), page);
}

// As Renderer::Impl: made again for the drawing's new sets after Drawing::refine, before the next record.
struct FrameRecorder::Impl {
    Drawing::Impl& drawing;
    VkFormat format;
    uint32_t frames;
    uint64_t generation;
    std::unique_ptr<ink::PointRenderer> renderer;
    ink::RenderStyle style;
    bool restyle = true;
    std::vector<bool> recorded;  // a slot's frame recorded since the renderer was made for the drawing's sets
    Impl(Drawing::Impl& d, VkFormat f, uint32_t n, const ink::RenderStyle& s)
        : drawing(d), format(f), frames(n), generation(d.generation), renderer(make()), style(s), recorded(n) {}
    std::unique_ptr<ink::PointRenderer> make() const {
        return std::make_unique<ink::PointRenderer>(drawing.scene.ctx, drawing.scene.pointers(), format, frames,
                                                    drawing.scene.strokes.get());
    }
    ink::PointRenderer& current() {
        if (generation != drawing.generation) {
            vkDeviceWaitIdle(drawing.scene.ctx.device);  // frames submitted since refine() still read the old
            renderer.reset();
            renderer = make();
            generation = drawing.generation;
            restyle = true;
            recorded.assign(frames, false);
        }
        return *renderer;
    }
};

FrameRecorder::FrameRecorder(const Drawing& drawing, VkFormat colorFormat, uint32_t framesInFlight, const Look& look) {
    impl_ = std::make_unique<Impl>(*drawing.impl_, colorFormat, std::max(1u, framesInFlight), api::toStyle(look));
}

FrameRecorder::~FrameRecorder() = default;
FrameRecorder::FrameRecorder(FrameRecorder&&) noexcept = default;
FrameRecorder& FrameRecorder::operator=(FrameRecorder&&) noexcept = default;

void FrameRecorder::setLook(const Look& look) {
    impl_->style = api::toStyle(look);
    impl_->restyle = true;
}

void FrameRecorder::record(VkCommandBuffer cmd, const Camera& camera, const FrameTarget& target, uint32_t frame) {
    if (frame >= impl_->frames)
        throw Error("frame " + std::to_string(frame) + " is not one of the " + std::to_string(impl_->frames) +
                    " frames in flight");
    ink::PointRenderer& renderer = impl_->current();
    if (impl_->style.up != ink::UpAxis(int(camera.up))) {
        impl_->style.up = ink::UpAxis(int(camera.up));
        impl_->restyle = true;
    }
    if (impl_->restyle) {
        renderer.setStyle(cmd, impl_->style, 1.0f);
        impl_->restyle = false;
    }
    impl_->drawing.traceFor(api::toCamera(camera));  // waits for the device when the eye moved
    renderer.recordFrame(cmd, api::toCamera(camera), target, frame);
    impl_->recorded[frame] = true;
}

std::vector<PenLayer> FrameRecorder::writeVector(const std::string& path, uint32_t frame, const Page& page) const {
    if (frame >= impl_->frames)
        throw Error("frame " + std::to_string(frame) + " is not one of the " + std::to_string(impl_->frames) +
                    " frames in flight");
    ink::PointRenderer& renderer = impl_->current();
    if (!impl_->recorded[frame])
        throw Error("FrameRecorder::writeVector: frame " + std::to_string(frame) +
                    " has recorded no frame of the drawing's points yet");
    return writeVectorDrawing(path, renderer.vectorDrawing(frame), page);
}

}  // namespace inkwell
