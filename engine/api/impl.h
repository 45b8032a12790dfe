// What the public objects (include/inkwell/inkwell.h) own, for the library's own code that works with them
// beside api.cpp (diagnostics.cpp): each Impl holds the engine object the public type names.
#pragma once

#include "inkwell/inkwell.h"

#include "base/common.h"
#include "draw/camera.h"
#include "draw/render_style.h"
#include "draw/scene.h"
#include "gpu/context.h"
#include "refine/refine_plan.h"
#include "surface/model.h"

#include <chrono>
#include <cmath>
#include <optional>

namespace inkwell {

struct Model::Impl {
    ink::Model model;
    std::optional<ink::UpAxis> convention;  // the file format's up axis (glTF: +y)
};

struct Device::Impl {
    ink::Context ctx;
    ~Impl() { ink::destroyContext(ctx); }
};

struct Drawing::Impl {
    ink::Scene scene;
    std::optional<ink::UpAxis> convention;  // the model file's up axis
    glm::vec3 tracedEye{NAN};               // where the contours on the device were traced from
    // Counts refine(), which replaces the sets: a renderer made before draws them again from new descriptors.
    uint64_t generation = 0;
    const uint64_t id;       // this drawing among all made in the process (an address may be reused)
    Reporter reporter;       // the last one given (the constructor's, refine's): the notes of later work go there
    DrawingOptions options;  // of the sets and lines in place
    Impl(ink::Context& ctx, std::shared_ptr<const ink::Model> model, const DrawingOptions& o);
    // The contours of the view from `camera`, traced again when the eye moved.
    void traceFor(const ink::Camera& camera) {
        if (!scene.lines.contours || camera.eye() == tracedEye) return;
        ink::ScopedReporter reporting(reporter);
        const auto start = std::chrono::steady_clock::now();
        scene.traceContours(camera);  // traced, trimmed, snapped to the feature lines and on the device
        traceSeconds = ink::secondsSince(start);
        tracedEye = camera.eye();
    }
    double traceSeconds = 0;  // the last traceFor's, wall clock
};

// The engine objects behind the public ones, for the library's code beside api.cpp.
struct Access {
    static ink::Context& context(Device& device) { return device.impl_->ctx; }
    static const ink::Model& model(const Model& model) { return model.impl_->model; }
    static ink::Scene& scene(const Drawing& drawing) { return drawing.impl_->scene; }
};

// The public values as the engine takes them, each checked against its range (ranges.h) first.
namespace api {
Eigen::Vector3d toEigen(const Vec3& v);
Vec3 toVec3(const Eigen::Vector3d& v);
ink::Camera toCamera(const Camera& c);
// The dots' silhouette threshold τ: with the contour drawn by the pen (`contours`: DrawingOptions::contours), the
// pen is the outline and the dots have no silhouette class (0); else Look::tau.
float dotsTau(const Look& look, bool contours);
// The renderer's style for a Look, its τ dotsTau's.
ink::RenderStyle toStyle(const Look& look, bool contours);
ink::RefineOptions toRefine(const DrawingOptions& o);
ink::LineOptions toLines(const DrawingOptions& o);
ink::DrawStyle toDrawStyle(Style s);
ink::ModelOptions toInk(const ModelOptions& o);
}  // namespace api

}  // namespace inkwell
