#include "base/image.h"
#include "draw/renderer.h"
#include "gpu_fixture.h"
#include "refine/refine.h"
#include "surface/hrbf.h"
#include "surface/model.h"
#include "surface/shapes.h"

#include <doctest/doctest.h>

#include <cmath>

using Eigen::Vector3d;

namespace {

ink::Model bunny(size_t controlPoints) {
    return ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {controlPoints});
}

}  // namespace

TEST_CASE("gpu: seeds projected on the device match the CPU evaluation, with zero validation errors" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = bunny(200);
    ink::RefineOptions options;
    options.levels = 0;
    options.seeds = ink::SeedMode::Grid;
    options.grid = 12;
    Refinement refined(gpu.ctx, model.surface, options);
    std::vector<ink::PointRecord> points = ink::readPoints(gpu.ctx, refined.r);
    auto stats = ink::readLevelStats(gpu.ctx, refined.r);

    REQUIRE(points.size() > 100);
    CHECK(stats[0].kept == points.size());
    for (const auto& p : points) {
        Vector3d x(p.position[0], p.position[1], p.position[2]), g;
        double f = model.surface.eval(x, g);
        CHECK(std::abs(f) / g.norm() < 2e-5);  // on the surface, by the CPU's double evaluation
        Vector3d n(p.normal[0], p.normal[1], p.normal[2]);
        CHECK(n.norm() == doctest::Approx(1.0).epsilon(1e-5));
        CHECK(n.dot(g.normalized()) > 0.9999);
    }
    gpu.requireNoValidationErrors();
}

TEST_CASE("gpu: the bunny renders as dots on white paper" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = bunny(200);
    ink::RefineOptions options;
    options.levels = 2;
    Refinement refined(gpu.ctx, model.surface, options);
    ink::OffscreenRenderer renderer(gpu.ctx, 256, 256, ink::RenderStyle{}, {&refined.r});
    ink::RgbaImage image = renderer.render(ink::Camera{});
    REQUIRE(image.width == 256);
    size_t dark = 0, white = 0;
    for (size_t i = 0; i < image.pixels.size(); i += 4) {
        if (image.pixels[i] < 128) ++dark;
        if (image.pixels[i] == 255) ++white;
    }
    CHECK(dark > 250);             // there is a drawing (about 900 stipples of 4200 candidates)
    CHECK(white > 256 * 256 / 2);  // on mostly white paper
    // The corners are paper: the camera frames the model.
    CHECK(image.pixels[0] == 255);
    CHECK(image.pixels[image.pixels.size() - 4] == 255);
    gpu.requireNoValidationErrors();
}

TEST_CASE("gpu: each pixel takes the ink once — paper, ink or hidden ink over paper — and frames repeat exactly" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::fitModel(ink::torusPoints(24, 12), {});
    ink::RefineOptions options;
    options.levels = 3;
    Refinement refined(gpu.ctx, model.surface, options);
    ink::RenderStyle style;
    style.supersample = 1;
    style.hiddenLines = true;
    style.frontSize = style.hiddenSize = 3.0f;  // large dots overlap a lot
    ink::Camera camera;
    // From 65° above, the front of the tube hides much of the hole's inner silhouette: 138 hidden pixels on lavapipe.
    // (From 35° the hidden dots lay among the visible outline's dots, whose strokes now join across them: 5.)
    camera.elevationDeg = 65.0f;
    ink::OffscreenRenderer renderer(gpu.ctx, 200, 200, style, {&refined.r});
    ink::RgbaImage first = renderer.render(camera);
    uint32_t dots = renderer.drawnDots();
    ink::RgbaImage second = renderer.render(camera);
    CHECK(first.pixels == second.pixels);
    // Blending the hidden ink once over white paper gives exactly this grey.
    const int grey = int(std::lround(255.0 * (1.0 - double(style.hiddenInk.a))));
    size_t paper = 0, ink = 0, hidden = 0, other = 0;
    for (size_t i = 0; i < first.pixels.size(); i += 4) {
        int v = first.pixels[i];
        if (v == 255)
            ++paper;
        else if (v == 0)
            ++ink;
        else if (std::abs(v - grey) <= 1)
            ++hidden;
        else
            ++other;
    }
    CHECK(other == 0);
    CHECK(ink > 500);
    CHECK(hidden > 20);
    CHECK(paper > 200 * 200 / 2);
    // Every drawn dot inks at least the pixel under its centre; overlapping dots share pixels.
    CHECK(dots > 0);
    CHECK(ink + hidden <= size_t(dots) * 9);
    CHECK(ink + hidden >= size_t(dots) / 4);
    gpu.requireNoValidationErrors();
}
