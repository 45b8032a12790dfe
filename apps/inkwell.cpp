// inkwell: pen-and-ink drawings of HRBF implicit surfaces. Argument parsing and the top-level flow only;
// the work is in engine/.
#include "common.h"
#include "context.h"
#include "export.h"
#include "image.h"
#include "model.h"
#include "refine.h"
#include "renderer.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Options {
    std::string model;
    size_t controlPoints = 0;
    std::string device;
    bool validation = false;
    std::string statsPath;
    ink::RefineOptions refine;
    std::string backend = "gpu";
    std::string keepLevels = "all";
    std::vector<double> axis;
};

void addModelOptions(CLI::App* cmd, Options& o) {
    cmd->add_option("model", o.model, "Mesh or oriented points (.obj, .ply, .pts/.xyzn/.txt)")->required();
    cmd->add_option("--control-points", o.controlPoints,
                    "Control points chosen by farthest-point sampling (default: all, at most 1000)");
    cmd->add_option("--stats", o.statsPath, "Write statistics as JSON to this file");
}

void addDeviceOptions(CLI::App* cmd, Options& o) {
    cmd->add_option("--device", o.device, "Vulkan device: an index or part of its name (default: a GPU, else lavapipe)");
    cmd->add_flag("--validation", o.validation, "Enable Vulkan validation and synchronization validation");
}

void addRefineOptions(CLI::App* cmd, Options& o) {
    ink::RefineOptions& r = o.refine;
    cmd->add_option("--levels", r.levels, "Refinement levels after the seeds")->capture_default_str();
    cmd->add_option("--passes", r.passes, "Independent refinement passes")->capture_default_str();
    cmd->add_option("--style", r.style, "Sampling: stipple (4 children) or direction (2, along a field)")
        ->transform(CLI::CheckedTransformer(std::map<std::string, ink::SampleStyle>{
            {"stipple", ink::SampleStyle::Stipple}, {"direction", ink::SampleStyle::Direction}}));
    cmd->add_option("--direction", r.direction, "Direction field: axis, curvature-min or curvature-max")
        ->transform(CLI::CheckedTransformer(std::map<std::string, ink::DirectionField>{
            {"axis", ink::DirectionField::Axis},
            {"curvature-min", ink::DirectionField::CurvatureMin},
            {"curvature-max", ink::DirectionField::CurvatureMax}}));
    cmd->add_option("--axis", o.axis, "Axis for --direction axis, as X Y Z (default: 0 1 0)")->expected(3);
    cmd->add_option("--seeds", r.seeds, "Seeds: control (the control points) or grid (a jittered grid)")
        ->transform(CLI::CheckedTransformer(std::map<std::string, ink::SeedMode>{
            {"control", ink::SeedMode::ControlPoints}, {"grid", ink::SeedMode::Grid}}));
    cmd->add_option("--grid", r.grid, "Grid cells along the longest side for --seeds grid")->capture_default_str();
    cmd->add_option("--rho", r.rho0, "ρ₀ as a fraction of the bounding-box diagonal (default: half the seed spacing)");
    cmd->add_option("--seed", r.seed, "Random seed")->capture_default_str();
    cmd->add_option("--keep-levels", o.keepLevels, "Keep all levels or only the last")
        ->check(CLI::IsMember({"all", "last"}))
        ->capture_default_str();
}

void finishRefineOptions(Options& o) {
    if (!o.axis.empty()) o.refine.axis = Eigen::Vector3d(o.axis[0], o.axis[1], o.axis[2]);
    if (!(o.refine.axis.norm() > 0) || !o.refine.axis.allFinite()) throw ink::Error("--axis must be a non-zero vector");
    o.refine.keepAllLevels = o.keepLevels == "all";
}

// Owns the Vulkan context of one command; validation errors count as a failure.
struct Session {
    ink::Context ctx;
    explicit Session(const Options& o) {
        ink::ContextOptions options;
        options.validation = o.validation;
        options.device = o.device;
        ink::createContext(ctx, options);
    }
    ~Session() { ink::destroyContext(ctx); }
    void checkValidation() const {
        if (ctx.validationErrors)
            throw ink::Error(std::to_string(ctx.validationErrors.load()) +
                             " Vulkan validation error(s); first: " + ctx.firstValidationMessage);
    }
};

// Destroys the refinement's device resources on every path out.
struct RefinementGuard {
    ink::Context& ctx;
    ink::GpuRefinement r;
    ~RefinementGuard() { ink::destroyRefinement(ctx, r); }
};

json fitJson(const ink::Model& m) {
    return {{"seconds", m.fit.seconds},
            {"relative_residual", m.fit.relativeResidual},
            {"max_distance", m.fit.maxDistance},
            {"max_normal_angle_deg", m.fit.maxNormalAngleDeg}};
}

json levelsJson(const std::vector<ink::LevelStats>& levels) {
    json list = json::array();
    for (const auto& s : levels) {
        json dropped;
        for (uint32_t k = 0; k < ink::DropReasonCount; ++k) dropped[ink::dropReasonName(k)] = s.dropped[k];
        list.push_back({{"level", s.level}, {"candidates", s.candidates}, {"kept", s.kept}, {"dropped", dropped},
                        {"gpu_ms", s.gpuMs}});
    }
    return list;
}

void writeJson(const std::string& path, const json& j) {
    if (path.empty()) return;
    ink::writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp);
        out << j.dump(2) << "\n";
        out.close();
        if (!out) throw ink::Error("cannot write '" + path + "'");
    });
}

int runSample(Options& o, const std::string& pointsPath) {
    finishRefineOptions(o);
    ink::Model model = ink::loadModel(o.model, {o.controlPoints});
    json stats = {{"control_points", model.fit.controlPoints}, {"fit", fitJson(model)}};
    std::vector<ink::PointRecord> points;
    std::vector<ink::LevelStats> levels;
    auto start = Clock::now();
    if (o.backend == "cpu") {
        ink::RefinePlan plan = ink::planRefinement(model.hrbf, o.refine, UINT32_MAX);
        points = ink::refineOnCpu(model.hrbf, o.refine, plan, &levels);
        stats["refine"]["seconds"] = secondsSince(start);
        stats["device"] = "cpu";
    } else {
        Session session(o);
        RefinementGuard g{session.ctx, {}};
        ink::createRefinement(session.ctx, g.r, model.hrbf, o.refine);
        start = Clock::now();
        ink::runRefinement(session.ctx, g.r);
        stats["refine"]["seconds"] = secondsSince(start);
        points = ink::readPoints(session.ctx, g.r);
        levels = ink::readLevelStats(session.ctx, g.r);
        session.checkValidation();
        stats["device"] = session.ctx.properties.deviceName;
        stats["driver"] = session.ctx.driverInfo;
    }
    stats["refine"]["points"] = points.size();
    stats["refine"]["levels"] = levelsJson(levels);
    ink::writePointsPly(pointsPath, points, model.hrbf.frame);
    writeJson(o.statsPath, stats);
    std::printf("%s: %zu control points, %zu points -> %s\n", o.model.c_str(), model.fit.controlPoints,
                points.size(), pointsPath.c_str());
    return 0;
}

int runRender(Options& o, const std::string& output, std::vector<uint32_t> size) {
    finishRefineOptions(o);
    auto start = Clock::now();
    ink::Model model = ink::loadModel(o.model, {o.controlPoints});
    Session session(o);
    RefinementGuard g{session.ctx, {}};
    ink::createRefinement(session.ctx, g.r, model.hrbf, o.refine);
    ink::runRefinement(session.ctx, g.r);
    ink::RgbaImage image;
    {
        ink::OffscreenRenderer renderer(session.ctx, size[0], size[1], ink::RenderStyle{}, {&g.r});
        image = renderer.render(ink::Camera{});
    }
    session.checkValidation();
    ink::writePng(output, image);
    auto levels = ink::readLevelStats(session.ctx, g.r);
    uint64_t points = 0;
    for (auto& s : levels) points += s.kept;
    writeJson(o.statsPath, {{"control_points", model.fit.controlPoints},
                            {"fit", fitJson(model)},
                            {"refine", {{"points", points}, {"levels", levelsJson(levels)}}},
                            {"preprocess_seconds", secondsSince(start)},
                            {"device", session.ctx.properties.deviceName},
                            {"driver", session.ctx.driverInfo}});
    std::printf("%s: %zu control points, %llu points, %.2f s -> %s\n", o.model.c_str(), model.fit.controlPoints,
                (unsigned long long)points, secondsSince(start), output.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"inkwell: pen-and-ink drawings (stipples and hatches) of Hermite RBF implicit surfaces, "
                 "fitted to meshes or oriented points and refined on the GPU with Vulkan"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "inkwell 0.1.0");

    Options o;
    o.refine.passes = 2;
    std::string output;
    std::vector<uint32_t> size{1024, 1024};

    CLI::App* render = app.add_subcommand("render", "Render a model headless to a PNG");
    addModelOptions(render, o);
    addRefineOptions(render, o);
    addDeviceOptions(render, o);
    render->add_option("-o,--output", output, "Output PNG")->required();
    render->add_option("--size", size, "Image width and height in pixels")->expected(2)->capture_default_str();

    CLI::App* sample = app.add_subcommand("sample", "Refine points on the surface and write them as PLY");
    addModelOptions(sample, o);
    addRefineOptions(sample, o);
    addDeviceOptions(sample, o);
    std::string pointsPath;
    sample->add_option("--points", pointsPath, "Output PLY (binary little endian, float x y z nx ny nz)")->required();
    sample->add_option("--backend", o.backend, "gpu (Vulkan) or cpu (the multi-threaded reference)")
        ->check(CLI::IsMember({"gpu", "cpu"}))
        ->capture_default_str();

    CLI::App* devices = app.add_subcommand("devices", "List the Vulkan devices");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }

    try {
        if (*render) return runRender(o, output, size);
        if (*sample) return runSample(o, pointsPath);
        if (*devices) {
            auto names = ink::listDevices();
            for (size_t i = 0; i < names.size(); ++i) std::printf("%zu: %s\n", i, names[i].c_str());
            return 0;
        }
    } catch (const ink::Error& e) {
        std::fprintf(stderr, "inkwell: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "inkwell: out of memory\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "inkwell: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}
