// The blue-noise stipple selection (select.h): the device against the CPU reference, the spacing of the whole
// set and its prefixes on an analytic torus, determinism, thin parts, and what the renderer draws from it.
#include "draw/renderer.h"
#include "gpu_fixture.h"
#include "refine/refine.h"
#include "refine/spacing.h"
#include "select/select.h"
#include "surface/model.h"
#include "surface/shapes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <vector>

namespace {

struct Selected {
    std::vector<ink::PointRecord> candidates, stipples;
    std::vector<uint32_t> added;
    ink::SelectPlan plan;
};

Selected selectOnGpu(GpuFixture& gpu, const ink::Surface& hrbf, const ink::RefineOptions& options) {
    Refinement refined(gpu.ctx, hrbf, options);
    REQUIRE(refined.r.selection);
    return {ink::readPoints(gpu.ctx, refined.r), ink::readDrawnPoints(gpu.ctx, refined.r),
            ink::readStageCounts(gpu.ctx, *refined.r.selection), refined.r.selection->plan};
}

// A torus (R = 0.3, r = 0.1 about z) and its area in the model's normalized units.
constexpr double kR = 0.3, kr = 0.1;
ink::Model torusModel() { return ink::fitModel(ink::torusPoints(48, 16, kR, kr), {}); }
double torusArea(const ink::Model& m) {
    return 4 * M_PI * M_PI * kR * kr * m.surface.frame.scale * m.surface.frame.scale;
}

// Selects on the device, then on the CPU from the device's own candidates: the same points, in the same order,
// the same stage counts, ranks within 1e-6.
void checkAgainstCpu(GpuFixture& gpu, const ink::Surface& hrbf) {
    ink::RefineOptions options;
    options.levels = 3;
    Selected gpuOut = selectOnGpu(gpu, hrbf, options);
    std::vector<uint32_t> added;
    std::vector<ink::PointRecord> cpu = ink::selectOnCpu(gpuOut.candidates, gpuOut.plan, &added);
    CHECK(added == gpuOut.added);
    REQUIRE(cpu.size() == gpuOut.stipples.size());
    REQUIRE(cpu.size() > gpuOut.candidates.size() / 8);
    size_t same = 0, rankClose = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
        const ink::PointRecord &a = cpu[i], &b = gpuOut.stipples[i];
        same += std::memcmp(a.position, b.position, 12) == 0 && std::memcmp(a.normal, b.normal, 12) == 0 &&
                a.level == b.level;
        rankClose += std::abs(a.tone - b.tone) <= 1e-6f;
    }
    CHECK(same == cpu.size());
    CHECK(rankClose == cpu.size());
}

}  // namespace

TEST_CASE("select: the device selects exactly the CPU reference's stipples, in the same order and ranks" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    checkAgainstCpu(gpu, ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {300}).surface);
    checkAgainstCpu(gpu, torusModel().surface);
    gpu.requireNoValidationErrors();
}

TEST_CASE("select: on a torus the stipples and every prefix of their ranking are evenly spaced" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model torus = torusModel();
    const double area = torusArea(torus);
    ink::RefineOptions options;  // the defaults but for the levels: 768 seeds, 3 levels of 4 children
    options.levels = 3;
    Selected out = selectOnGpu(gpu, torus.surface, options);
    const double n = double(out.stipples.size());
    REQUIRE(n > 10000);
    CHECK(double(out.candidates.size()) / n > 3.0);  // about 4 candidates a stipple, as planned from the area
    CHECK(double(out.candidates.size()) / n < 8.0);
    for (double fraction : {1.0, 0.5, 0.25, 0.125}) {
        ink::SpacingStats s = ink::measureSpacing(out.stipples, fraction, area);
        INFO("prefix " << fraction << ": " << s.points << " points, mean " << s.meanNearest << ", min "
                       << s.minNearest);
        CHECK(double(s.points) == doctest::Approx(fraction * n).epsilon(0.05));
        CHECK(s.meanNearest >= 0.75);
        CHECK(s.minNearest >= 0.5);
        CHECK(s.minNearest * s.rMax > 1e-6);  // no duplicates (the diagonal is 1)
        CHECK(s.clumped == 0.0);
    }
    // The candidates alone, with their random tone values, are white noise at best: what the selection fixes.
    ink::SpacingStats raw = ink::measureSpacing(out.candidates, 1.0, area);
    CHECK(raw.meanNearest < 0.6);
    // The area estimated from the stipples alone (what --stats reports) is within a few percent.
    CHECK(ink::estimateSurfaceArea(out.stipples) == doctest::Approx(area).epsilon(0.08));
    gpu.requireNoValidationErrors();
}

TEST_CASE("select: the refinement writes no point twice, with the report's two passes too" *
          doctest::test_suite("unit")) {
    ink::Model torus = torusModel();
    for (ink::Distribution d : {ink::Distribution::BlueNoise, ink::Distribution::Refinement}) {
        ink::RefineOptions options;
        options.levels = 2;
        options.distribution = d;
        ink::RefinePlan plan = ink::planRefinement(torus.surface, options, UINT32_MAX);
        CHECK(plan.passes == (d == ink::Distribution::BlueNoise ? 1u : 2u));
        std::vector<ink::PointRecord> points = ink::refineOnCpu(torus.surface, options, plan);
        REQUIRE(points.size() == 768 * (1 + 4 * plan.passes + 16 * plan.passes));
        ink::SpacingStats s = ink::measureSpacing(points, 1.0, torusArea(torus));
        CHECK(s.minNearest * s.rMax > 1e-6);
    }
}

TEST_CASE("select: the same input selects the same stipples, bit for bit" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model bunny = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {200});
    ink::RefineOptions options;
    options.levels = 3;
    Selected a = selectOnGpu(gpu, bunny.surface, options), b = selectOnGpu(gpu, bunny.surface, options);
    REQUIRE(a.stipples.size() == b.stipples.size());
    CHECK(std::memcmp(a.stipples.data(), b.stipples.data(), a.stipples.size() * sizeof(ink::PointRecord)) == 0);
    options.seed = 2;  // another seed, another selection
    Selected c = selectOnGpu(gpu, bunny.surface, options);
    CHECK((c.stipples.size() != a.stipples.size() ||
           std::memcmp(a.stipples.data(), c.stipples.data(), a.stipples.size() * sizeof(ink::PointRecord)) != 0));
    gpu.requireNoValidationErrors();
}

TEST_CASE("select: the two sides of a thin part do not suppress each other" * doctest::test_suite("unit")) {
    // Two sheets 1e-4 apart (far below the stipple spacing) facing away from each other, like the two sides of
    // a thin plate, then the same sheets facing the same way.
    ink::Surface hrbf;
    std::vector<ink::PointRecord> candidates;
    for (int side = 0; side < 2; ++side)
        for (int i = 0; i < 120; ++i)
            for (int j = 0; j < 120; ++j) {
                float jitter = float((i * 7 + j * 13 + side * 5) % 17) / 17.0f;
                ink::PointRecord p{{(float(i) + jitter) / 240.0f, (float(j) + 0.5f * jitter) / 240.0f, side * 1e-4f},
                                   0,
                                   {0, 0, side ? -1.0f : 1.0f},
                                   0};
                candidates.push_back(p);
            }
    for (int i = 0; i <= 10; ++i)
        for (int j = 0; j <= 10; ++j) hrbf.seeds.emplace_back(i / 20.0, j / 20.0, 0.0);
    ink::RefinePlan refine;
    refine.maxPoints = candidates.size();
    ink::SelectPlan plan = ink::planSelection(hrbf, refine, {});
    auto bySide = [&](const std::vector<ink::PointRecord>& points) {
        std::array<size_t, 2> count{};
        for (const auto& p : points) ++count[p.position[2] > 0 ? 1 : 0];
        return count;
    };
    auto apart = bySide(ink::selectOnCpu(candidates, plan));
    CHECK(apart[0] > 1000);
    CHECK(double(apart[1]) == doctest::Approx(double(apart[0])).epsilon(0.1));
    for (size_t k = candidates.size() / 2; k < candidates.size(); ++k) candidates[k].normal[2] = 1.0f;
    auto together = bySide(ink::selectOnCpu(candidates, plan));
    CHECK(together[0] + together[1] < 0.6 * double(apart[0] + apart[1]));  // one surface: one set of stipples
}

TEST_CASE("select: the dots of a frame stay on the same points when the camera orbits by 1 degree" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model bunny = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {300});
    ink::RefineOptions options;
    options.levels = 3;
    Refinement refined(gpu.ctx, bunny.surface, options);
    ink::RenderStyle fixedLight;  // the light fixed to the model (--light-fixed): the tone stays put too
    fixedLight.lightFollowsCamera = false;
    ink::OffscreenRenderer renderer(gpu.ctx, 512, 512, fixedLight, {&refined.r});
    ink::Camera camera;
    for (float azimuth : {0.0f, 40.0f, 200.0f}) {
        camera.azimuthDeg = azimuth;
        renderer.render(camera);
        std::vector<uint32_t> first = renderer.drawnPoints(0);
        camera.azimuthDeg = azimuth + 1.0f;
        renderer.render(camera);
        std::vector<uint32_t> next = renderer.drawnPoints(0);
        REQUIRE(first.size() > 500);
        std::vector<uint32_t> kept;
        std::set_intersection(first.begin(), first.end(), next.begin(), next.end(), std::back_inserter(kept));
        INFO("azimuth " << azimuth << ": " << kept.size() << " of " << first.size() << " dots stay");
        CHECK(double(kept.size()) >= 0.95 * double(first.size()));
    }
    gpu.requireNoValidationErrors();
}

namespace {

// Dots of an image: 4-connected components of pixels darker than 128, at their centroids.
std::vector<Eigen::Vector2d> findDots(const ink::RgbaImage& image) {
    const int w = int(image.width), h = int(image.height);
    std::vector<int> label(size_t(w) * h, -1);
    std::vector<Eigen::Vector2d> dots;
    for (int y0 = 0; y0 < h; ++y0)
        for (int x0 = 0; x0 < w; ++x0) {
            size_t i0 = size_t(y0) * w + x0;
            if (label[i0] >= 0 || image.pixels[4 * i0] >= 128) continue;
            Eigen::Vector2d sum(0, 0);
            int count = 0;
            std::vector<std::pair<int, int>> stack{{x0, y0}};
            label[i0] = int(dots.size());
            while (!stack.empty()) {
                auto [x, y] = stack.back();
                stack.pop_back();
                sum += Eigen::Vector2d(x + 0.5, y + 0.5);
                ++count;
                for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                    int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    size_t j = size_t(ny) * w + nx;
                    if (label[j] >= 0 || image.pixels[4 * j] >= 128) continue;
                    label[j] = int(dots.size());
                    stack.push_back({nx, ny});
                }
            }
            dots.push_back(sum / count);
        }
    return dots;
}

}  // namespace

TEST_CASE("select: drawn dots in an evenly toned region are evenly spaced" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model sphere = ink::fitModel(ink::spherePoints(1000), {});
    Refinement refined(gpu.ctx, sphere.surface, ink::RefineOptions{});
    // Lit from the camera, the middle of the sphere is one tone; ambient light puts about half its dots there.
    ink::RenderStyle style;
    style.light = {0, 0, 1};
    style.lightFollowsCamera = true;
    style.ambient = 0.5f;
    ink::OffscreenRenderer renderer(gpu.ctx, 1024, 1024, style, {&refined.r});
    ink::Camera camera;
    camera.distance = 1.2f;
    ink::RgbaImage image = renderer.render(camera);
    std::vector<Eigen::Vector2d> dots = findDots(image);
    const double lo = 412, hi = 612;  // the window, pixels
    auto inside = [&](const Eigen::Vector2d& d) { return d.x() >= lo && d.x() < hi && d.y() >= lo && d.y() < hi; };
    size_t n = 0, clumped = 0;
    double sum = 0;
    std::vector<double> nearest;
    for (const auto& d : dots) {
        if (!inside(d)) continue;
        double best = INFINITY;
        for (const auto& e : dots)
            if (&e != &d) best = std::min(best, (e - d).norm());
        nearest.push_back(best);
    }
    n = nearest.size();
    REQUIRE(n > 300);
    double rMax = std::sqrt(2.0 * (hi - lo) * (hi - lo) / (std::sqrt(3.0) * double(n)));
    for (double d : nearest) {
        sum += d / rMax;
        clumped += d < 0.5 * rMax;
    }
    INFO(n << " dots, mean " << sum / double(n) << " r_max, " << clumped << " clumped");
    CHECK(sum / double(n) >= 0.72);
    CHECK(double(clumped) <= 0.05 * double(n));
    gpu.requireNoValidationErrors();
}
