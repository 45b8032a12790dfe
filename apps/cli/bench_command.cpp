// bench: the report's workloads (ALGORITHM.md §7) timed end to end, side by side with the CPU reference.
#include "commands.h"
#include "inkwell/diagnostics.h"
#include "inkwell/files.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>

namespace app {

namespace {

using Workload = inkwell::BenchWorkload;
using Source = inkwell::BenchWorkload::Source;
constexpr auto kPu = inkwell::FitMethod::PartitionOfUnity;

// The report's workloads (with the default fit), the bunny-684 one with the report's global fit for comparison,
// and 10⁵ oriented points (issue 15's fit budget). The default run leaves out torus-100k (ask for it by name).
const std::vector<Workload>& builtinWorkloads() {
    static const std::vector<Workload> w = {{"sphere", Source::Sphere, "", 6, 6},
                                            {"bunny-312", Source::File, "", 312, 4},
                                            {"bunny-684", Source::File, "", 684, 4},
                                            {"bunny-684-lines", Source::File, "", 684, 4, kPu, true},
                                            {"bunny-684-lines-device", Source::File, "", 684, 4, kPu, true, true},
                                            {"bunny-lines", Source::File, "", 0, 4, kPu, true},
                                            {"bunny-lines-device", Source::File, "", 0, 4, kPu, true, true},
                                            {"bunny-684-global", Source::File, "", 684, 4, inkwell::FitMethod::Global},
                                            {"torus-100k", Source::Torus100k, "", 0, 3}};
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
    throw inkwell::Error("cannot find assets/bunny.obj: run bench from the repository root");
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
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
            throw inkwell::Error("unknown workload '" + name + "': use one of " + known);
        }
        workloads.push_back(*it);
    }
    if (!o.model.empty())
        workloads.push_back({std::filesystem::path(o.model).filename().string(), Source::File, o.model, o.controlPoints,
                             o.drawing.levels, o.fit == "global" ? inkwell::FitMethod::Global : kPu});
    if (workloads.empty())
        for (const Workload& w : builtinWorkloads())
            if (w.name != "torus-100k") workloads.push_back(w);
    if (repeat < 1 || repeat > 100) throw inkwell::Error("--repeat must be between 1 and 100");
    if (frames < 1 || frames > 10000) throw inkwell::Error("--frames must be between 1 and 10000");
    inkwell::checkOutputs({jsonPath}, {o.model});  // never over the model it times

    auto deviceStart = Clock::now();
    inkwell::Device device = openDevice(o, o.validation);
    double deviceSeconds = secondsSince(deviceStart);
    inkwell::BenchOptions options;
    options.frames = frames;
    options.distribution =
        o.distribution == "refinement" ? inkwell::Distribution::Refinement : inkwell::Distribution::BlueNoise;
    options.screenSpacing = screenSpacing;
    json results = json::array();
    for (Workload& w : workloads) {
        if (w.source == Source::File && w.model.empty()) w.model = bunnyPath();
        std::vector<json> runs;
        for (uint32_t i = 0; i < repeat; ++i)
            runs.push_back(json::parse(inkwell::bench(device, w, options, reporter())));
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
    checkValidation(device);
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
    bench->add_option("--levels", o.drawing.levels, "Levels for --model")
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
