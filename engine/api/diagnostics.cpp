// The library's self-check and benchmarks (include/inkwell/diagnostics.h): white box, on the engine's objects.
#include "inkwell/diagnostics.h"

#include "api/impl.h"
#include "api/stats_json.h"
#include "base/common.h"
#include "draw/renderer.h"
#include "lines/contour_device.h"
#include "refine/refine.h"
#include "select/select.h"
#include "surface/shapes.h"

#include <sys/resource.h>
#include <algorithm>
#include <chrono>

namespace inkwell {

namespace {

using Clock = std::chrono::steady_clock;
using namespace api;  // the stats as JSON
using ink::secondsSince;

void require(SelfCheck& check, bool ok, const std::string& what) {
    if (!ok) check.failures.push_back(what);
}

void checkScene(ink::Context& ctx, const std::string& name, const ink::Model& model, SelfCheck& check) {
    for (ink::SampleStyle style : {ink::SampleStyle::Stipple, ink::SampleStyle::Direction}) {
        ink::RefineOptions options;
        options.style = style;
        options.levels = 3;
        std::string label = name + (style == ink::SampleStyle::Stipple ? " stipple" : " direction");
        {
            ink::Refinement refinement(ctx, model.surface, options);
            ink::GpuRefinement& r = refinement.gpu();
            ink::runRefinement(ctx, r);
            auto points = ink::readPoints(ctx, r);
            auto levels = ink::readLevelStats(ctx, r);
            uint64_t kept = 0;
            for (const auto& l : levels) {
                kept += l.kept;
                uint64_t accounted = l.kept;
                for (uint32_t d : l.dropped) accounted += d;
                require(check, accounted == l.candidates,
                        label + ": level " + std::to_string(l.level) + " loses candidates (" +
                            std::to_string(accounted) + " of " + std::to_string(l.candidates) + ")");
            }
            require(check, kept == points.size(), label + ": drawn points differ from the kept count");
            require(check, levels.back().kept > levels.front().kept, label + ": the last level added no points");
            size_t off = 0;
            for (const auto& p : points) {
                Eigen::Vector3d x(p.position[0], p.position[1], p.position[2]), g;
                double f = model.surface.eval(x, g);
                if (!(std::abs(f) / g.norm() < 2.0 * options.eps1)) ++off;
            }
            require(check, off == 0, label + ": " + std::to_string(off) + " points off the surface");
            check.points += points.size();
            if (r.selection) {
                // The stipples: a subset of the points, each ranked in [0, 1).
                auto stipples = ink::readDrawnPoints(ctx, r);
                size_t badRanks = 0;
                for (const auto& p : stipples) badRanks += !(p.tone >= 0.0f && p.tone < 1.0f);
                require(check, !stipples.empty() && stipples.size() < points.size(),
                        label + ": " + std::to_string(stipples.size()) + " stipples selected from " +
                            std::to_string(points.size()) + " points");
                require(check, badRanks == 0,
                        label + ": " + std::to_string(badRanks) + " stipples ranked outside [0, 1)");
            }

            // The contour traced on the device from the default view: every vertex on both of its equations.
            if (style == ink::SampleStyle::Stipple && ink::DeviceContours::supports(r)) {
                const glm::vec3 e = ink::Camera{}.eye();
                const Eigen::Vector3d eye(e.x, e.y, e.z);
                ink::DeviceContours tracer(ctx, r, uint32_t(ink::readDrawnPoints(ctx, r).size()), {});
                ink::ContourStats stats;
                const auto pieces = tracer.trace(model.surface, eye, &stats);
                size_t offContour = 0;
                for (const ink::PenStroke& s : pieces)
                    for (const Eigen::Vector3f& p : s.points) {
                        Eigen::Vector3d x = p.cast<double>(), g;
                        const double f = model.surface.eval(x, g);
                        offContour += !(std::abs(f) / g.norm() < 1e-4 &&
                                        std::abs(g.normalized().dot((x - eye).normalized())) < 1e-2);
                    }
                require(check, !pieces.empty(), label + ": the device traced no contour");
                require(check, offContour == 0,
                        label + ": " + std::to_string(offContour) + " vertices of the device's contour off it");
            }

            ink::RgbaImage image;
            {
                ink::RenderStyle renderStyle;
                renderStyle.hiddenLines = true;
                ink::OffscreenRenderer renderer(ctx, 256, 256, renderStyle, {&r});
                image = renderer.render(ink::Camera{});
            }
            size_t dark = 0;
            for (size_t i = 0; i < image.pixels.size(); i += 4) dark += image.pixels[i] < 128;
            require(check, dark > 300, label + ": the image is blank (" + std::to_string(dark) + " dark pixels)");
            require(check, image.pixels[0] == 255, label + ": the image corner is not paper");
        }
    }
}

}  // namespace

std::vector<SelfCheck> selfCheck(Device& device, const std::string& model, const ModelOptions& options,
                                 const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    struct Source {
        std::string name;
        ink::Model model;
    };
    std::vector<Source> sources;
    sources.push_back({"sphere", ink::fitModel(ink::spherePoints(64), {})});
    sources.push_back({"torus", ink::fitModel(ink::torusPoints(24, 12), {})});
    if (!model.empty()) sources.push_back({model, ink::loadModel(model, api::toInk(options))});
    std::vector<SelfCheck> checks;
    for (const Source& s : sources) {
        SelfCheck check{s.name, 0, {}};
        checkScene(Access::context(device), s.name, s.model, check);
        checks.push_back(std::move(check));
    }
    return checks;
}

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

double peakMemoryMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

}  // namespace

std::string bench(Device& device, const BenchWorkload& w, const BenchOptions& o, const Reporter& reporter) {
    ink::ScopedReporter reporting(reporter);
    if (o.frames < 1 || o.frames > 10000) throw Error("frames must be between 1 and 10000");
    ink::Context& ctx = Access::context(device);
    const ink::Distribution distribution =
        o.distribution == Distribution::BlueNoise ? ink::Distribution::BlueNoise : ink::Distribution::Refinement;
    const uint32_t frames = o.frames;
    const bool screenSpacing = o.screenSpacing;
    const ink::FitMethod method =
        w.method == FitMethod::Global ? ink::FitMethod::Global : ink::FitMethod::PartitionOfUnity;
    auto start = Clock::now();
    ink::Model model = w.source == BenchWorkload::Source::Sphere ? ink::fitModel(ink::sphereAxisPoints(), {0, method})
                       : w.source == BenchWorkload::Source::Torus100k
                           ? ink::fitModel(ink::torusPoints(500, 200), {0, method})
                           : ink::loadModel(w.model, {w.controlPoints, method});
    ink::RefineOptions options;
    options.levels = w.levels;
    options.distribution = distribution;  // the passes follow it: 1 for blue-noise stipples, the report's 2 else
    ink::LineOptions lines;
    lines.contours = lines.hatching = w.lines;
    lines.contourTracer =
        w.linesOnDevice ? ink::LineOptions::ContourTracer::Device : ink::LineOptions::ContourTracer::Cpu;
    lines.fieldSolver = w.linesOnDevice ? ink::LineOptions::FieldSolver::Device : ink::LineOptions::FieldSolver::Cpu;
    const double loadSeconds = secondsSince(start);
    json out;
    {
        ink::Scene scene(ctx, std::move(model), ink::DrawStyle::Stipple, options, lines);
        const double sceneSeconds = secondsSince(start) - loadSeconds;
        const ink::Model& fitted = scene.model;
        ink::GpuRefinement& r = scene.sets.front()->gpu();
        double refineSeconds = scene.refineSeconds;
        auto levels = ink::readLevelStats(ctx, r);

        ink::RenderStyle style;
        style.supersample = 1;
        style.drawDots = !w.lines;
        style.screenSpacing = screenSpacing;
        ink::Camera first;
        first.azimuthDeg = 30.0f;
        scene.traceContours(first);  // the first view's contour: part of the preprocessing
        double contourSeconds = scene.contourStats.seconds;
        const double beforeRenderer = secondsSince(start);
        ink::OffscreenRenderer renderer(ctx, 1024, 1024, style, scene.pointers(), scene.strokes.get());
        double preprocess = secondsSince(start);
        // Where the preprocessing goes, in milliseconds: loading and fitting, the scene (the refinement, its
        // selection and the lines), the first view's contour, the renderer (its images and pipelines); and of the
        // refinement, the host's part (GpuRefinement::HostMs).
        json preprocessMs = {{"load_fit", 1e3 * loadSeconds},
                             {"scene", 1e3 * sceneSeconds},
                             {"first_contour", 1e3 * (beforeRenderer - loadSeconds - sceneSeconds)},
                             {"renderer", 1e3 * (preprocess - beforeRenderer)}};

        // Frames with the camera moving every frame; the first few warm caches and pipelines up.
        std::vector<double> frameMs, splatMs, spaceMs, stampMs, inkMs, traceMs, traceDeviceMs;
        uint32_t dots = 0;  // drawn in the first timed frame
        ink::Camera camera;
        for (uint32_t i = 0; i < frames + 3; ++i) {
            camera.azimuthDeg = 30.0f + 360.0f * float(i) / float(frames + 3);
            // The contour of this view, traced and timed apart from the frame (a viewer traces it once the eye
            // stops).
            if (w.lines) {
                auto traceStart = Clock::now();
                scene.traceContours(camera);
                if (i >= 3) traceMs.push_back(1000.0 * secondsSince(traceStart));
                if (i >= 3) traceDeviceMs.push_back(scene.contourStats.deviceMs);
            }
            auto t = Clock::now();
            renderer.draw(camera);
            if (i < 3) continue;
            frameMs.push_back(1000.0 * secondsSince(t));
            ink::PointRenderer::Timings passes = renderer.timings();
            splatMs.push_back(passes.splatMs);
            spaceMs.push_back(passes.spaceMs);
            stampMs.push_back(passes.stampMs);
            inkMs.push_back(passes.inkMs);
            if (i == 3) dots = renderer.drawnDots();
        }

        // The stipples on the page, from the first camera (not timed).
        renderer.render(first);
        const json page = pageJson(renderer, scene.pointers().size(), style, 1024, 1024);

        auto cpuStart = Clock::now();
        ink::refineOnCpu(fitted.surface, options, r.plan);
        double cpuRefine = secondsSince(cpuStart);
        uint64_t stipples = 0;
        if (r.selection)
            for (uint32_t added : ink::readStageCounts(ctx, *r.selection)) stipples += added;

        uint64_t candidates = 0, points = 0;
        json levelMs = json::array();
        for (const auto& l : levels) {
            candidates += l.candidates;
            points += l.kept;
            levelMs.push_back(l.gpuMs);
        }
        out = {{"workload", w.name},
               {"control_points", fitted.fit.controlPoints},
               {"levels", w.levels},
               {"candidates", candidates},
               {"points", points},
               {"distribution", distribution == ink::Distribution::BlueNoise ? "blue-noise" : "refinement"},
               {"stipples", stipples},
               {"select_ms", ink::selectionMs(ctx, r)},
               {"fit_seconds", fitted.fit.seconds},
               {"fit", fitJson(fitted)},
               {"refine_seconds", refineSeconds},
               {"preprocess_seconds", preprocess},
               {"preprocess_ms", preprocessMs},
               {"refine_host_ms", hostMsJson(r.hostMs)},
               {"frame_ms_median", median(frameMs)},
               {"frame_passes_ms_median",
                {{"splat", median(splatMs)},
                 {"space", median(spaceMs)},
                 {"stamp", median(stampMs)},
                 {"ink", median(inkMs)}}},
               {"fps", 1000.0 / median(frameMs)},
               {"dots_drawn_first_frame", dots},
               {"page", page},
               {"cpu_refine_seconds", cpuRefine},
               {"gpu_over_cpu_refine", cpuRefine / refineSeconds},
               {"level_gpu_ms", levelMs},
               {"peak_memory_mb", peakMemoryMb()}};
        if (w.lines)
            out.update({{"hatch_seconds", scene.hatchSeconds},
                        {"hatch_strokes", scene.hatching.size()},
                        {"hatch_vertices", scene.hatchStats.vertices},
                        {"hatch_field_seconds", scene.hatchStats.fieldSeconds},
                        {"hatch_field_on", scene.hatchStats.fieldOnDevice ? "device" : "cpu"},
                        {"hatch_field_device_ms", scene.hatchStats.fieldDeviceMs},
                        {"contour_seconds_first_view", contourSeconds},
                        {"contour_trace_ms_median", median(traceMs)},
                        {"contour_traced_on", scene.contourStats.onDevice ? "device" : "cpu"},
                        {"contour_device_ms_median", median(traceDeviceMs)},
                        {"contour_cusps", scene.contourStats.cusps},
                        {"contour_vertices", scene.contourStats.vertices},
                        {"frame_with_trace_ms_median", median(frameMs) + median(traceMs)}});
        out.update(deviceJson(ctx));
    }
    return out.dump();
}

}  // namespace inkwell
