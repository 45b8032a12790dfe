// Stipples on the page (screen_spacing.h, spacing.comp): the device's screen spacing against its CPU twin, the
// spacing and tone of the drawn dots on a torus whose tone is one everywhere (so that the foreshortening towards
// its silhouettes shows), and dots that stay put as the camera orbits.
#include "draw/page_metrics.h"
#include "draw/renderer.h"
#include "draw/screen_spacing.h"
#include "gpu_fixture.h"
#include "refine/refine.h"
#include "surface/model.h"
#include "surface/shapes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

namespace {

// A torus lit from the camera with a steep tone curve: every front dot away from the outline has darkness
// `ambient`, so that the page should show one even tone from the middle out to the silhouettes.
struct EvenTorus {
    GpuFixture gpu;
    ink::Model model = ink::fitModel(ink::torusPoints(48, 16), {});
    Refinement refined{gpu.ctx, model.surface, ink::RefineOptions{}};
    ink::RenderStyle style;
    EvenTorus() {
        style.light = {0, 0, 1};
        style.lightFollowsCamera = true;
        style.toneGamma = 60.0f;
        style.ambient = 0.12f;
        style.screenSpacing = true;
    }
};

ink::Camera tiltedCamera(float azimuth = 30.0f) {
    ink::Camera camera;
    camera.azimuthDeg = azimuth;
    camera.elevationDeg = 50.0f;
    camera.distance = 1.3f;
    return camera;
}

bool drawnFront(const ink::gpu::Dot& d) {
    return ((d.cls >> 2) & 3u) == ink::gpu::FRONT && d.state == ink::gpu::SPACE_ACCEPTED;
}

// 128-pixel windows of the 1024² page (in the supersampled target's pixels), away from the outline by 8 pixels.
ink::PageMetrics page(const ink::OffscreenRenderer& renderer, const ink::RenderStyle& style, uint32_t size = 1024) {
    const double factor = renderer.supersample();
    return ink::measurePage(renderer.dotList(0), uint32_t(size * factor), uint32_t(size * factor), 128.0 * factor,
                            style.frontSize * factor, 8.0 * factor);
}

// The windows' worst mean NN and clumping, and their coverage against `asked` (fractions of it allowed each way).
void checkPage(const ink::PageMetrics& m, double asked, double minMean, double maxClump, double below, double above) {
    REQUIRE(m.windows.size() >= 8);
    INFO(m.windows.size() << " windows: worst mean NN " << m.worstNearest << " r_max, worst clumping " << m.worstClumped
                          << ", coverage " << m.leastCoverage << ".." << m.mostCoverage << " for " << asked);
    CHECK(m.worstNearest >= minMean);
    CHECK(m.worstClumped <= maxClump);
    CHECK(m.leastCoverage >= (1.0 - below) * asked);
    CHECK(m.mostCoverage <= (1.0 + above) * asked);
}

}  // namespace

TEST_CASE("page: the device's screen spacing accepts exactly the dots its CPU twin does, and moves them as far" *
          doctest::test_suite("gpu")) {
    EvenTorus t;
    t.style.toneGamma = 1.5f;  // a range of tones: radii from small to large
    t.style.ambient = 0.04f;
    t.style.light = {-0.5f, 0.6f, 0.65f};
    t.style.relaxDots = false;  // the greedy's choice where it lies: what the twin starts from
    ink::OffscreenRenderer renderer(t.gpu.ctx, 512, 512, t.style, {&t.refined.r});
    renderer.render(tiltedCamera());
    std::vector<ink::gpu::Dot> device = renderer.dotList(0);
    std::vector<ink::gpu::Dot> cpu = device;
    size_t open = 0;
    for (auto& d : cpu)
        if (d.state != ink::gpu::SPACE_FIXED) d.state = ink::gpu::SPACE_OPEN, ++open;
    REQUIRE(open > 2000);
    const uint32_t extent = 512 * renderer.supersample();
    ink::spaceDotsOnCpu(cpu, extent, extent, renderer.spacing().y);
    size_t same = 0, accepted = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
        same += cpu[i].state == device[i].state;
        accepted += device[i].state == ink::gpu::SPACE_ACCEPTED;
    }
    INFO(open << " open dots, " << accepted << " accepted");
    CHECK(same == cpu.size());
    CHECK(accepted > open / 5);
    CHECK(accepted < open * 3 / 4);

    // The same frame relaxed on the device: each accepted dot (found by its point) where the twin moved it, to within
    // float rounding (the device's division, square root and snorm rounding are its own), and no further than
    // SPACE_RELAX_MAX radii from where the greedy chose it.
    t.style.relaxDots = true;
    renderer.setStyle(t.style);
    renderer.render(tiltedCamera());
    std::vector<ink::gpu::Dot> relaxed = renderer.dotList(0);
    auto byPoint = [](std::vector<ink::gpu::Dot> dots) {
        std::sort(dots.begin(), dots.end(), [](const auto& a, const auto& b) { return a.cls < b.cls; });
        return dots;
    };
    cpu = byPoint(cpu), relaxed = byPoint(relaxed), device = byPoint(device);
    REQUIRE(relaxed.size() == cpu.size());
    size_t agree = 0, moved = 0, beyond = 0;
    double worst = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
        REQUIRE(relaxed[i].cls == cpu[i].cls);
        if (cpu[i].state != ink::gpu::SPACE_ACCEPTED) continue;
        const double apart = glm::length(relaxed[i].pixel - cpu[i].pixel);
        const double from = glm::length(relaxed[i].pixel - device[i].pixel);
        worst = std::max(worst, apart);
        agree += apart <= 1e-3;
        moved += from > 0.05 * device[i].radius;
        beyond += from > ink::gpu::SPACE_RELAX_MAX * device[i].radius * 1.001;
    }
    INFO(agree << " of " << accepted << " accepted dots where the twin put them (worst " << worst << " px), " << moved
               << " moved over a twentieth of their radius, " << beyond << " past the limit");
    CHECK(double(agree) >= 0.995 * double(accepted));
    CHECK(double(moved) >= 0.5 * double(accepted));
    CHECK(beyond == 0);
    t.gpu.requireNoValidationErrors();
}

TEST_CASE("page: one tone on a torus is evenly spaced and evenly inked out to the silhouettes" *
          doctest::test_suite("gpu")) {
    EvenTorus t;
    t.style.relaxDots = false;
    ink::OffscreenRenderer renderer(t.gpu.ctx, 1024, 1024, t.style, {&t.refined.r});
    renderer.render(tiltedCamera());
    const ink::PageMetrics greedy = page(renderer, t.style);
    t.style.relaxDots = true;
    renderer.setStyle(t.style);
    renderer.render(tiltedCamera());
    // The tone asks for kCoverage · darkness (renderer.cpp): 0.5 · 0.12 of the page. Measured on lavapipe: worst
    // window 0.787 (mean 0.814), clumping 0.5%, coverage 0.058..0.064 (the issue asks 0.78: docs/performance.md);
    // the greedy alone 0.760 (mean 0.774) and the rank prefix alone 0.72 with clumps.
    const ink::PageMetrics m = page(renderer, t.style);
    checkPage(m, 0.5 * 0.12, 0.77, 0.02, 0.1, 0.1);
    INFO("mean NN over the windows: greedy " << greedy.meanNearest << ", relaxed " << m.meanNearest);
    CHECK(m.meanNearest >= greedy.meanNearest + 0.02);
    t.gpu.requireNoValidationErrors();
}

TEST_CASE("page: a quarter degree of orbit keeps the spaced dots on their points" * doctest::test_suite("gpu")) {
    EvenTorus t;
    t.style.toneGamma = 1.5f;
    t.style.ambient = 0.04f;
    t.style.light = {-0.5f, 0.6f, 0.65f};
    t.style.lightFollowsCamera = false;
    ink::OffscreenRenderer renderer(t.gpu.ctx, 1024, 1024, t.style, {&t.refined.r});
    auto accepted = [&](float azimuth) {
        renderer.render(tiltedCamera(azimuth));
        std::vector<uint32_t> points;
        for (const auto& d : renderer.dotList(0))
            if (drawnFront(d)) points.push_back(d.cls >> 4);
        std::sort(points.begin(), points.end());
        return points;
    };
    std::vector<uint32_t> first = accepted(30.0f), next = accepted(30.25f), kept;
    REQUIRE(next.size() > 2000);
    std::set_intersection(first.begin(), first.end(), next.begin(), next.end(), std::back_inserter(kept));
    INFO(kept.size() << " of " << next.size() << " dots stay");
    CHECK(double(kept.size()) >= 0.9 * double(next.size()));
    t.gpu.requireNoValidationErrors();
}

TEST_CASE("page: where the points are too few for a dark tone, fewer and larger dots carry its ink, evenly spaced" *
          doctest::test_suite("gpu")) {
    // The torus of one tone, dark (ambient 0.5: 0.25 of the page asked): its stipples cannot give
    // SPACE_SUPPLY_KEPT candidates a dot, so the dots are spaced for less density and drawn larger (Dot::scale).
    EvenTorus t;
    t.style.ambient = 0.5f;
    ink::OffscreenRenderer renderer(t.gpu.ctx, 1024, 1024, t.style, {&t.refined.r});
    renderer.render(tiltedCamera());
    const std::vector<ink::gpu::Dot> dots = renderer.dotList(0);
    size_t larger = 0, drawn = 0;
    for (const auto& d : dots)
        if (drawnFront(d)) ++drawn, larger += d.scale > 1.0f;
    INFO(drawn << " dots drawn, " << larger << " larger");
    CHECK(larger > drawn / 2);
    const ink::PageMetrics m = page(renderer, t.style);
    CHECK(m.largerDots == larger);
    // 0.5 · 0.5 of the page asked. Measured on lavapipe: 0.793, no clumps, 0.229..0.246 (99% of the dots larger;
    // the greedy alone gave 0.758).
    checkPage(m, 0.5 * 0.5, 0.77, 0.02, 0.12, 0.12);
    t.gpu.requireNoValidationErrors();
}

namespace {

// The 8-connected components of an image's pixels darker than 128.
size_t inkComponents(const ink::RgbaImage& image) {
    const int w = int(image.width), h = int(image.height);
    std::vector<char> seen(size_t(w) * h, 0);
    auto ink = [&](int x, int y) { return image.pixels[4 * (size_t(y) * w + x)] < 128; };
    size_t components = 0;
    for (int y0 = 0; y0 < h; ++y0)
        for (int x0 = 0; x0 < w; ++x0) {
            if (seen[size_t(y0) * w + x0] || !ink(x0, y0)) continue;
            ++components;
            std::vector<std::pair<int, int>> stack{{x0, y0}};
            seen[size_t(y0) * w + x0] = 1;
            while (!stack.empty()) {
                auto [x, y] = stack.back();
                stack.pop_back();
                for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, h - 1); ++ny)
                    for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, w - 1); ++nx)
                        if (!seen[size_t(ny) * w + nx] && ink(nx, ny)) {
                            seen[size_t(ny) * w + nx] = 1;
                            stack.push_back({nx, ny});
                        }
            }
        }
    return components;
}

}  // namespace

TEST_CASE("page: a thin tube's silhouette dots join into its outline, stroked along it" * doctest::test_suite("gpu")) {
    // A ring of tube radius 0.03 (a tenth of the ring's), refined to 3 levels: its band |n·v| < τ is about 2τ·0.03
    // wide on the surface, less than a point apart, so round silhouette dots laid each outline down as a dotted
    // line; stroked along the outline to their neighbours (SILHOUETTE_REACH) they join. The outline only: no tone.
    GpuFixture gpu;
    ink::Model ring = ink::fitModel(ink::torusPoints(192, 24, 0.3, 0.03), {});
    ink::RefineOptions options;
    options.levels = 3;
    Refinement refined(gpu.ctx, ring.surface, options);
    ink::RenderStyle style;
    style.inkDensity = 0.0f;
    ink::OffscreenRenderer renderer(gpu.ctx, 512, 512, style, {&refined.r});
    const ink::RgbaImage image = renderer.render(tiltedCamera());
    size_t silhouettes = 0, round = 0, inked = 0;
    for (const ink::gpu::Dot& d : renderer.dotList(0))
        if ((d.cls & 3u) == ink::gpu::SILHOUETTE) ++silhouettes, round += !(glm::length(d.along) > 0.0f);
    for (size_t i = 0; i < image.pixels.size(); i += 4) inked += image.pixels[i] < 128;
    const size_t components = inkComponents(image);
    // Measured on lavapipe: 1,347 silhouette dots, none left round, ink 4,047 pixels in 2 components, the ring's
    // outer and inner outlines; drawn round (SILHOUETTE_REACH 0) they inked 2,888 pixels in 130.
    INFO(silhouettes << " silhouette dots (" << round << " round), " << inked << " inked pixels in " << components
                     << " components");
    CHECK(silhouettes > 500);
    CHECK(round * 20 <= silhouettes);  // a dot with no neighbour within reach stays round
    CHECK(components <= 12);
    gpu.requireNoValidationErrors();
}

TEST_CASE("page: direction sampling's dots stay on their lines: the screen spacing leaves them alone" *
          doctest::test_suite("gpu")) {
    EvenTorus t;
    t.style.toneGamma = 1.5f;
    ink::RefineOptions direction;
    direction.style = ink::SampleStyle::Direction;
    Refinement lines{t.gpu.ctx, t.model.surface, direction};
    ink::OffscreenRenderer renderer(t.gpu.ctx, 512, 512, t.style, {&lines.r, &t.refined.r});
    renderer.render(tiltedCamera());
    size_t directionDots = 0, stippleSpaced = 0;
    for (const auto& d : renderer.dotList(0)) {
        ++directionDots;
        CHECK(d.state == ink::gpu::SPACE_FIXED);
        CHECK(d.scale == 1.0f);
    }
    for (const auto& d : renderer.dotList(1)) stippleSpaced += d.state == ink::gpu::SPACE_ACCEPTED;
    CHECK(directionDots > 1000);
    CHECK(stippleSpaced > 1000);
    t.gpu.requireNoValidationErrors();
}

TEST_CASE("page: on a very large target the spacing's grid grows coarser to fit, without a validation error" *
          doctest::test_suite("gpu")) {
    // 8192² at one sample a pixel: the grid of the style's cells would take 686 MB, past lavapipe's 128 MiB
    // storage buffers and the 256 MiB any device is given; its cells grow until it fits (renderer.cpp,
    // fitSpacing). Before, the descriptor's range passed the device's limit (VUID-VkWriteDescriptorSet-00333).
    EvenTorus t;
    t.style.supersample = 1;
    ink::OffscreenRenderer renderer(t.gpu.ctx, 8192, 8192, t.style, {&t.refined.r});
    renderer.render(tiltedCamera());
    const glm::vec2 spacing = renderer.spacing();
    const double cells = std::ceil(8192.0 * spacing.y) * std::ceil(8192.0 * spacing.y);
    CHECK(cells * 16 <=
          double(std::min<VkDeviceSize>(t.gpu.ctx.properties.limits.maxStorageBufferRange, VkDeviceSize(256) << 20)));
    size_t accepted = 0;
    for (const auto& d : renderer.dotList(0)) accepted += drawnFront(d);
    CHECK(accepted > 1000);
    t.gpu.requireNoValidationErrors();
}

TEST_CASE("page: targets of a few pixels are spaced and drawn without a validation error or a stray write" *
          doctest::test_suite("gpu")) {
    // A grid of a few cells has no room for the relaxation's list and blocks (SPACE_RELAX_MIN_CELLS): at 1 × 1 its
    // fill once underflowed and its list overwrote the accepted dots' plane (lavapipe crashed).
    EvenTorus t;
    for (const std::pair<uint32_t, uint32_t>& size : {std::pair{1u, 1u}, {2u, 3u}, {3u, 40u}, {9u, 9u}}) {
        const uint32_t width = size.first, height = size.second;
        CAPTURE(width);
        CAPTURE(height);
        ink::OffscreenRenderer renderer(t.gpu.ctx, width, height, t.style, {&t.refined.r});
        const ink::RgbaImage image = renderer.render(tiltedCamera());
        CHECK(image.width == width);
        CHECK(image.height == height);
        for (const auto& d : renderer.dotList(0))
            if (d.state == ink::gpu::SPACE_ACCEPTED) {
                CHECK(d.pixel.x >= -1.0f);
                CHECK(d.pixel.x <= float(width * renderer.supersample()) + 1.0f);
                CHECK(d.pixel.y >= -1.0f);
                CHECK(d.pixel.y <= float(height * renderer.supersample()) + 1.0f);
            }
    }
    t.gpu.requireNoValidationErrors();
}
