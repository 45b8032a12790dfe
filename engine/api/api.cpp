// The public API (include/inkwell/inkwell.h) over the engine: each public object owns the engine object it
// names, and long calls install the caller's Reporter for their duration. Here the conversions of the public
// values, Model, measureFidelity and Device; drawing.cpp has Drawing, rendering.cpp the rest.
#include "api/impl.h"
#include "inkwell/ranges.h"

#include "api/stats_json.h"
#include "base/common.h"
#include "base/files.h"
#include "base/image.h"
#include "draw/renderer.h"
#include "draw/scene.h"
#include "gpu/context.h"
#include "io/export.h"
#include "io/hrbf_io.h"
#include "select/select.h"
#include "surface/fidelity.h"
#include "surface/model.h"
#include "surface/surface_sampling.h"
#include "surface/viewpoint.h"
#include "vector/vector.h"

#include <algorithm>
#include <chrono>
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

float dotsTau(const Look& look, bool contours) {
    // The silhouette class's band |n·v| < τ widens where the view runs along a surface that curves little across
    // it (τ²/2κ_r on the screen: a cylinder seen obliquely), and its strokes beside the pen's line drew a second,
    // heavier outline there: filled wedges along CGAL's dragknob, 13 pixels thick at the widest.
    return contours ? 0.0f : look.tau;
}

ink::RenderStyle toStyle(const Look& look, bool contours) {
    checkLook(look);
    ink::RenderStyle s;
    s.ink = {look.ink[0], look.ink[1], look.ink[2], look.ink[3]};
    s.paper = {look.paper[0], look.paper[1], look.paper[2], look.paper[3]};
    s.hiddenInk = glm::vec4(glm::vec3(s.ink), look.hiddenOpacity);
    s.hiddenSize = look.hiddenDotSize;
    s.frontSize = look.dotSize;
    s.silhouetteSize = look.silhouetteSize;
    s.tau = dotsTau(look, contours);
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
    s.occlusion = look.occlusion;
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
    if (!ranges::passes.contains(o.passes) && o.passes != 0) throw Error("passes must be 0 (automatic) or 1 to 64");
    r.passes = o.passes;
    if (!ink::validRho(o.rho))
        throw Error("rho must be in (0, 1]: a fraction of the bounding-box diagonal (above 1 every child is dropped)");
    r.rho0 = o.rho;
    if (o.rhoDivisor != 0 && !(o.rhoDivisor >= 1.5 && o.rhoDivisor <= 4.0))
        throw Error("rhoDivisor must be 0 (automatic) or in [1.5, 4]");
    r.rhoDivisor = o.rhoDivisor;
    r.seeds = o.gridSeeds ? ink::SeedMode::Grid : ink::SeedMode::ControlPoints;
    if (o.grid < 2 || o.grid > 512) throw Error("grid " + std::to_string(o.grid) + " must be between 2 and 512 cells");
    r.grid = o.grid;
    r.keepAllLevels = o.keepAllLevels;
    r.direction = o.direction == DirectionField::Axis           ? ink::DirectionField::Axis
                  : o.direction == DirectionField::CurvatureMin ? ink::DirectionField::CurvatureMin
                                                                : ink::DirectionField::CurvatureMax;
    const Eigen::Vector3d axis = toEigen(o.axis);
    if (!(axis.norm() > 0) || !axis.allFinite()) throw Error("axis must be a finite, non-zero vector");
    r.axis = axis;
    return r;
}

ink::DrawStyle toDrawStyle(Style s) {
    return s == Style::Stipple     ? ink::DrawStyle::Stipple
           : s == Style::Direction ? ink::DrawStyle::Direction
                                   : ink::DrawStyle::Both;
}

static_assert(int(Up::NegZ) == int(ink::UpAxis::NegZ) && int(Up::Y) == int(ink::UpAxis::PosY));
static_assert(int(Where::Device) == int(ink::LineOptions::ContourTracer::Device) &&
              int(Where::Cpu) == int(ink::LineOptions::FieldSolver::Cpu));
static_assert(ranges::penWidthMm.lo == ink::kMinPenWidth && ranges::penWidthMm.hi == ink::kMaxPenWidth);
static_assert(ranges::levels.hi == ink::kMaxLevels - 1, "ranges.h: levels follow the device's MAX_LEVELS");

}  // namespace api

using api::toEigen;
using api::toVec3;

// ---- Model

ink::ModelOptions api::toInk(const ModelOptions& o) {
    return {o.controlPoints,  o.method == FitMethod::Global ? ink::FitMethod::Global : ink::FitMethod::PartitionOfUnity,
            o.creaseAngleDeg, o.trim,
            o.removeOutliers, o.smoothNoise,
            o.features,       o.support};
}

void checkModelOptions(const ModelOptions& options) { ink::checkModelOptions(api::toInk(options)); }

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

void Model::save(const std::string& path, HrbfFormat format) const {
    ink::saveHrbf(path, impl_->model.surface,
                  format == HrbfFormat::Text ? ink::HrbfFormat::Text : ink::HrbfFormat::Binary);
}

FitReport Model::report() const {
    const ink::Model& m = impl_->model;
    FitReport r;
    r.inputPoints = m.inputPoints;
    r.mergedDuplicates = m.mergedDuplicates;
    r.flippedNormals = m.flippedNormals;
    r.estimatedNormals = m.estimatedNormals;
    r.twoSided = m.twoSided;
    r.controlPoints = m.fit.controlPoints;
    r.seconds = m.fit.seconds;
    r.maxDistance = m.fit.maxDistance;
    r.maxNormalAngleDeg = m.fit.maxNormalAngleDeg;
    r.inputMaxDistance = m.inputMaxDistance;
    r.inputMaxAngleDeg = m.inputMaxAngleDeg;
    r.patches = m.patches.patches;
    r.faceSamples = m.faceSamples;
    r.loadSeconds = m.loadSeconds;
    return r;
}

std::string Model::statsJson() const { return api::fitJson(impl_->model).dump(); }

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

struct FidelityMesh::Impl {
    ink::OrientedPoints mesh;
};

namespace {

void checkFidelityOptions(double tolerance, double creaseAngleDeg) {
    if (!(tolerance > 0)) throw Error("the fidelity tolerance must be positive (it is in bounding-box diagonals)");
    if (!(creaseAngleDeg > 0 && creaseAngleDeg < 180)) throw Error("the crease angle must be in (0, 180) degrees");
}

}  // namespace

FidelityMesh::FidelityMesh(const std::string& meshPath, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    ink::OrientedPoints mesh = ink::loadPoints(meshPath);
    double area = 0;
    for (double a : ink::triangleAreas(mesh)) area += a;
    if (!(area > 0)) throw Error(meshPath + ": fidelity needs a mesh with faces; this file has none with area");
    impl_ = std::make_shared<const Impl>(Impl{std::move(mesh)});
}

Fidelity measureFidelity(const std::string& meshPath, const std::vector<Vec3>& points, double tolerance,
                         const Reporter& reporter, double creaseAngleDeg) {
    checkFidelityOptions(tolerance, creaseAngleDeg);  // before the mesh is read
    return FidelityMesh(meshPath, reporter).measure(points, tolerance, reporter, creaseAngleDeg);
}

Fidelity FidelityMesh::measure(const std::vector<Vec3>& points, double tolerance, const Reporter& reporter,
                               double creaseAngleDeg) const {
    ink::ScopedReporter reporting(reporter);
    checkFidelityOptions(tolerance, creaseAngleDeg);
    std::vector<Eigen::Vector3d> at;
    at.reserve(points.size());
    for (const Vec3& p : points) at.push_back(toEigen(p));
    ink::Fidelity f = ink::measureFidelity(impl_->mesh, at, tolerance, 0, creaseAngleDeg);
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
std::vector<std::string> Device::list() { return ink::listDevices(); }
AdoptedDevice Device::handles() const {
    const ink::Context& c = impl_->ctx;
    return {c.instance, c.physicalDevice, c.device, c.queue, c.queueFamily, c.float64, c.bufferDeviceAddress};
}
void Device::checkImageSize(uint32_t width, uint32_t height, uint32_t supersample) const {
    if (!ranges::supersample.contains(supersample)) throw Error("supersample must be 1 to 4");
    ink::checkOffscreenSize(impl_->ctx, width, height, supersample);
}

}  // namespace inkwell
