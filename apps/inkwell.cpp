// inkwell: pen-and-ink drawings of HRBF implicit surfaces. Argument parsing and the top-level flow only;
// the work is in engine/.
#include "common.h"
#include "context.h"
#include "image.h"
#include "model.h"
#include "refine.h"
#include "renderer.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <fstream>

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct CommonOptions {
    std::string model;
    size_t controlPoints = 0;
    std::string device;
    bool validation = false;
};

void addModelOptions(CLI::App* cmd, CommonOptions& o) {
    cmd->add_option("model", o.model, "Mesh or oriented points: .obj, .ply, .pts/.xyzn/.txt")->required();
    cmd->add_option("--control-points", o.controlPoints,
                    "Control points chosen by farthest-point sampling (default: all, at most 1000)");
}

void addDeviceOptions(CLI::App* cmd, CommonOptions& o) {
    cmd->add_option("--device", o.device, "Vulkan device: an index or part of its name (default: a GPU, else lavapipe)");
    cmd->add_flag("--validation", o.validation, "Enable Vulkan validation and synchronization validation");
}

// Owns the Vulkan context for one command; reports validation errors as a failure.
struct Session {
    ink::Context ctx;
    explicit Session(const CommonOptions& o) {
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

int runRender(const CommonOptions& common, const std::string& output, uint32_t levels, uint32_t passes) {
    auto start = Clock::now();
    ink::Model model = ink::loadModel(common.model, {common.controlPoints});
    Session session(common);
    ink::RefineOptions refineOptions;
    refineOptions.levels = levels;
    refineOptions.passes = passes;
    ink::GpuRefinement refinement;
    try {
        ink::createRefinement(session.ctx, refinement, model.hrbf, refineOptions);
        ink::runRefinement(session.ctx, refinement);
        ink::RenderStyle style;
        ink::RgbaImage image;
        {
            ink::OffscreenRenderer renderer(session.ctx, 1024, 1024, style, refinement);
            image = renderer.render(ink::Camera{});
        }
        session.checkValidation();
        ink::writePng(output, image);
        auto stats = ink::readLevelStats(session.ctx, refinement);
        uint64_t points = 0;
        for (auto& s : stats) {
            points += s.kept;
            std::fprintf(stderr, "level %u: %u candidates, %u kept, dropped %u/%u/%u/%u, %.1f ms\n", s.level,
                         s.candidates, s.kept, s.dropped[0], s.dropped[1], s.dropped[2], s.dropped[3], s.gpuMs);
        }
        std::printf("%s: %zu control points, %llu points, %.2f s -> %s\n", common.model.c_str(),
                    model.fit.controlPoints, (unsigned long long)points, secondsSince(start), output.c_str());
    } catch (...) {
        ink::destroyRefinement(session.ctx, refinement);
        throw;
    }
    ink::destroyRefinement(session.ctx, refinement);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"inkwell: pen-and-ink drawings (stipples and hatches) of Hermite RBF implicit surfaces, "
                 "fitted to meshes or oriented points and refined on the GPU with Vulkan"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "inkwell 0.1.0");

    CommonOptions common;
    std::string output;
    uint32_t levels = 4, passes = 2;
    CLI::App* render = app.add_subcommand("render", "Render a model headless to a PNG");
    addModelOptions(render, common);
    addDeviceOptions(render, common);
    render->add_option("-o,--output", output, "Output PNG")->required();
    render->add_option("--levels", levels, "Refinement levels after the seeds")->capture_default_str();
    render->add_option("--passes", passes, "Independent refinement passes")->capture_default_str();

    CLI::App* devices = app.add_subcommand("devices", "List the Vulkan devices");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }

    try {
        if (*render) return runRender(common, output, levels, passes);
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
