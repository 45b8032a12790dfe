// fit, sample, render, devices.
#include "commands.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <optional>

namespace app {

static int runFit(Options& o, const std::string& output, bool text) {
    inkwell::checkModelOptions(modelOptions(o));
    inkwell::checkOutputs({output, o.statsPath}, {o.model, o.preset});
    const inkwell::Model model = loadModel(o);
    const inkwell::FitReport fit = model.report();
    inkwell::OutputBatch outputs;  // the model and the stats, both or neither
    model.save(output, text ? inkwell::HrbfFormat::Text : inkwell::HrbfFormat::Binary);
    writeJson(o.statsPath, {{"control_points", fit.controlPoints},
                            {"input_points", fit.inputPoints},
                            {"face_samples", fit.faceSamples},
                            {"merged_duplicates", fit.mergedDuplicates},
                            {"flipped_normals", fit.flippedNormals},
                            {"estimated_normals", fit.estimatedNormals},
                            {"load_seconds", fit.loadSeconds},
                            {"fit", json::parse(model.statsJson())}});
    outputs.commit();
    std::printf("%s: %zu control points, fitted in %.3f s, max distance %.2g, max angle %.2g deg -> %s\n",
                o.model.c_str(), fit.controlPoints, fit.seconds, fit.maxDistance, fit.maxNormalAngleDeg,
                output.c_str());
    return 0;
}

static json fidelityJson(const inkwell::Fidelity& f) {
    return {{"tolerance", f.tolerance}, {"surface_samples", f.surfaceSamples}, {"points", f.points},
            {"coverage", f.coverage},   {"coverage_p99", f.coverageP99},       {"coverage_max", f.coverageMax},
            {"accuracy", f.accuracy},   {"accuracy_p99", f.accuracyP99},       {"accuracy_max", f.accuracyMax}};
}

static int runSample(Options& o, const std::string& pointsPath) {
    finishOptions(o);
    inkwell::checkOutputs({pointsPath, o.statsPath}, {o.model, o.preset});
    // The mesh --fidelity measures against (the input, not a fitted model), read before any other work so that a
    // file without faces is refused first.
    std::optional<inkwell::FidelityMesh> mesh;
    if (o.fidelity) {
        std::string ext = std::filesystem::path(o.model).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (ext == ".hrbf")
            throw inkwell::Error(o.model +
                                 ": --fidelity measures against the input mesh; give the mesh, not a fitted .hrbf");
        mesh.emplace(o.model, reporter());
    }
    // The device first: without one there is no point in fitting.
    std::optional<inkwell::Device> device;
    if (o.backend != "cpu") device.emplace(openDevice(o, o.validation));
    const inkwell::Model model = loadModel(o);
    const inkwell::Samples samples(device ? &*device : nullptr, model, o.drawing, o.fidelity, reporter());
    if (device) checkValidation(*device);
    json stats = json::parse(samples.statsJson(!o.statsPath.empty()));  // nearest neighbours: only when asked
    stats["control_points"] = model.report().controlPoints;
    stats["fit"] = json::parse(model.statsJson());
    if (o.fidelity) {
        auto start = Clock::now();
        const inkwell::Fidelity f = mesh->measure(samples.refined(), 0.01, reporter(), o.creaseAngle);
        stats["fidelity"] = fidelityJson(f);
        stats["fidelity"]["seconds"] = secondsSince(start);
        std::printf(
            "fidelity: %.2f%% of the surface has a refined point within %g%% of the diagonal (99th percentile "
            "%.3g%%, max %.3g%%); %.2f%% of the %zu refined points lie within it of the surface (99th "
            "percentile %.3g%%, max %.3g%%)\n",
            100 * f.coverage, 100 * f.tolerance, 100 * f.coverageP99, 100 * f.coverageMax, 100 * f.accuracy, f.points,
            100 * f.accuracyP99, 100 * f.accuracyMax);
    }
    inkwell::OutputBatch outputs;  // the points and the stats, both or neither
    samples.writePly(pointsPath);
    writeJson(o.statsPath, stats);
    outputs.commit();
    std::printf("%s: %zu control points, %zu points -> %s\n", o.model.c_str(), model.report().controlPoints,
                samples.size(), pointsPath.c_str());
    return 0;
}

// One frame, written as each output asks: .svg/.pdf its marks laid out on a page, any other name the PNG.
static int runRender(Options& o, const std::vector<std::string>& outputs) {
    finishOptions(o);
    std::vector<std::string> written = outputs;
    written.push_back(o.statsPath);
    inkwell::checkOutputs(written, {o.model, o.preset});
    auto start = Clock::now();
    inkwell::Device device = openDevice(o, o.validation);
    device.checkImageSize(o.size[0], o.size[1], o.look.supersample);
    const inkwell::Model model = loadModel(o);
    const inkwell::Drawing drawing(device, model, o.drawing, reporter());
    const ViewReport view = resolveView(o, drawing, float(o.size[0]) / float(o.size[1]));
    try {
        (void)drawing.contours(cameraFrom(o));  // traced for this view before the renderer draws it
    } catch (const inkwell::Error& e) {
        throw inkwell::Error(o.model + ": " + e.what());
    }
    inkwell::Image image;
    std::optional<inkwell::Plot> plot;
    json stipples;  // with --stats: the page's
    double layoutSeconds = 0;
    const bool vectors = std::any_of(outputs.begin(), outputs.end(), inkwell::Plot::isVectorPath);
    {
        inkwell::Renderer renderer(drawing, o.size[0], o.size[1], o.look);
        image = renderer.render(cameraFrom(o));
        if (!o.statsPath.empty()) stipples = json::parse(renderer.statsJson());
        if (vectors) {
            auto layoutStart = Clock::now();
            plot = renderer.plot(o.page);
            layoutSeconds = secondsSince(layoutStart);
        }
    }
    checkValidation(device);
    inkwell::OutputBatch batch;  // the image, the drawings and the stats, all or none
    for (const std::string& out : outputs) {
        if (inkwell::Plot::isVectorPath(out))
            plot->write(out);
        else
            image.writePng(out);
    }
    const uint64_t points = drawing.pointCount();
    const size_t controlPoints = model.report().controlPoints;
    json stats = json::parse(drawing.statsJson());
    stats["control_points"] = controlPoints;
    stats["fit"] = json::parse(model.statsJson());
    stats["stipples"] = stipples;
    stats["view"] = viewJson(view);
    stats["seconds"] = secondsSince(start);
    if (plot) {
        stats["vector"] = json::parse(plot->statsJson());
        stats["vector"]["seconds"] = layoutSeconds;  // the layout and the ordering
    }
    stats.update(deviceJson(device));
    writeJson(o.statsPath, stats);
    batch.commit();
    std::string names;
    for (const std::string& out : outputs) names += (names.empty() ? "" : ", ") + out;
    std::printf("%s: %zu control points, %llu points, %.2f s -> %s\n", o.model.c_str(), controlPoints,
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
        const std::vector<std::string> names = inkwell::Device::list();
        for (size_t i = 0; i < names.size(); ++i) std::printf("%zu: %s\n", i, names[i].c_str());
        return 0;
    });
}

}  // namespace app
