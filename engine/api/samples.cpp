// inkwell::Samples (include/inkwell/inkwell.h): a model's refined points read back, from the device or the CPU
// reference, with the refinement's and the selection's figures.
#include "api/impl.h"
#include "api/stats_json.h"
#include "base/common.h"
#include "io/export.h"
#include "refine/refine.h"
#include "select/select.h"

#include <chrono>

namespace inkwell {

namespace {

// The selection's figures, alike from both backends.
api::json selectJson(const ink::SelectPlan& plan, size_t candidates, const std::vector<uint32_t>& added) {
    return {{"candidates", candidates},
            {"radius", plan.radius0},
            {"area_estimate", plan.areaEstimate},
            {"stage_added", added}};
}

}  // namespace

struct Samples::Impl {
    std::vector<ink::PointRecord> points, refined;
    bool keptRefined = false;
    ink::Frame frame;
    api::json stats;
};

Samples::Samples(Device* device, const Model& model, const DrawingOptions& options, bool keepRefined,
                 const Reporter& reporter)
    : impl_(std::make_unique<Impl>()) {
    ink::ScopedReporter reporting(reporter);
    if (options.style == Style::Both) throw Error("Samples make one set: a style of Stipple or Direction");
    ink::RefineOptions refine = api::toRefine(options);
    refine.style = options.style == Style::Direction ? ink::SampleStyle::Direction : ink::SampleStyle::Stipple;
    const ink::Surface& surface = Access::model(model).surface;
    impl_->frame = surface.frame;
    api::json& stats = impl_->stats;
    std::vector<ink::LevelStats> levels;
    using Clock = std::chrono::steady_clock;
    if (!device) {
        auto start = Clock::now();
        ink::RefinePlan plan = ink::planRefinement(surface, refine, ink::kMaxCpuPoints);
        impl_->points = ink::refineOnCpu(surface, refine, plan, &levels);
        stats["refine"]["seconds"] = ink::secondsSince(start);
        if (keepRefined) impl_->refined = impl_->points;
        impl_->keptRefined = keepRefined;
        if (refine.selects()) {
            start = Clock::now();
            ink::SelectPlan selectPlan = ink::planSelection(surface, plan, ink::selectOptions(refine));
            std::vector<uint32_t> added;
            const size_t candidates = impl_->points.size();
            impl_->points = ink::selectOnCpu(impl_->points, selectPlan, &added);
            stats["select"] = selectJson(selectPlan, candidates, added);
            stats["select"]["seconds"] = ink::secondsSince(start);
        }
        stats["device"] = "cpu";
        stats["refine"]["levels"] = api::levelsJson(levels);
        return;
    }
    ink::Context& ctx = Access::context(*device);
    ink::Refinement refinement(ctx, surface, refine);
    ink::GpuRefinement& r = refinement.gpu();
    auto start = Clock::now();
    ink::runRefinement(ctx, r);
    stats["refine"]["seconds"] = ink::secondsSince(start);
    levels = ink::readLevelStats(ctx, r);
    if (r.selection) {
        stats["select"] =
            selectJson(r.selection->plan, ink::readPointCount(ctx, r), ink::readStageCounts(ctx, *r.selection));
        stats["select"]["gpu_ms"] = ink::selectionMs(ctx, r);
    }
    impl_->points = ink::readDrawnPoints(ctx, r);
    if (keepRefined) impl_->refined = r.selection ? ink::readPoints(ctx, r) : impl_->points;
    impl_->keptRefined = keepRefined;
    stats["refine"]["levels"] = api::levelsJson(levels);
    stats.update(api::deviceJson(ctx));
}

Samples::~Samples() = default;
Samples::Samples(Samples&&) noexcept = default;
Samples& Samples::operator=(Samples&&) noexcept = default;

size_t Samples::size() const { return impl_->points.size(); }

std::vector<Point> Samples::points() const {
    std::vector<Point> out;
    out.reserve(impl_->points.size());
    for (const ink::PointRecord& p : impl_->points) {
        const Eigen::Vector3d x = impl_->frame.toInput(Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
        out.push_back({{x.x(), x.y(), x.z()}, {p.normal[0], p.normal[1], p.normal[2]}, p.tone, p.level});
    }
    return out;
}

std::vector<Vec3> Samples::refined() const {
    if (!impl_->keptRefined) throw Error("Samples::refined: made without keepRefined");
    std::vector<Vec3> out;
    out.reserve(impl_->refined.size());
    for (const ink::PointRecord& p : impl_->refined) {
        const Eigen::Vector3d x = impl_->frame.toInput(Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
        out.push_back({x.x(), x.y(), x.z()});
    }
    return out;
}

void Samples::writePly(const std::string& path) const { ink::writePointsPly(path, impl_->points, impl_->frame); }

std::string Samples::statsJson(bool spacing) const {
    api::json stats = impl_->stats;
    stats["refine"]["points"] = impl_->points.size();
    if (spacing) stats["spacing"] = api::spacingJson(impl_->points);
    return stats.dump();
}

}  // namespace inkwell
