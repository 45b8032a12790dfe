// fit, sample, render, devices.
#include "base/files.h"
#include "base/image.h"
#include "commands.h"
#include "io/export.h"
#include "io/hrbf_io.h"
#include "select/select.h"
#include "surface/fidelity.h"
#include "surface/surface_sampling.h"
#include "vector/vector.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <optional>

namespace app {

static int runFit(Options& o, const std::string& output, bool text) {
    ink::checkModelOptions(modelOptions(o));
    ink::checkOutputs({output, o.statsPath}, {o.model, o.preset});
    ink::Model model = ink::loadModel(o.model, modelOptions(o));
    ink::OutputBatch outputs;  // the model and the stats, both or neither
    ink::saveHrbf(output, model.surface, text ? ink::HrbfFormat::Text : ink::HrbfFormat::Binary);
    writeJson(o.statsPath, {{"control_points", model.fit.controlPoints},
                            {"input_points", model.inputPoints},
                            {"face_samples", model.faceSamples},
                            {"merged_duplicates", model.mergedDuplicates},
                            {"flipped_normals", model.flippedNormals},
                            {"load_seconds", model.loadSeconds},
                            {"fit", fitJson(model)}});
    outputs.commit();
    std::printf("%s: %zu control points, fitted in %.3f s, max distance %.2g, max angle %.2g deg -> %s\n",
                o.model.c_str(), model.fit.controlPoints, model.fit.seconds, model.fit.maxDistance,
                model.fit.maxNormalAngleDeg, output.c_str());
    return 0;
}

// The selection's figures, alike from both backends.
static json selectJson(const ink::SelectPlan& plan, size_t candidates, const std::vector<uint32_t>& added) {
    return {{"candidates", candidates},
            {"radius", plan.radius0},
            {"area_estimate", plan.areaEstimate},
            {"stage_added", added}};
}

// The mesh --fidelity measures against, read before any other work so that a file without faces is refused first.
static ink::OrientedPoints fidelityMesh(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".hrbf")
        throw ink::Error(path + ": --fidelity measures against the input mesh; give the mesh, not a fitted .hrbf");
    ink::OrientedPoints mesh = ink::loadPoints(path);
    double area = 0;
    for (double a : ink::triangleAreas(mesh)) area += a;
    if (!(area > 0)) throw ink::Error(path + ": --fidelity needs a mesh with faces; this file has none with area");
    return mesh;
}

static json fidelityJson(const ink::Fidelity& f) {
    return {{"tolerance", f.tolerance}, {"surface_samples", f.surfaceSamples}, {"points", f.points},
            {"coverage", f.coverage},   {"coverage_p99", f.coverageP99},       {"coverage_max", f.coverageMax},
            {"accuracy", f.accuracy},   {"accuracy_p99", f.accuracyP99},       {"accuracy_max", f.accuracyMax}};
}

static int runSample(Options& o, const std::string& pointsPath) {
    finishOptions(o);
    ink::checkOutputs({pointsPath, o.statsPath}, {o.model, o.preset});
    ink::OrientedPoints mesh;
    if (o.fidelity) mesh = fidelityMesh(o.model);
    // The device first: without one there is no point in fitting.
    std::unique_ptr<Session> session;
    if (o.backend != "cpu") session = std::make_unique<Session>(o);
    ink::Model model = ink::loadModel(o.model, modelOptions(o));
    json stats = {{"control_points", model.fit.controlPoints}, {"fit", fitJson(model)}};
    std::vector<ink::PointRecord> points;
    std::vector<ink::PointRecord> refined;  // every refined point, before any selection: what --fidelity measures
    std::vector<ink::LevelStats> levels;
    if (!session) {
        auto start = Clock::now();
        ink::RefinePlan plan = ink::planRefinement(model.surface, o.refine, ink::kMaxCpuPoints);
        points = ink::refineOnCpu(model.surface, o.refine, plan, &levels);
        stats["refine"]["seconds"] = secondsSince(start);
        if (o.fidelity) refined = points;
        if (o.refine.selects()) {
            start = Clock::now();
            ink::SelectPlan selectPlan = ink::planSelection(model.surface, plan, ink::selectOptions(o.refine));
            std::vector<uint32_t> added;
            size_t candidates = points.size();
            points = ink::selectOnCpu(points, selectPlan, &added);
            stats["select"] = selectJson(selectPlan, candidates, added);
            stats["select"]["seconds"] = secondsSince(start);
        }
        stats["device"] = "cpu";
    } else {
        {
            ink::Refinement refinement(session->ctx, model.surface, o.refine);
            ink::GpuRefinement& r = refinement.gpu();
            auto start = Clock::now();
            ink::runRefinement(session->ctx, r);
            stats["refine"]["seconds"] = secondsSince(start);
            levels = ink::readLevelStats(session->ctx, r);
            if (r.selection) {
                stats["select"] = selectJson(r.selection->plan, ink::readPointCount(session->ctx, r),
                                             ink::readStageCounts(session->ctx, *r.selection));
                stats["select"]["gpu_ms"] = ink::selectionMs(session->ctx, r);
            }
            points = ink::readDrawnPoints(session->ctx, r);
            if (o.fidelity) refined = r.selection ? ink::readPoints(session->ctx, r) : points;
        }
        session->checkValidation();
        stats.update(deviceJson(session->ctx));
    }
    stats["refine"]["points"] = points.size();
    stats["refine"]["levels"] = levelsJson(levels);
    if (!o.statsPath.empty()) stats["spacing"] = spacingJson(points);  // nearest neighbours: only when asked
    if (o.fidelity) {
        std::vector<Eigen::Vector3d> at;
        at.reserve(refined.size());
        for (const ink::PointRecord& p : refined)
            at.push_back(model.surface.frame.toInput(Eigen::Vector3d(p.position[0], p.position[1], p.position[2])));
        auto start = Clock::now();
        ink::Fidelity f = ink::measureFidelity(mesh, at, 0.01, 0, o.creaseAngle);
        stats["fidelity"] = fidelityJson(f);
        stats["fidelity"]["seconds"] = secondsSince(start);
        std::printf(
            "fidelity: %.2f%% of the surface has a refined point within %g%% of the diagonal (99th percentile "
            "%.3g%%, max %.3g%%); %.2f%% of the %zu refined points lie within it of the surface (99th "
            "percentile %.3g%%, max %.3g%%)\n",
            100 * f.coverage, 100 * f.tolerance, 100 * f.coverageP99, 100 * f.coverageMax, 100 * f.accuracy, f.points,
            100 * f.accuracyP99, 100 * f.accuracyMax);
    }
    ink::OutputBatch outputs;  // the points and the stats, both or neither
    ink::writePointsPly(pointsPath, points, model.surface.frame);
    writeJson(o.statsPath, stats);
    outputs.commit();
    std::printf("%s: %zu control points, %zu points -> %s\n", o.model.c_str(), model.fit.controlPoints, points.size(),
                pointsPath.c_str());
    return 0;
}

// One frame, written as each output asks: .svg/.pdf its marks laid out on a page, any other name the PNG.
static int runRender(Options& o, const std::vector<std::string>& outputs) {
    finishOptions(o);
    std::vector<std::string> written = outputs;
    written.push_back(o.statsPath);
    ink::checkOutputs(written, {o.model, o.preset});
    auto start = Clock::now();
    Session session(o);
    ink::checkOffscreenSize(session.ctx, o.size[0], o.size[1], std::max(1u, o.render.supersample));
    Scene scene(session.ctx, o);
    const ViewReport view = resolveView(o, scene, float(o.size[0]) / float(o.size[1]));
    try {
        scene.traceContours(cameraFrom(o));
    } catch (const ink::Error& e) {
        throw ink::Error(o.model + ": " + e.what());
    }
    ink::RgbaImage image;
    ink::VectorDrawing marks;
    json stipples;  // with --stats: the page's
    const bool vectors = std::any_of(outputs.begin(), outputs.end(), ink::isVectorPath);
    {
        ink::OffscreenRenderer renderer(session.ctx, o.size[0], o.size[1], o.render, scene.pointers(),
                                        scene.strokes.get());
        image = renderer.render(cameraFrom(o));
        if (vectors) marks = renderer.vectorDrawing();
        if (!o.statsPath.empty())
            stipples = pageJson(renderer, scene.pointers().size(), o.render, o.size[0], o.size[1]);
    }
    session.checkValidation();
    std::optional<ink::Plot> plot;
    double layoutSeconds = 0;
    if (vectors) {
        auto layoutStart = Clock::now();
        plot = ink::layoutPlot(marks, o.page);
        layoutSeconds = secondsSince(layoutStart);
    }
    ink::OutputBatch batch;  // the image, the drawings and the stats, all or none
    for (const std::string& out : outputs) {
        if (ink::isVectorPath(out))
            ink::writePlot(out, *plot);
        else
            ink::writePng(out, image);
    }
    uint64_t points = scene.points();
    json levels = json::array();
    ink::HostMs hostMs;
    for (auto& s : scene.sets) {
        levels.push_back(levelsJson(ink::readLevelStats(session.ctx, s->gpu())));
        hostMs += s->gpu().hostMs;
    }
    json stats = {
        {"control_points", scene.model.fit.controlPoints},
        {"fit", fitJson(scene.model)},
        {"refine",
         {{"seconds", scene.refineSeconds}, {"points", points}, {"sets", levels}, {"host_ms", hostMsJson(hostMs)}}},
        {"lines", linesJson(scene)},
        {"stipples", stipples},
        {"view", viewJson(view)},
        {"seconds", secondsSince(start)}};
    if (plot) {
        stats["vector"] = plotJson(*plot);
        stats["vector"]["seconds"] = layoutSeconds;  // the layout and the ordering
    }
    stats.update(deviceJson(session.ctx));
    writeJson(o.statsPath, stats);
    batch.commit();
    std::string names;
    for (const std::string& out : outputs) names += (names.empty() ? "" : ", ") + out;
    std::printf("%s: %zu control points, %llu points, %.2f s -> %s\n", o.model.c_str(), scene.model.fit.controlPoints,
                (unsigned long long)points, secondsSince(start), names.c_str());
    if (plot) printPlot(*plot);
    return 0;
}

void addModelCommands(CLI::App& cli, Options& o, Commands& commands) {
    auto output = std::make_shared<std::string>();

    CLI::App* fit = cli.add_subcommand("fit", "Fit the HRBF to a model and save it as .hrbf");
    addModelOptions(fit, o);
    fit->add_option("-o,--output", *output, "Output .hrbf file")->required();
    auto text = std::make_shared<bool>(false);
    fit->add_flag("--text", *text,
                  "Write the .hrbf as text (versions 1 and 2, for interchange; 17 digits, exact) instead of the "
                  "binary version 3 (the default: float patches, about 6x smaller, fast to load)");
    commands.emplace_back(fit, [&o, output, text] { return runFit(o, *output, *text); });

    CLI::App* sample = cli.add_subcommand("sample", "Refine points on the surface and write them as PLY");
    addModelOptions(sample, o);
    addRefineOptions(sample, o);
    addDeviceOptions(sample, o);
    sample->add_option("--style", o.sampling, "Sampling: stipple (4 children a point) or direction (2, along a field)")
        ->check(CLI::IsMember({"stipple", "direction"}))
        ->capture_default_str();
    sample->add_option("--points", *output, "Output PLY (binary little endian, float x y z nx ny nz)")->required();
    sample->add_flag("--fidelity", o.fidelity,
                     "Measure the refined points against MODEL's faces: the share of the surface with a point within "
                     "1% of the diagonal, and of the points within 1% of the surface");
    sample->add_option("--backend", o.backend, "gpu (Vulkan) or cpu (the multi-threaded reference)")
        ->check(CLI::IsMember({"gpu", "cpu"}))
        ->capture_default_str();
    commands.emplace_back(sample, [&o, output] { return runSample(o, *output); });

    auto renderOutputs = std::make_shared<std::vector<std::string>>();
    CLI::App* render = cli.add_subcommand("render", "Render a model headless to a PNG, an SVG or a PDF");
    addModelOptions(render, o);
    addRefineOptions(render, o);
    addRenderOptions(render, o);
    addVectorOptions(render, o);
    addDeviceOptions(render, o);
    render
        ->add_option("-o,--output", *renderOutputs,
                     "Output: .svg or .pdf (the marks on a page, for plotters and print), else a PNG; repeat for "
                     "several of the same frame")
        ->required()
        ->allow_extra_args(false);
    commands.emplace_back(render, [&o, renderOutputs] { return runRender(o, *renderOutputs); });

    CLI::App* devices = cli.add_subcommand("devices", "List the Vulkan devices");
    commands.emplace_back(devices, [] {
        auto names = ink::listDevices();
        for (size_t i = 0; i < names.size(); ++i) std::printf("%zu: %s\n", i, names[i].c_str());
        return 0;
    });
}

}  // namespace app
