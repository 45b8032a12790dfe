// Visual regression: golden images of a few small scenes rendered in-process (lavapipe references, compared
// with the tolerance of `inkwell compare`), and the capture and compare commands as a user runs them.
// INKWELL_UPDATE_GOLDENS=1 rewrites the goldens instead (scripts/update-goldens.sh; docs/capture.md).
#include "compare.h"
#include "gpu_fixture.h"
#include "image.h"
#include "model.h"
#include "refine.h"
#include "renderer.h"

#include "run_command.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace fs = std::filesystem;

namespace {

// A golden scene. Each is also `inkwell render MODEL --size 256 256 ...` with the same options (the CLI's
// defaults are RenderStyle's and RefineOptions'), which is how docs/capture.md describes them.
struct GoldenScene {
    const char* name;      // tests/golden/<name>.png
    const char* model;     // relative to the source directory
    size_t controlPoints;  // 0: all the points of the file
    uint32_t levels;
    ink::SampleStyle style;
    ink::Camera camera;
    bool hiddenLines;
};

ink::Camera camera(float azimuthDeg, float elevationDeg, float distance) {
    ink::Camera c;
    c.azimuthDeg = azimuthDeg;
    c.elevationDeg = elevationDeg;
    c.distance = distance;
    return c;
}

constexpr uint32_t kGoldenSize = 256;

const GoldenScene kBunnyStipple{"bunny-stipple",           "assets/bunny.obj", 150,  3,
                                ink::SampleStyle::Stipple, ink::Camera{},      false};
const GoldenScene kBunnyDirection{"bunny-direction",           "assets/bunny.obj",    150,  4,
                                  ink::SampleStyle::Direction, camera(-60, 20, 1.5f), false};
const GoldenScene kTorusHidden{
    "torus-hidden", "tests/golden/torus.pts", 0, 4, ink::SampleStyle::Stipple, camera(20, 20, 1.4f), true};

std::string sourcePath(const std::string& relative) { return std::string(INKWELL_SOURCE_DIR) + "/" + relative; }

// Where failing tests leave their images: beside the inkwell binary, i.e. the build directory.
fs::path buildDir() { return fs::path(INKWELL_BINARY).parent_path(); }

bool updatingGoldens() {
    const char* v = std::getenv("INKWELL_UPDATE_GOLDENS");
    return v && std::string(v) == "1";
}

ink::RgbaImage renderScene(ink::Context& ctx, const GoldenScene& scene) {
    ink::Model model = ink::loadModel(sourcePath(scene.model), {scene.controlPoints});
    ink::RefineOptions options;
    options.levels = scene.levels;
    options.style = scene.style;
    ink::RenderStyle style;
    style.hiddenLines = scene.hiddenLines;
    Refinement refined(ctx, model.hrbf, options);
    ink::OffscreenRenderer renderer(ctx, kGoldenSize, kGoldenSize, style, {&refined.r});
    return renderer.render(scene.camera);
}

void checkGolden(const GoldenScene& scene) {
    GpuFixture gpu;
    ink::RgbaImage actual = renderScene(gpu.ctx, scene);
    gpu.requireNoValidationErrors();
    REQUIRE(actual.width == kGoldenSize);

    // The goldens are lavapipe's pictures: another driver rasterizes and rounds differently.
    std::string device = gpu.ctx.properties.deviceName;
    bool lavapipe = device.find("llvmpipe") != std::string::npos;
    std::string golden = sourcePath(std::string("tests/golden/") + scene.name + ".png");
    if (updatingGoldens()) {
        if (!lavapipe) FAIL("goldens are made on lavapipe, not " << device << "; scripts/update-goldens.sh selects it");
        ink::writePng(golden, actual);
        MESSAGE("updated " << golden);
        return;
    }
    if (!lavapipe) {
        MESSAGE("skipped the comparison with " << golden << ": rendered on " << device << ", not lavapipe");
        return;
    }
    INFO("golden " << golden << " (scripts/update-goldens.sh rewrites it after an intended change)");
    REQUIRE(fs::exists(golden));
    ink::RgbaImage expected = ink::readPng(golden);
    ink::CompareResult result = ink::compareImages(expected, actual, ink::kCompareThreshold);
    INFO(ink::describe(result));
    if (!ink::withinTolerance(result, ink::kCompareMaxFraction)) {
        std::string actualPath = (buildDir() / (std::string(scene.name) + "-actual.png")).string();
        std::string diffPath = (buildDir() / (std::string(scene.name) + "-diff.png")).string();
        ink::writePng(actualPath, actual);
        ink::writePng(diffPath, ink::diffImage(expected, actual, ink::kCompareThreshold));
        FAIL("the rendering differs from its golden; see " << actualPath << " and " << diffPath);
    }
}

Run run(const std::string& args) { return runInkwell(args); }

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

// A fresh directory per test case: CTest runs the cases in parallel.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& tag)
        : path(fs::temp_directory_path() / ("inkwell-capture-" + tag + "-" + std::to_string(getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
    std::string operator/(const std::string& name) const { return (path / name).string(); }
};

// Small and fast on lavapipe; the goldens cover the larger scenes.
const std::string kSmallCapture =
    "capture " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 100 --levels 1 --size 128 128 ";

ink::RgbaImage solid(uint32_t width, uint32_t height, uint8_t value) {
    ink::RgbaImage image{width, height, std::vector<uint8_t>(size_t(width) * height * 4, value)};
    for (size_t i = 3; i < image.pixels.size(); i += 4) image.pixels[i] = 255;
    return image;
}

}  // namespace

TEST_CASE("capture: golden bunny-stipple (default camera) matches") { checkGolden(kBunnyStipple); }

TEST_CASE("capture: golden bunny-direction (another angle) matches") { checkGolden(kBunnyDirection); }

TEST_CASE("capture: golden torus-hidden (oriented points, hidden lines) matches") { checkGolden(kTorusHidden); }

TEST_CASE("capture: the default tolerance notices the torus golden's hidden lines going missing") {
    // The grey hidden silhouettes are the smallest feature a golden holds (0.7% of the pixels): if the
    // tolerance let them go, it would let most regressions go.
    if (updatingGoldens()) return;
    GpuFixture gpu;
    GoldenScene scene = kTorusHidden;
    scene.hiddenLines = false;
    ink::RgbaImage withoutHidden = renderScene(gpu.ctx, scene);
    gpu.requireNoValidationErrors();
    if (std::string(gpu.ctx.properties.deviceName).find("llvmpipe") == std::string::npos) return;
    ink::RgbaImage golden = ink::readPng(sourcePath("tests/golden/torus-hidden.png"));
    ink::CompareResult result = ink::compareImages(golden, withoutHidden, ink::kCompareThreshold);
    INFO(ink::describe(result));
    CHECK_FALSE(ink::withinTolerance(result, ink::kCompareMaxFraction));
}

TEST_CASE("capture: compareImages counts pixels that differ by more than the threshold") {
    ink::RgbaImage a = solid(10, 10, 200), b = a;
    ink::CompareResult same = ink::compareImages(a, b, 8);
    CHECK(same.sameSize);
    CHECK(same.maxAbsDiff == 0);
    CHECK(same.differingPixels == 0);
    CHECK(same.pixels == 100);
    CHECK(ink::withinTolerance(same, 0.0));

    b.pixels[0] = 208;          // pixel 0: red off by 8, within the threshold
    b.pixels[4 * 5 + 2] = 191;  // pixel 5: blue off by 9, over it
    b.pixels[4 * 7 + 3] = 0;    // pixel 7: alpha counts too
    ink::CompareResult r = ink::compareImages(a, b, 8);
    CHECK(r.maxAbsDiff == 255);
    CHECK(r.differingPixels == 2);
    CHECK(r.differingFraction == doctest::Approx(0.02));
    CHECK(ink::describe(r) == "max abs diff 255, 2.000% pixels differ (2 of 100)");
    CHECK(ink::withinTolerance(r, 0.02));
    CHECK_FALSE(ink::withinTolerance(r, 0.019));

    ink::RgbaImage diff = ink::diffImage(a, b, 8);
    REQUIRE(diff.width == 10);
    auto pixel = [&](size_t i) {
        return std::array<int, 4>{diff.pixels[4 * i], diff.pixels[4 * i + 1], diff.pixels[4 * i + 2],
                                  diff.pixels[4 * i + 3]};
    };
    CHECK(pixel(5) == std::array<int, 4>{255, 0, 0, 255});
    CHECK(pixel(7) == std::array<int, 4>{255, 0, 0, 255});
    std::array<int, 4> grey = pixel(0);  // a faded copy of a: lighter than a, and grey
    CHECK(grey[0] > 200);
    CHECK(grey[0] == grey[1]);
    CHECK(grey[1] == grey[2]);

    ink::CompareResult sizes = ink::compareImages(a, solid(10, 11, 200), 255);
    CHECK_FALSE(sizes.sameSize);
    CHECK(sizes.differingFraction == 1.0);
    CHECK_FALSE(ink::withinTolerance(sizes, 1.0));
    CHECK(ink::diffImage(a, solid(12, 11, 200), 8).width == 12);
}

TEST_CASE("capture: two captures of the same frames pass compare, exit 0") {
    TempDir dir("twice");
    REQUIRE(run(kSmallCapture + "--frames 2 -o " + dir / "a").status == 0);
    REQUIRE(run(kSmallCapture + "--frames 2 -o " + dir / "b").status == 0);
    for (const char* frame : {"frame_0000.png", "frame_0001.png"}) {
        Run r = run("compare " + dir / "a/" + frame + " " + dir / "b/" + frame);
        CHECK(r.status == 0);
        CHECK(r.output == "max abs diff 0, 0.000% pixels differ (0 of 16384)\n");
    }
}

TEST_CASE("capture: frames of different azimuth fail compare, exit 1, with a diff image") {
    TempDir dir("azimuth");
    REQUIRE(run(kSmallCapture + "--frames 4 -o " + dir / "c").status == 0);
    Run r = run("compare " + dir / "c/frame_0000.png " + dir / "c/frame_0001.png");
    CHECK(r.status == 1);
    CHECK(lines(r.output) == 1);
    CHECK(r.output.find("pixels differ") != std::string::npos);
    std::string diff = dir / "c/frame_0001-diff.png";  // the default: beside B
    CHECK(r.output.find(diff) != std::string::npos);
    REQUIRE(fs::exists(diff));
    CHECK(ink::readPng(diff).width == 128);

    // Even a one-degree turn moves the dots too far for the default tolerance (1.4% of this small scene's
    // pixels differ; 0.9% of a golden's for a fifth of a degree).
    REQUIRE(run(kSmallCapture + "--frames 2 --orbit 2 -o " + dir / "d").status == 0);
    std::string frames = dir / "d/frame_0000.png " + dir / "d/frame_0001.png";
    Run small = run("compare " + frames + " --diff " + dir / "d.png");
    CHECK(small.status == 1);
    CHECK(fs::exists(dir / "d.png"));
    // ... and a tolerance that lets everything through passes them.
    CHECK(run("compare " + frames + " --max-fraction 1").status == 0);
}

TEST_CASE("capture: compare of a missing file or of a non-PNG exits 1 with one line") {
    TempDir dir("missing");
    ink::writePng(dir / "a.png", solid(4, 4, 255));
    Run r = run("compare " + dir / "a.png " + dir / "nope.png");
    CHECK(r.status == 1);
    CHECK(r.output == "inkwell: cannot open '" + dir / "nope.png" + "': No such file or directory\n");
    std::ofstream(dir / "text.png") << "not a png\n";
    Run text = run("compare " + dir / "text.png " + dir / "a.png");
    CHECK(text.status == 1);
    CHECK(lines(text.output) == 1);
    CHECK(text.output.rfind("inkwell: cannot read '", 0) == 0);
}

TEST_CASE("capture: compare of images of different sizes exits 1 with one line") {
    TempDir dir("sizes");
    ink::writePng(dir / "a.png", solid(4, 4, 255));
    ink::writePng(dir / "b.png", solid(4, 5, 255));
    Run r = run("compare " + dir / "a.png " + dir / "b.png");
    CHECK(r.status == 1);
    CHECK(r.output == "images differ in size: '" + dir / "a.png" + "' is 4x4, '" + dir / "b.png" + "' is 4x5\n");
    CHECK_FALSE(fs::exists(dir / "b-diff.png"));
}

TEST_CASE("capture: the manifest lists N frames with distinct azimuths, and validation stays clean") {
    TempDir dir("manifest");
    std::string out = dir / "new/frames";  // created, parents included
    Run r = run(kSmallCapture + "--frames 5 --orbit 90 --camera 10,20,1.8 --validation -o " + out);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("validation error") == std::string::npos);
    std::ifstream in(out + "/manifest.json");
    REQUIRE(in);
    nlohmann::json m = nlohmann::json::parse(in);
    CHECK(m["model"] == INKWELL_SOURCE_DIR "/assets/bunny.obj");
    CHECK(m["device"].get<std::string>().size() > 0);
    CHECK(m["points"].get<uint64_t>() > 100);
    CHECK(m["parameters"]["control_points"] == 100);
    CHECK(m["parameters"]["levels"] == 1);
    CHECK(m["parameters"]["size"] == nlohmann::json::array({128, 128}));
    REQUIRE(m["frames"].size() == 5);
    std::set<double> azimuths;
    for (size_t i = 0; i < 5; ++i) {
        const auto& f = m["frames"][i];
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04zu.png", i);
        CHECK(f["file"] == name);
        CHECK(fs::exists(out + "/" + name));
        CHECK(f["camera"]["azimuth_deg"].get<double>() == doctest::Approx(10 + 18.0 * double(i)));
        CHECK(f["camera"]["elevation_deg"] == 20.0);
        CHECK(f["camera"]["distance"] == 1.8);
        azimuths.insert(f["camera"]["azimuth_deg"].get<double>());
    }
    CHECK(azimuths.size() == 5);
}

TEST_CASE("capture: frame 0 of a capture matches the bunny-stipple golden") {
    // The command and the in-process golden render the same scene: capture is a way to remake a golden.
    TempDir dir("golden");
    std::string golden = "capture " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 150 --levels 3 ";
    REQUIRE(run(golden + "--size 256 256 --frames 2 -o " + dir / "g").status == 0);
    nlohmann::json m = nlohmann::json::parse(std::ifstream(dir / "g/manifest.json"));
    if (m["device"].get<std::string>().find("llvmpipe") == std::string::npos) {
        MESSAGE("skipped: the golden is lavapipe's picture");
        return;
    }
    Run r = run("compare " + sourcePath("tests/golden/bunny-stipple.png") + " " + dir / "g/frame_0000.png");
    INFO(r.output);
    CHECK(r.status == 0);
}

TEST_CASE("capture: an output directory that cannot be created exits 1 with one line") {
    TempDir dir("nodir");
    std::ofstream(dir / "file") << "x\n";
    Run r = run(kSmallCapture + "--frames 1 -o " + dir / "file/frames");
    CHECK(r.status == 1);
    CHECK(lines(r.output) == 1);
    CHECK(r.output.rfind("inkwell: cannot create directory '" + dir / "file/frames" + "'", 0) == 0);
}
