// bench: the report's workloads (ALGORITHM.md §7) timed end to end, side by side with the CPU reference.
#include "base/files.h"
#include "base/image.h"
#include "commands.h"
#include "select/select.h"
#include "surface/shapes.h"

#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>

namespace app {

namespace {

struct Workload {
    std::string name;
    std::string model;  // a path, "" for the sphere of six axis points, "torus-100k" for 10⁵ points on a torus
    size_t controlPoints;
    uint32_t levels;
    bool lines = false;  // pen lines: contours and hatching over the stipple set's depth, no dots (docs/lines.md)
    ink::FitMethod method = ink::FitMethod::PartitionOfUnity;
    // The contour traced and the hatching's cross field solved on the device (--contour-tracer device, --hatch-field
    // device), else on the CPU.
    bool linesOnDevice = false;
};

// The report's workloads (with the default fit), the bunny-684 one with the report's global fit for comparison,
// and 10⁵ oriented points (issue 15's fit budget). The default run leaves out torus-100k (ask for it by name).
const std::vector<Workload>& builtinWorkloads() {
    static const std::vector<Workload> w = {
        {"sphere", "", 6, 6},
        {"bunny-312", "bunny", 312, 4},
        {"bunny-684", "bunny", 684, 4},
        {"bunny-684-lines", "bunny", 684, 4, true},
        {"bunny-684-lines-device", "bunny", 684, 4, true, ink::FitMethod::PartitionOfUnity, true},
        {"bunny-lines", "bunny", 0, 4, true},
        {"bunny-lines-device", "bunny", 0, 4, true, ink::FitMethod::PartitionOfUnity, true},
        {"bunny-684-global", "bunny", 684, 4, false, ink::FitMethod::Global},
        {"torus-100k", "torus-100k", 0, 3}};
    return w;
}

// The bundled bunny, found beside the executable's source tree (build/inkwell → assets/bunny.obj) or from
// the working directory.
std::string bunnyPath() {
    std::error_code ec;
    std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    for (std::filesystem::path p :
         {exe.parent_path().parent_path() / "assets/bunny.obj", std::filesystem::path("assets/bunny.obj")})
        if (!ec && std::filesystem::exists(p)) return p.string();
    throw ink::Error("cannot find assets/bunny.obj: run bench from the repository root");
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

double peakMemoryMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

json runWorkload(Session& session, const Workload& w, ink::Distribution distribution, uint32_t frames,
                 bool screenSpacing) {
    auto start = Clock::now();
    ink::Model model = w.model.empty() ? ink::fitModel(ink::sphereAxisPoints(), {0, w.method})
                       : w.model == "torus-100k"
                           ? ink::fitModel(ink::torusPoints(500, 200), {0, w.method})
                           : ink::loadModel(w.model == "bunny" ? bunnyPath() : w.model, {w.controlPoints, w.method});
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
        ink::Scene scene(session.ctx, std::move(model), ink::DrawStyle::Stipple, options, lines);
        const double sceneSeconds = secondsSince(start) - loadSeconds;
        const ink::Model& fitted = scene.model;
        ink::GpuRefinement& r = scene.sets.front()->gpu();
        double refineSeconds = scene.refineSeconds;
        auto levels = ink::readLevelStats(session.ctx, r);

        ink::RenderStyle style;
        style.supersample = 1;
        style.drawDots = !w.lines;
        style.screenSpacing = screenSpacing;
        ink::Camera first;
        first.azimuthDeg = 30.0f;
        scene.traceContours(first);  // the first view's contour: part of the preprocessing
        double contourSeconds = scene.contourStats.seconds;
        const double beforeRenderer = secondsSince(start);
        ink::OffscreenRenderer renderer(session.ctx, 1024, 1024, style, scene.pointers(), scene.strokes.get());
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
            for (uint32_t added : ink::readStageCounts(session.ctx, *r.selection)) stipples += added;

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
               {"select_ms", ink::selectionMs(session.ctx, r)},
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
        out.update(deviceJson(session.ctx));
    }
    return out;
}

// Each number of the runs' results, the objects' in them too (preprocess_ms, refine_host_ms, ...), as its median
// over the runs; the rest as the first run had it.
json medianOf(const std::vector<json>& runs) {
    json m = runs.front();
    for (auto& [key, value] : m.items()) {
        if (value.is_number_float()) {
            std::vector<double> v;
            for (const auto& r : runs) v.push_back(r[key].get<double>());
            value = median(v);
        } else if (value.is_object()) {
            std::vector<json> inner;
            for (const auto& r : runs) inner.push_back(r[key]);
            value = medianOf(inner);
            value.erase("repeats");
        }
    }
    m["repeats"] = runs.size();
    return m;
}

int runBench(Options& o, const std::vector<std::string>& names, const std::string& jsonPath, uint32_t repeat,
             uint32_t frames, bool screenSpacing) {
    finishOptions(o);
    std::vector<Workload> workloads;
    for (const std::string& name : names) {
        auto it = std::find_if(builtinWorkloads().begin(), builtinWorkloads().end(),
                               [&](const Workload& w) { return w.name == name; });
        if (it == builtinWorkloads().end()) {
            std::string known;
            for (const Workload& w : builtinWorkloads()) known += (known.empty() ? "" : ", ") + w.name;
            throw ink::Error("unknown workload '" + name + "': use one of " + known);
        }
        workloads.push_back(*it);
    }
    if (!o.model.empty())
        workloads.push_back({std::filesystem::path(o.model).filename().string(), o.model, o.controlPoints,
                             o.refine.levels, false, modelOptions(o).method});
    if (workloads.empty())
        for (const Workload& w : builtinWorkloads())
            if (w.name != "torus-100k") workloads.push_back(w);
    if (repeat < 1 || repeat > 100) throw ink::Error("--repeat must be between 1 and 100");
    if (frames < 1 || frames > 10000) throw ink::Error("--frames must be between 1 and 10000");
    ink::checkOutputs({jsonPath}, {o.model});  // never over the model it times

    auto deviceStart = Clock::now();
    Session session(o);
    double deviceSeconds = secondsSince(deviceStart);
    json results = json::array();
    for (const Workload& w : workloads) {
        std::vector<json> runs;
        for (uint32_t i = 0; i < repeat; ++i)
            runs.push_back(runWorkload(session, w, o.refine.distribution, frames, screenSpacing));
        json m = medianOf(runs);
        m["device_seconds"] = deviceSeconds;
        m["screen_spacing"] = screenSpacing;  // creating the Vulkan device, once per process, not in preprocess
        std::printf(
            "%-16s %8llu points %7llu stipples  fit %6.3f s  refine %6.3f s (select %5.0f ms; cpu refine %6.3f s, "
            "%.2fx)  preprocess %6.3f s  frame %7.2f ms (%5.1f fps)\n",
            w.name.c_str(), (unsigned long long)m["points"].get<uint64_t>(),
            (unsigned long long)m["stipples"].get<uint64_t>(), m["fit_seconds"].get<double>(),
            m["refine_seconds"].get<double>(), m["select_ms"].get<double>(), m["cpu_refine_seconds"].get<double>(),
            m["gpu_over_cpu_refine"].get<double>(), m["preprocess_seconds"].get<double>(),
            m["frame_ms_median"].get<double>(), m["fps"].get<double>());
        if (m.contains("hatch_seconds"))
            std::printf(
                "%-10s hatching %6.3f s (%llu strokes; field %.3f s on the %s)  contours %6.3f s first view, "
                "%6.1f ms a view\n",
                "", m["hatch_seconds"].get<double>(), (unsigned long long)m["hatch_strokes"].get<uint64_t>(),
                m["hatch_field_seconds"].get<double>(), m["hatch_field_on"].get<std::string>().c_str(),
                m["contour_seconds_first_view"].get<double>(), m["contour_trace_ms_median"].get<double>());
        results.push_back(m);
    }
    session.checkValidation();
    writeJson(jsonPath, results.size() == 1 ? results[0] : results);
    return 0;
}

}  // namespace

void addBenchCommand(CLI::App& cli, Options& o, Commands& commands) {
    auto names = std::make_shared<std::vector<std::string>>();
    auto jsonPath = std::make_shared<std::string>();
    auto repeat = std::make_shared<uint32_t>(3);
    auto frames = std::make_shared<uint32_t>(30);
    auto screenSpacing = std::make_shared<bool>(true);
    CLI::App* bench = cli.add_subcommand("bench", "Time the report's workloads (preprocessing, frames, CPU reference)");
    bench->add_option("--workload", *names,
                      "sphere, bunny-312, bunny-684, bunny-684-lines, bunny-684-lines-device, bunny-lines, "
                      "bunny-lines-device, bunny-684-global, torus-100k (default: all but torus-100k; -device: the "
                      "contour traced and the hatching's cross field solved on the device)");
    bench->add_option("--model", o.model, "Also time this model (with --control-points and --levels)");
    bench->add_option("--control-points", o.controlPoints, "Control points for --model (default: as fit)")
        ->check(nonNegativeInteger());
    bench->add_option("--fit", o.fit, "Fit for --model: pu or global")
        ->check(CLI::IsMember({"pu", "global"}))
        ->capture_default_str();
    bench->add_option("--levels", o.refine.levels, "Levels for --model")
        ->check(nonNegativeInteger())
        ->capture_default_str();
    bench->add_option("--json", *jsonPath, "Write the results as JSON");
    bench->add_option("--repeat", *repeat, "Runs per workload; numbers are medians")->capture_default_str();
    bench->add_option("--frames", *frames, "Frames timed per run")->capture_default_str();
    bench
        ->add_option("--distribution", o.distribution,
                     "What is drawn: blue-noise stipples selected from the refined points, or every refined point "
                     "(the report's look and workload)")
        ->check(CLI::IsMember({"blue-noise", "refinement"}))
        ->capture_default_str();
    bench->add_flag("--screen-spacing,!--no-screen-spacing", *screenSpacing,
                    "Space the stipples on the page every frame, as render does (on by default; its cost: "
                    "frame_passes_ms_median.space)");
    addDeviceOptions(bench, o);
    commands.emplace_back(bench, [&o, names, jsonPath, repeat, frames, screenSpacing] {
        return runBench(o, *names, *jsonPath, *repeat, *frames, *screenSpacing);
    });
}

}  // namespace app
