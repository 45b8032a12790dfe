// The public API (include/inkwell/inkwell.h) as an application uses it: errors as inkwell::Error, notes through
// a Reporter, a device adopted from the application, and frames recorded into the application's own command
// buffer and image, which must show what the offscreen Renderer shows.
#include "inkwell/inkwell.h"

#include "draw/render_style.h"
#include "draw/renderer.h"
#include "gpu/resources.h"
#include "gpu_fixture.h"
#include "surface/shapes.h"
#include "temp_dir.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace {

std::string asset(const char* name) { return std::string(INKWELL_SOURCE_DIR) + "/" + name; }

// A sphere of radius ½ as oriented points (the fit interpolates it closely).
void spherePoints(std::vector<inkwell::Vec3>& positions, std::vector<inkwell::Vec3>& normals) {
    for (const Eigen::Vector3d& p : ink::sphereAxisPoints().positions) {
        positions.push_back({p.x(), p.y(), p.z()});
        normals.push_back({p.x(), p.y(), p.z()});
    }
}

// The sphere, fitted.
inkwell::Model sphereModel() {
    std::vector<inkwell::Vec3> positions, normals;
    spherePoints(positions, normals);
    return inkwell::Model::fit(positions, normals);
}

// The test's device, adopted.
inkwell::AdoptedDevice adopted(const GpuFixture& gpu) {
    return {gpu.ctx.instance, gpu.ctx.physicalDevice, gpu.ctx.device, gpu.ctx.queue, gpu.ctx.queueFamily};
}

size_t inked(const inkwell::Image& image) {
    size_t n = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4) n += image.rgba[i] < 128;
    return n;
}

// Of 64 directions from the centre of the inked pixels' box, those where the outline of a round shape is inked: a
// pixel within 2 of the box's half-width from the centre.
int outlinedDirections(const inkwell::Image& image) {
    int x0 = int(image.width), y0 = int(image.height), x1 = -1, y1 = -1;
    for (int y = 0; y < int(image.height); ++y)
        for (int x = 0; x < int(image.width); ++x)
            if (image.rgba[(size_t(y) * image.width + x) * 4] < 128)
                x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    if (x1 < x0) return 0;
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1), r = 0.25 * (x1 - x0 + y1 - y0);
    int found = 0;
    for (int k = 0; k < 64; ++k) {
        const double a = 2 * M_PI * k / 64;
        bool ink = false;
        for (double d = r - 2; d <= r + 0.5 && !ink; d += 0.5) {
            const int x = int(cx + d * std::cos(a) + 0.5), y = int(cy + d * std::sin(a) + 0.5);
            ink = x >= 0 && y >= 0 && x < int(image.width) && y < int(image.height) &&
                  image.rgba[(size_t(y) * image.width + x) * 4] < 128;
        }
        found += ink;
    }
    return found;
}

// The application's colour image and a host-visible copy of it, for frames a FrameRecorder records.
struct AppTarget {
    ink::Context& ctx;
    uint32_t size;
    ink::Image image;
    ink::Buffer readback;
    AppTarget(ink::Context& c, uint32_t s) : ctx(c), size(s) {
        image = ink::createImage(ctx, size, size, VK_FORMAT_R8G8B8A8_UNORM,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT);
        readback = ink::createBuffer(ctx, VkDeviceSize(size) * size * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     ink::MemoryUse::Readback);
    }
    ~AppTarget() {
        ink::destroyBuffer(ctx, readback);
        ink::destroyImage(ctx, image);
    }
    // Records frame slot `frame` into one command buffer, submits it, waits, and reads the image back.
    // With `capture`, the recorder copies the drawing into its own buffer too (FrameRecorder::captured).
    inkwell::Image record(inkwell::FrameRecorder& recorder, const inkwell::Camera& camera, uint32_t frame,
                          bool capture = false, bool traceContours = true) {
        ink::submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            inkwell::FrameTarget t{image.image,
                                   image.view,
                                   {size, size},
                                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                                   capture};
            recorder.record(cmd, camera, t, frame, traceContours);
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {size, size, 1};
            vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer, 1, &region);
            ink::stageBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                              VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
        });
        inkwell::Image out{size, size, std::vector<uint8_t>(size_t(size) * size * 4)};
        std::memcpy(out.rgba.data(), readback.mapped, out.rgba.size());
        return out;
    }
};

}  // namespace

TEST_CASE("api: a fitted sphere evaluates as the sphere, and bad input is an inkwell::Error with a sentence" *
          doctest::test_suite("unit")) {
    std::vector<inkwell::Vec3> positions, normals;
    spherePoints(positions, normals);
    inkwell::Model model = inkwell::Model::fit(positions, normals);
    CHECK(model.report().controlPoints == positions.size());
    // sphereAxisPoints: radius 0.5.
    CHECK(model.value({0, 0, 0}) < 0);  // inside
    CHECK(model.value({2, 0, 0}) > 0);  // outside
    CHECK(std::abs(model.value({0.3, 0.4, 0})) < 1e-2 * std::abs(model.value({2, 0, 0})));
    inkwell::Vec3 g = model.gradient({0.3, 0.4, 0});
    double norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    CHECK(std::acos((0.6 * g[0] + 0.8 * g[1]) / norm) < 0.05);  // along the outward normal

    normals[3] = {0, 0, 0};
    CHECK_THROWS_WITH_AS(inkwell::Model::fit(positions, normals),
                         "point 3 has a non-finite coordinate or a zero normal", inkwell::Error);
    normals.pop_back();
    CHECK_THROWS_AS(inkwell::Model::fit(positions, normals), inkwell::Error);
    CHECK_THROWS_WITH_AS(inkwell::Model::load(asset("no-such-model.obj")), doctest::Contains("no-such-model.obj"),
                         inkwell::Error);
    inkwell::ModelOptions tooMany;
    tooMany.controlPoints = 100000;
    tooMany.method = inkwell::FitMethod::Global;
    CHECK_THROWS_WITH_AS(inkwell::Model::load(asset("assets/bunny.obj"), tooMany), doctest::Contains("4000"),
                         inkwell::Error);
    tooMany.controlPoints = 3000000;
    tooMany.method = inkwell::FitMethod::PartitionOfUnity;
    CHECK_THROWS_WITH_AS(inkwell::Model::load(asset("assets/bunny.obj"), tooMany), doctest::Contains("2000000"),
                         inkwell::Error);
}

TEST_CASE("api: notes reach the Reporter, and nothing else is said" * doctest::test_suite("unit")) {
    std::vector<std::string> notes;
    inkwell::Reporter reporter;
    reporter.note = [&](const std::string& line) { notes.push_back(line); };
    inkwell::ModelOptions options;
    options.controlPoints = 200;
    inkwell::Model model = inkwell::Model::load(asset("assets/bunny.obj"), options, reporter);
    CHECK(model.report().controlPoints == 200);
    CHECK(model.report().inputPoints > 1000);
    // Saved and loaded back with a control-point count: ignored, with a note.
    TempDir dir;
    std::string path = dir / "model.hrbf";
    model.save(path);
    inkwell::Model loaded = inkwell::Model::load(path, options, reporter);
    CHECK(loaded.report().controlPoints == 200);
    // The .hrbf file holds the partition of unity in float, as the device draws it: the value moves by rounding.
    CHECK(loaded.value({0, 0.1, 0}) == doctest::Approx(model.value({0, 0.1, 0})).epsilon(1e-5));
    REQUIRE(!notes.empty());
    CHECK(notes.back().find("ignored") != std::string::npos);
}

TEST_CASE("api: an adopted device draws into the application's own image what the Renderer draws" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;  // the application's instance and device, with validation
    inkwell::Device device(adopted(gpu));
    CHECK(device.name() == gpu.ctx.properties.deviceName);
    inkwell::DrawingOptions options;
    options.levels = 5;
    inkwell::Drawing drawing(device, sphereModel(), options);
    std::vector<inkwell::Point> points = drawing.points();
    REQUIRE(points.size() > 1000);
    for (const inkwell::Point& p : {points.front(), points.back()}) {
        CHECK(std::abs(std::hypot(p.position[0], p.position[1], p.position[2]) - 0.5) < 0.01);  // on the sphere
        CHECK(p.rank >= 0.0f);
        CHECK(p.rank < 1.0f);
    }

    const uint32_t size = 160;
    inkwell::Look look;
    look.supersample = 1;
    look.ink = {0.1f, 0.2f, 0.6f, 1.0f};
    inkwell::Camera camera;
    camera.azimuthDeg = 70;
    inkwell::Image offscreen;
    TempDir dir;
    const std::string svgRenderer = dir / "renderer.svg", svgRecorder = dir / "recorder.svg";
    inkwell::Page page = inkwell::Page::named("100x100mm");
    page.marginMm = 5;
    {
        inkwell::Renderer renderer(drawing, size, size, look);
        offscreen = renderer.render(camera);
        // The frame's marks as vectors: one pen, its paths ordered.
        std::vector<inkwell::PenLayer> layers = renderer.writeVector(svgRenderer, page);
        REQUIRE(layers.size() == 1);
        CHECK(layers[0].pen == 1);
        CHECK(layers[0].name == "stipple");
        CHECK(layers[0].paths > 100);
        CHECK(layers[0].travelAfterMm < layers[0].travelBeforeMm);
        CHECK_THROWS_WITH_AS(renderer.writeVector(dir / "drawing.eps", page),
                             doctest::Contains("is not an .svg or .pdf file"), inkwell::Error);
        CHECK_THROWS_WITH_AS(inkwell::Page::named("huge"), doctest::Contains("page 'huge' is not"), inkwell::Error);
    }
    REQUIRE(inked(offscreen) > 200);

    // The application's frame: its image, its command buffer, its submission; two frames in flight.
    inkwell::Image recorded;
    {
        AppTarget target(gpu.ctx, size);
        inkwell::FrameRecorder recorder(drawing, VK_FORMAT_R8G8B8A8_UNORM, 2, look);
        for (uint32_t frame : {0u, 1u}) {
            recorded = target.record(recorder, camera, frame);
            CHECK(recorded.rgba == offscreen.rgba);  // the same passes, the same pixels
        }
        CHECK_THROWS_AS(recorder.record(VK_NULL_HANDLE, camera, {}, 2), inkwell::Error);
        // The application's frame gives the Renderer's marks, to the byte.
        recorder.writeVector(svgRecorder, 1, page);
        std::ifstream a(svgRenderer), b(svgRecorder);
        std::string textA((std::istreambuf_iterator<char>(a)), {}), textB((std::istreambuf_iterator<char>(b)), {});
        CHECK(textA.size() > 1000);
        CHECK(textA == textB);
        CHECK(textA.find("stroke=\"#1a3399\"") != std::string::npos);  // the ink's colour
    }
    // The ink colour came through: the darkest pixel is the ink's.
    uint8_t bluest = 0;
    for (size_t i = 0; i < recorded.rgba.size(); i += 4)
        if (recorded.rgba[i] < 60) bluest = std::max(bluest, recorded.rgba[i + 2]);
    CHECK(bluest > 120);
    gpu.requireNoValidationErrors();
}

TEST_CASE("api: a drawing's contour is the sphere's circle seen from the eye, and its hatching lies on the surface" *
          doctest::test_suite("gpu")) {
    std::vector<inkwell::Vec3> positions, normals;
    for (const Eigen::Vector3d& p : ink::spherePoints(300, 0.5).positions) {
        positions.push_back({p.x(), p.y(), p.z()});
        normals.push_back({p.x(), p.y(), p.z()});
    }
    inkwell::Model model = inkwell::Model::fit(positions, normals);
    inkwell::DeviceOptions validated;
    validated.validation = true;
    inkwell::Device device(validated);
    inkwell::DrawingOptions options;
    options.levels = 3;
    options.contours = options.hatching = true;
    options.hatchFamilies = 3;
    inkwell::Drawing drawing(device, model, options);
    inkwell::Camera camera;
    camera.azimuthDeg = 0;  // the eye on +z, 1.6 diagonals (of the sphere's box, √3) away
    camera.elevationDeg = 0;
    const double r = 0.5, eye = 1.6 * std::sqrt(3.0);
    std::vector<inkwell::Polyline> contours = drawing.contours(camera);
    REQUIRE(contours.size() == 1);  // one closed circle, no cusps
    CHECK(contours[0].closed);
    CHECK(contours[0].points.size() > 50);
    for (const inkwell::Vec3& p : contours[0].points) {
        // On the sphere, where its tangent plane holds the eye: z = r²/eye (in the fit's accuracy).
        CHECK(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) == doctest::Approx(r).epsilon(2e-3));
        CHECK(p[2] == doctest::Approx(r * r / eye).epsilon(2e-2));
    }
    std::vector<inkwell::Polyline> hatching = drawing.hatching();
    REQUIRE(hatching.size() > 20);
    size_t families[3] = {0, 0, 0};
    for (const inkwell::Polyline& s : hatching) {
        REQUIRE(s.family < 3);
        ++families[s.family];
        for (const inkwell::Vec3& p : s.points) CHECK(std::abs(model.value(p)) < 1e-5);
    }
    CHECK(families[0] > 10);
    CHECK(families[1] > 10);
    CHECK(families[2] > 10);  // the third, diagonal family
    inkwell::Look look;
    look.dots = false;
    inkwell::Image image = inkwell::Renderer(drawing, 128, 128, look).render(camera);
    size_t inked = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4) inked += image.rgba[i] < 128;
    CHECK(inked > 200);  // the circle alone is about 2π·40 pixels of pen
    {
        // The diagonal family inks only the darkest tones: against the same drawing with two families, the ink it
        // adds lies on the side turned from the light (the upper left, following the camera), none towards it.
        inkwell::DrawingOptions two = options;
        two.hatchFamilies = 2;
        inkwell::Drawing crossed(device, model, two);
        const inkwell::Image a = inkwell::Renderer(crossed, 256, 256, look).render(camera);
        const inkwell::Image b = inkwell::Renderer(drawing, 256, 256, look).render(camera);
        REQUIRE(a.rgba.size() == b.rgba.size());
        // The ink added, in pixels of full ink (summed, not thresholded: antialiasing differs between devices, and
        // the thin diagonal strokes crossed mid-grey on 24 pixels here, 9 on an H200).
        double lit = 0, dark = 0;
        for (uint32_t y = 0; y < 256; ++y)
            for (uint32_t x = 0; x < 256; ++x) {
                const size_t i = 4 * (size_t(y) * 256 + x);
                const double added = std::max(0, int(a.rgba[i]) - int(b.rgba[i])) / 255.0;
                if (x < 128 && y < 128) lit += added;     // the quarter towards the light
                if (x >= 128 && y >= 128) dark += added;  // the quarter turned from it
            }
        MESSAGE("diagonal family: " << dark << " pixels of ink added turned from the light, " << lit << " towards it");
        CHECK(dark > 10);
        CHECK(lit < 0.5);
    }
    look.penWidth = 0;
    CHECK_THROWS_WITH_AS(inkwell::Renderer(drawing, 128, 128, look), "pen widths must be in (0, 32] pixels",
                         inkwell::Error);
    // The hidden lines' defaults are the engine's (the command line's too).
    const ink::RenderStyle engine;
    CHECK(look.hiddenDotSize == engine.hiddenSize);
    CHECK(look.hiddenPenWidth == engine.hiddenPenWidth);
    CHECK(look.hiddenOpacity == engine.hiddenInk.a);
    look.penWidth = 2;
    look.hiddenPenWidth = 40;
    CHECK_THROWS_WITH_AS(inkwell::Renderer(drawing, 128, 128, look), "pen widths must be in (0, 32] pixels",
                         inkwell::Error);
    look.hiddenPenWidth = 1.2f;
    look.hiddenOpacity = -0.5f;
    CHECK_THROWS_WITH_AS(inkwell::Renderer(drawing, 128, 128, look), "hiddenOpacity must be in [0, 1]", inkwell::Error);
    look.hiddenOpacity = 0.45f;
    look.hiddenDotSize = 0;
    CHECK_THROWS_WITH_AS(inkwell::Renderer(drawing, 128, 128, look), "hiddenDotSize must be in (0, 64] pixels",
                         inkwell::Error);
    CHECK(device.validationErrors() == 0);
}

namespace {

// Whether a public object hands out its internals (it must not: the API is what applications can rely on).
template <class T>
concept ExposesImpl = requires(const T& t) {
    t.impl();
};

}  // namespace

TEST_CASE("api: the public objects hide their internals, and the version macros are the project's" *
          doctest::test_suite("unit")) {
    CHECK_FALSE(ExposesImpl<inkwell::Model>);
    CHECK_FALSE(ExposesImpl<inkwell::Device>);
    CHECK_FALSE(ExposesImpl<inkwell::Drawing>);
    CHECK_FALSE(ExposesImpl<inkwell::Renderer>);
    CHECK_FALSE(ExposesImpl<inkwell::FrameRecorder>);
    CHECK(std::string(INKWELL_VERSION_STRING) == INKWELL_PROJECT_VERSION);  // CMakeLists.txt's project(VERSION)
    CHECK(std::to_string(INKWELL_VERSION_MAJOR) + "." + std::to_string(INKWELL_VERSION_MINOR) + "." +
              std::to_string(INKWELL_VERSION_PATCH) ==
          INKWELL_PROJECT_VERSION);
    static_assert(INKWELL_VERSION ==
                  INKWELL_VERSION_MAJOR * 10000 + INKWELL_VERSION_MINOR * 100 + INKWELL_VERSION_PATCH);
}

TEST_CASE("api: Drawing::refine under a live Renderer and FrameRecorder: both draw the new sets, validation clean" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    inkwell::Device device(adopted(gpu));
    inkwell::DrawingOptions options;
    options.levels = 3;
    inkwell::Drawing drawing(device, sphereModel(), options);
    const uint32_t size = 96;
    inkwell::Look look;
    look.supersample = 1;
    inkwell::Camera camera;
    inkwell::Renderer renderer(drawing, size, size, look);
    inkwell::FrameRecorder recorder(drawing, VK_FORMAT_R8G8B8A8_UNORM, 1, look);
    AppTarget app(gpu.ctx, size);
    const inkwell::Image before = renderer.render(camera);
    CHECK(app.record(recorder, camera, 0).rgba == before.rgba);
    REQUIRE(drawing.sets() == 1);

    // Two sets now, and more levels: the renderer and the recorder made before draw them, as new ones do.
    options.levels = 4;
    options.style = inkwell::Style::Both;
    drawing.refine(options);
    REQUIRE(drawing.sets() == 2);
    CHECK(renderer.dotsDrawn() == 0);  // nothing drawn of the new sets yet
    TempDir dir;
    CHECK_THROWS_WITH_AS(renderer.writeVector(dir / "none.svg"), doctest::Contains("no frame"), inkwell::Error);
    CHECK_FALSE(std::filesystem::exists(dir / "none.svg"));
    const inkwell::Image after = renderer.render(camera);
    CHECK(renderer.dotsDrawn() > 0);
    CHECK(after.rgba != before.rgba);
    CHECK(after.rgba == inkwell::Renderer(drawing, size, size, look).render(camera).rgba);
    CHECK(app.record(recorder, camera, 0).rgba == after.rgba);
    gpu.requireNoValidationErrors();
}

TEST_CASE("api: every Look value is checked, with one error naming the field and its range" *
          doctest::test_suite("gpu")) {
    inkwell::DeviceOptions validated;
    validated.validation = true;
    inkwell::Device device(validated);
    std::vector<inkwell::Vec3> positions, normals;
    spherePoints(positions, normals);
    inkwell::DrawingOptions options;
    options.levels = 1;
    inkwell::Drawing drawing(device, inkwell::Model::fit(positions, normals), options);
    struct Case {
        void (*spoil)(inkwell::Look&);
        const char* message;
    };
    const Case cases[] = {
        {[](inkwell::Look& l) { l.dotSize = -1; }, "dotSize must be in (0, 64] pixels"},
        {[](inkwell::Look& l) { l.dotSize = NAN; }, "dotSize must be in (0, 64] pixels"},
        {[](inkwell::Look& l) { l.silhouetteSize = 100; }, "silhouetteSize must be in (0, 64] pixels"},
        {[](inkwell::Look& l) { l.tau = 1; }, "tau must be in [0, 1)"},
        {[](inkwell::Look& l) { l.toneGamma = -0.5f; }, "toneGamma must be in [0, 16]"},
        {[](inkwell::Look& l) { l.inkDensity = INFINITY; }, "inkDensity must be in [0, 100]"},
        {[](inkwell::Look& l) { l.ink[1] = 1.5f; }, "ink colour components must be in [0, 1]"},
        {[](inkwell::Look& l) { l.paper[3] = -1; }, "paper colour components must be in [0, 1]"},
        {[](inkwell::Look& l) {
             l.light = {0, 0, 0};
         },
         "light must be a finite, non-zero vector"},
        {[](inkwell::Look& l) {
             l.light = {NAN, 1, 0};
         },
         "light must be a finite, non-zero vector"},
        // 160 × 2²⁷ wrapped around 2³² to a 0×0 image.
        {[](inkwell::Look& l) { l.supersample = 1u << 27; }, "supersample must be 1 to 4"},
        {[](inkwell::Look& l) { l.supersample = 0; }, "supersample must be 1 to 4"},
    };
    for (const Case& c : cases) {
        inkwell::Look look;
        c.spoil(look);
        CAPTURE(c.message);
        CHECK_THROWS_WITH_AS(inkwell::Renderer(drawing, 160, 160, look), c.message, inkwell::Error);
        CHECK_THROWS_WITH_AS(inkwell::FrameRecorder(drawing, VK_FORMAT_R8G8B8A8_UNORM, 1, look), c.message,
                             inkwell::Error);
        inkwell::Renderer renderer(drawing, 32, 32);
        CHECK_THROWS_WITH_AS(renderer.setLook(look), c.message, inkwell::Error);
    }
    CHECK(device.validationErrors() == 0);
    // The engine's own size check (the commands') counts in 64 bits: 160 × 2²⁷ supersampling is refused, not
    // wrapped around to a 0×0 image.
    GpuFixture gpu;
    CHECK_THROWS_WITH_AS(ink::checkOffscreenSize(gpu.ctx, 160, 160, 1u << 27), doctest::Contains("is outside 1.."),
                         inkwell::Error);
}

TEST_CASE("api: firstView finds the bunny's up axis and frames it to fill 85% of the image" *
          doctest::test_suite("gpu")) {
    inkwell::ModelOptions few;
    few.controlPoints = 150;
    inkwell::Model model = inkwell::Model::load(asset("assets/bunny.obj"), few);
    inkwell::Device device;
    inkwell::DrawingOptions options;
    options.levels = 3;
    inkwell::Drawing drawing(device, model, options);
    CHECK(drawing.firstUp() == inkwell::Up::Y);
    const inkwell::Camera camera = drawing.firstView(1.0f);
    CHECK(camera.up == inkwell::Up::Y);
    CHECK((camera.elevationDeg == 15.0f || camera.elevationDeg == 30.0f));
    CHECK(camera.distance < inkwell::Camera{}.distance);  // nearer than the fixed default: the model fills more
    // Deterministic, and about a given axis too.
    const inkwell::Camera again = drawing.firstView(inkwell::Up::Y, 1.0f);
    CHECK(again.azimuthDeg == camera.azimuthDeg);
    CHECK(again.distance == camera.distance);
    CHECK_THROWS_WITH_AS(drawing.firstView(0.0f), "firstView: aspect (width / height) must be in [1/16384, 16384]",
                         inkwell::Error);
    CHECK(drawing.firstView(8192.0f).distance > 0);  // render --size 8192 1
    CHECK(drawing.firstView(1.0f / 8192).distance > 0);
    // The rendered ink's bounding box: 80-90% of the image's side.
    inkwell::Renderer renderer(drawing, 256, 256);
    const inkwell::Image image = renderer.render(camera);
    uint32_t x0 = 256, y0 = 256, x1 = 0, y1 = 0;
    for (uint32_t y = 0; y < 256; ++y)
        for (uint32_t x = 0; x < 256; ++x)
            if (image.rgba[(size_t(y) * 256 + x) * 4] < 128) {
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    REQUIRE(x1 > x0);
    const double fill = std::max(x1 - x0 + 1, y1 - y0 + 1) / 256.0;
    CHECK(fill >= 0.80);
    CHECK(fill <= 0.90);
}

// ---- What the apps use (issue 28: the command line and the viewer on the public API alone) --------------------

TEST_CASE("api: prepare and apply refine in two halves under a live FrameRecorder, whose captured frame is its image" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    inkwell::Device device(adopted(gpu));
    const inkwell::AdoptedDevice handles = device.handles();
    CHECK(handles.device == gpu.ctx.device);
    CHECK(handles.queue == gpu.ctx.queue);
    inkwell::DrawingOptions options;
    options.levels = 3;
    inkwell::Drawing drawing(device, sphereModel(), options);
    const uint32_t size = 96;
    inkwell::Look look;
    look.supersample = 1;
    inkwell::Camera camera;
    inkwell::FrameRecorder recorder(drawing, VK_FORMAT_R8G8B8A8_UNORM, 2, look);
    inkwell::Renderer renderer(drawing, size, size, look);  // made before the contour is turned on (below)
    AppTarget app(gpu.ctx, size);
    CHECK_THROWS_WITH_AS(recorder.captured(1),
                         doctest::Contains("last recording was not made with FrameTarget::capture"), inkwell::Error);
    const inkwell::Image before = app.record(recorder, camera, 1, true);
    CHECK(recorder.captured(1).rgba == before.rgba);  // the recorder's copy is the application's image
    CHECK(before.rgba == inkwell::Renderer(drawing, size, size, look).render(camera).rgba);
    const uint64_t points = drawing.pointCount();

    // The first half leaves the drawing as it was; the second puts the new sets in place.
    options.levels = 4;
    CHECK(drawing.work(options) == inkwell::Drawing::Work::Sets);
    CHECK_FALSE(options == drawing.options());
    inkwell::Drawing::Pending pending = drawing.prepare(options);
    CHECK(pending.refined());
    CHECK(pending.traced());  // the new sets' pen lines (none asked: their seeds only)
    CHECK(pending.seconds() > 0);
    CHECK(drawing.pointCount() == points);
    CHECK(drawing.options().levels == 3);
    CHECK(app.record(recorder, camera, 0).rgba == before.rgba);
    drawing.apply(std::move(pending));
    CHECK(drawing.options() == options);
    CHECK(drawing.options().levels == 4);
    CHECK(drawing.pointCount() > 3 * points);
    const inkwell::Image after = app.record(recorder, camera, 0, true);
    CHECK(after.rgba != before.rgba);
    CHECK(recorder.captured(0).rgba == after.rgba);
    CHECK(after.rgba == inkwell::Renderer(drawing, size, size, look).render(camera).rgba);
    CHECK_THROWS_WITH_AS(drawing.apply(inkwell::Drawing::Pending()), doctest::Contains("nothing prepared"),
                         inkwell::Error);
    // A Pending applies to the drawing it was prepared for, as it was then.
    inkwell::Drawing other(device, sphereModel(), options);
    CHECK_THROWS_WITH_AS(other.apply(drawing.prepare(options)), doctest::Contains("prepared for another drawing"),
                         inkwell::Error);
    inkwell::Drawing::Pending stale = other.prepare(options);
    other.refine(options);
    CHECK_THROWS_AS(other.apply(std::move(stale)), inkwell::Error);
    CHECK_THROWS_WITH_AS(inkwell::FrameRecorder(drawing, VK_FORMAT_R8G8B8A8_UNORM, 0, look),
                         "framesInFlight must be 1 to 16", inkwell::Error);

    // Contours on: traced over the current sets (no new sets); then off: nothing to make or trace at all. With the
    // contour the pen draws the outline, and the renderer made before draws no silhouette dots (api::toStyle).
    const auto outlineDots = [&] {
        renderer.render(camera);
        size_t dots = 0;
        for (const auto& set : nlohmann::json::parse(renderer.statsJson())) dots += set["outline_dots"].get<size_t>();
        return dots;
    };
    CHECK(outlineDots() > 10);
    options.contours = true;
    CHECK(drawing.work(options) == inkwell::Drawing::Work::Lines);
    pending = drawing.prepare(options);
    CHECK_FALSE(pending.refined());
    CHECK(pending.traced());
    drawing.apply(std::move(pending));
    CHECK(drawing.pointCount() > 3 * points);
    CHECK(outlineDots() == 0);
    const inkwell::Image outlined = app.record(recorder, camera, 1);
    CHECK_THROWS_AS(recorder.captured(1), inkwell::Error);  // recorded without capture since: its buffer is gone
    CHECK(outlined.rgba != after.rgba);
    CHECK(outlinedDirections(outlined) >= 60);  // the contour's pen, without the silhouette dots
    CHECK(outlinedDirections(after) >= 60);     // the silhouette dots, without the pen
    CHECK(drawing.contourSeconds() > 0);
    options.contours = false;
    CHECK(drawing.work(options) == inkwell::Drawing::Work::None);
    pending = drawing.prepare(options);
    CHECK_FALSE(pending.refined());
    CHECK_FALSE(pending.traced());
    drawing.apply(std::move(pending));
    CHECK(app.record(recorder, camera, 1).rgba == after.rgba);
    CHECK(outlineDots() > 10);
    gpu.requireNoValidationErrors();
}

TEST_CASE("api: Samples from the device and the CPU, a Plot written twice, and the stats as JSON" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    inkwell::Device device(adopted(gpu));
    const inkwell::Model model = sphereModel();
    CHECK(model.statsJson().find("\"method\":\"pu\"") != std::string::npos);
    inkwell::DrawingOptions options;
    options.levels = 5;
    const inkwell::Samples onDevice(&device, model, options, true), onCpu(nullptr, model, options, true);
    REQUIRE(onDevice.size() > 500);
    // The CPU reference refines and selects as the device does (the same count on lavapipe; a GPU's float may
    // keep or drop a candidate or two differently).
    CHECK(double(onCpu.size()) == doctest::Approx(double(onDevice.size())).epsilon(0.02));
    for (const inkwell::Samples* samples : {&onDevice, &onCpu}) {
        CHECK(samples->refined().size() > samples->size());  // the stipples are a selection of the refined points
        for (const inkwell::Point& p : samples->points())
            REQUIRE(std::abs(std::hypot(p.position[0], p.position[1], p.position[2]) - 0.5) < 0.01);
    }
    CHECK(onCpu.statsJson().find("\"device\":\"cpu\"") != std::string::npos);
    CHECK_THROWS_WITH_AS(inkwell::Samples(nullptr, model, options).refined(), doctest::Contains("keepRefined"),
                         inkwell::Error);
    CHECK(onDevice.statsJson(true).find("\"spacing\"") != std::string::npos);
    options.style = inkwell::Style::Both;
    CHECK_THROWS_WITH_AS(inkwell::Samples(nullptr, model, options), doctest::Contains("one set"), inkwell::Error);

    inkwell::Drawing drawing(device, model, {});
    inkwell::Renderer renderer(drawing, 128, 128, {});
    CHECK_THROWS_WITH_AS(renderer.plot(), doctest::Contains("no frame"), inkwell::Error);
    renderer.render({});
    CHECK(renderer.statsJson().find("\"front_dots\"") != std::string::npos);
    CHECK(drawing.statsJson().find("\"refine\"") != std::string::npos);
    TempDir dir;
    const inkwell::Plot plot = renderer.plot();
    plot.write(dir / "a.svg");
    renderer.writeVector(dir / "b.svg");
    auto slurp = [](const std::string& path) {
        std::ifstream in(path);
        return std::string((std::istreambuf_iterator<char>(in)), {});
    };
    CHECK(slurp(dir / "a.svg").size() > 1000);
    CHECK(slurp(dir / "a.svg") == slurp(dir / "b.svg"));
    REQUIRE(plot.layers().size() == 1);
    CHECK(plot.layers()[0].pathsGiven >= plot.layers()[0].paths);
    CHECK(plot.statsJson().find("\"layers\"") != std::string::npos);
    CHECK(inkwell::Plot::isVectorPath("x.PDF"));
    CHECK_FALSE(inkwell::Plot::isVectorPath("x.png"));
    CHECK_THROWS_WITH_AS(plot.write(dir / "c.eps"), doctest::Contains("is not an .svg or .pdf file"), inkwell::Error);
    gpu.requireNoValidationErrors();
}

TEST_CASE("api: images compared, cameras panned, up axes named, model options checked up front" *
          doctest::test_suite("unit")) {
    inkwell::Image a{4, 2, std::vector<uint8_t>(4 * 2 * 4, 200)}, b = a;
    CHECK(inkwell::compareImages(a, b).differingPixels == 0);
    b.rgba[5] = 250;  // one channel of the second pixel, 50 off
    inkwell::ImageDifference d = inkwell::compareImages(a, b);
    CHECK(d.differingPixels == 1);
    CHECK(d.pixels == 8);
    CHECK(d.maxAbsDiff == 50);
    CHECK(d.sameSize);
    CHECK(inkwell::compareImages(a, b, 50).differingPixels == 0);
    CHECK(inkwell::differenceImage(a, b).width == 4);
    inkwell::Image c{2, 2, std::vector<uint8_t>(16, 0)};
    CHECK_FALSE(inkwell::compareImages(a, c).sameSize);
    CHECK_THROWS_WITH_AS(inkwell::compareImages(a, b, 256), doctest::Contains("threshold must be in [0, 255]"),
                         inkwell::Error);
    inkwell::Image broken{4, 4, std::vector<uint8_t>(12)};  // 12 bytes, not 64
    CHECK_THROWS_WITH_AS(inkwell::compareImages(a, broken), doctest::Contains("width × height × 4 bytes"),
                         inkwell::Error);
    CHECK_THROWS_AS(inkwell::differenceImage(broken, a), inkwell::Error);
    TempDir dir;
    CHECK_THROWS_AS(broken.writePng(dir / "broken.png"), inkwell::Error);
    CHECK_FALSE(std::filesystem::exists(dir / "broken.png"));

    inkwell::Camera camera;
    const std::array<float, 3> eye = camera.eye();
    CHECK(std::hypot(eye[0], eye[1], eye[2]) == doctest::Approx(camera.distance));
    camera.pan(100, 0, 1000);  // a tenth of the view to the right: the target moves across the view
    const std::array<float, 3> moved = camera.target;
    const float along = moved[0] * eye[0] + moved[1] * eye[1] + moved[2] * eye[2];
    CHECK(std::hypot(moved[0], moved[1], moved[2]) > 0.05f);
    CHECK(std::abs(along) < 1e-5f);  // in the view plane

    for (inkwell::Up up :
         {inkwell::Up::X, inkwell::Up::NegX, inkwell::Up::Y, inkwell::Up::NegY, inkwell::Up::Z, inkwell::Up::NegZ})
        CHECK(inkwell::parseUp(inkwell::upName(up)) == up);
    CHECK(inkwell::parseUp("+z") == inkwell::Up::Z);
    CHECK_THROWS_WITH_AS(inkwell::parseUp("w"), doctest::Contains("is not one of x, -x, y, -y, z, -z"), inkwell::Error);
    CHECK(std::string(inkwell::styleName(inkwell::Style::Both)) == "both");
    inkwell::ModelOptions options;
    options.creaseAngleDeg = 0;
    CHECK_THROWS_WITH_AS(inkwell::checkModelOptions(options), doctest::Contains("crease angle"), inkwell::Error);
}
