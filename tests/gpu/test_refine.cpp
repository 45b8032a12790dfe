// Refinement on the device, read back level by level and checked against the CPU evaluation and reference.
#include "base/common.h"
#include "draw/renderer.h"
#include "gpu_fixture.h"
#include "refine/refine.h"
#include "skip.h"
#include "surface/model.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

using Eigen::Vector3d;

namespace {

// A torus (R = 0.3, r = 0.1 around the z axis) as oriented points: analytic surface and normals.
ink::OrientedPoints torus(int nu, int nv) {
    ink::OrientedPoints pts;
    const double R = 0.3, r = 0.1;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double u = 2 * M_PI * (i + 0.5 * (j % 2)) / nu, v = 2 * M_PI * j / nv;
            Vector3d c(std::cos(u), std::sin(u), 0);
            Vector3d n = std::cos(v) * c + std::sin(v) * Vector3d::UnitZ();
            pts.positions.push_back(R * c + r * n);
            pts.normals.push_back(n);
        }
    return pts;
}

// Distance from x to the torus above, and its outward normal there.
double torusDistance(const Vector3d& x, Vector3d* normal) {
    Vector3d c(x.x(), x.y(), 0);
    c = 0.3 * c.normalized();
    Vector3d d = x - c;
    if (normal) *normal = d.normalized();
    return d.norm() - 0.1;
}

struct Refined {
    std::vector<ink::PointRecord> points;
    std::vector<ink::LevelStats> levels;
    ink::RefinePlan plan;
};

Refined refineOnGpu(GpuFixture& gpu, const ink::Surface& hrbf, const ink::RefineOptions& options) {
    Refinement refined(gpu.ctx, hrbf, options);
    return {ink::readPoints(gpu.ctx, refined.r), ink::readLevelStats(gpu.ctx, refined.r), refined.r.plan};
}

// Refines on the device and with the CPU reference on the same plan; the counts per level must agree. Returns
// the device's points and the fraction of them within `distance` of the reference's, normals within `cosine`.
std::pair<Refined, double> compareWithCpu(GpuFixture& gpu, const ink::Surface& hrbf, const ink::RefineOptions& options,
                                          float distance, float cosine = -1.0f) {
    Refined gpuOut = refineOnGpu(gpu, hrbf, options);
    std::vector<ink::LevelStats> cpuLevels;
    auto cpuPoints = ink::refineOnCpu(hrbf, options, gpuOut.plan, &cpuLevels, 2);
    REQUIRE(cpuLevels.size() == gpuOut.levels.size());
    for (size_t l = 0; l < cpuLevels.size(); ++l) {
        CHECK(cpuLevels[l].candidates == gpuOut.levels[l].candidates);
        CHECK(cpuLevels[l].kept == gpuOut.levels[l].kept);
    }
    REQUIRE(cpuPoints.size() == gpuOut.points.size());
    REQUIRE(!cpuPoints.empty());
    size_t close = 0;
    for (size_t i = 0; i < cpuPoints.size(); ++i) {
        Eigen::Vector3f a(cpuPoints[i].position), b(gpuOut.points[i].position);
        Eigen::Vector3f na(cpuPoints[i].normal), nb(gpuOut.points[i].normal);
        close += (a - b).norm() < distance && na.dot(nb) > cosine && cpuPoints[i].level == gpuOut.points[i].level;
    }
    return {std::move(gpuOut), double(close) / double(cpuPoints.size())};
}

}  // namespace

TEST_CASE("refine: every kept point of every level is on the surface with a unit normal along grad f" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {120});
    for (auto style : {ink::SampleStyle::Stipple, ink::SampleStyle::Direction}) {
        ink::RefineOptions options;
        options.style = style;
        options.levels = 3;
        Refined out = refineOnGpu(gpu, model.surface, options);
        REQUIRE(out.levels.size() == 4);
        size_t total = 0;
        for (const auto& l : out.levels) {
            CHECK(l.kept + l.dropped[0] + l.dropped[1] + l.dropped[2] + l.dropped[3] == l.candidates);
            total += l.kept;
        }
        CHECK(out.points.size() == total);
        std::vector<size_t> perLevel(4, 0);
        for (const auto& p : out.points) {
            REQUIRE(p.level < 4);
            perLevel[p.level]++;
            Vector3d x(p.position[0], p.position[1], p.position[2]), g;
            double f = model.surface.eval(x, g);
            CHECK(std::abs(f) / g.norm() < 2e-5);  // ε₁ = 1e-5, plus float storage of the position
            Vector3d n(p.normal[0], p.normal[1], p.normal[2]);
            CHECK(std::abs(n.norm() - 1.0) < 1e-5);
            CHECK(n.dot(g.normalized()) > 0.99999);
            CHECK(p.tone >= 0.0f);
            CHECK(p.tone < 1.0f);
        }
        for (size_t l = 0; l < 4; ++l) CHECK(perLevel[l] == out.levels[l].kept);
    }
    gpu.requireNoValidationErrors();
}

TEST_CASE("refine: identical runs give identical bytes, and the seed changes them" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {80});
    ink::RefineOptions options;
    options.levels = 3;
    options.passes = 2;
    Refined a = refineOnGpu(gpu, model.surface, options);
    Refined b = refineOnGpu(gpu, model.surface, options);
    REQUIRE(a.points.size() == b.points.size());
    CHECK(std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(ink::PointRecord)) == 0);
    options.seed = 2;
    Refined c = refineOnGpu(gpu, model.surface, options);
    CHECK(std::memcmp(a.points.data(), c.points.data(), std::min(a.points.size(), c.points.size()) * 32) != 0);
    gpu.requireNoValidationErrors();
}

TEST_CASE("refine: counts per level match the CPU reference and points agree" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {100});
    for (auto direction : {ink::DirectionField::Axis, ink::DirectionField::CurvatureMax}) {
        ink::RefineOptions options;
        options.levels = 3;
        options.passes = 2;
        options.style =
            direction == ink::DirectionField::Axis ? ink::SampleStyle::Stipple : ink::SampleStyle::Direction;
        options.direction = direction;
        CHECK(compareWithCpu(gpu, model.surface, options, 1e-3f).second >= 0.99);
    }
    gpu.requireNoValidationErrors();
}

// hrbf.glsl (the global fit's evaluation, refine_global.comp) shares the centres across a subgroup, a chunk at
// a time, from 64 KiB blocks of 1024 centres: a model with a second block and a last chunk that is not full
// must still match the CPU reference. The global fit: the partition of unity's patches (pu_hrbf.glsl) hold
// far fewer centres each, so with it this case would never reach a second block.
TEST_CASE("refine: more than 1024 centres, not a multiple of the subgroup size, match the CPU reference" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    if (!gpu.ctx.float64) {
        skipTest(std::string(gpu.ctx.properties.deviceName) + " lacks shaderFloat64, which the global fit needs");
        return;
    }
    ink::OrientedPoints pts = torus(60, 19);  // 1140 = 1024 + 116 centres: 1140 mod 8 = 4, 1140 mod 16 = 4
    ink::ModelOptions fitOptions;
    fitOptions.controlPoints = pts.positions.size();
    fitOptions.method = ink::FitMethod::Global;
    ink::Model model = ink::fitModel(pts, fitOptions);
    REQUIRE(model.surface.size() == 1140);
    ink::RefineOptions options;
    options.levels = 2;
    auto [gpuOut, agreement] = compareWithCpu(gpu, model.surface, options, 1e-5f, 0.99999f);
    CHECK(gpuOut.points.size() > 3 * 1140);
    CHECK(agreement >= 0.99);
    gpu.requireNoValidationErrors();
}

TEST_CASE("refine: stippling a torus puts points within 1% of its size of the true surface" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::fitModel(torus(24, 12), {});
    ink::RefineOptions options;
    options.levels = 3;
    Refined out = refineOnGpu(gpu, model.surface, options);
    REQUIRE(out.points.size() > 5000);
    double worstDistance = 0, worstAngle = 0;
    for (const auto& p : out.points) {
        Vector3d x = model.surface.frame.toInput(Vector3d(p.position[0], p.position[1], p.position[2])), n;
        worstDistance = std::max(worstDistance, std::abs(torusDistance(x, &n)));
        double c = std::clamp(n.dot(Vector3d(p.normal[0], p.normal[1], p.normal[2])), -1.0, 1.0);
        worstAngle = std::max(worstAngle, std::acos(c) * 180 / M_PI);
    }
    CHECK(worstDistance < 0.01 * 0.8);  // the torus is 0.8 across
    CHECK(worstAngle < 5.0);
    gpu.requireNoValidationErrors();
}

TEST_CASE("refine: grid seeds project onto the surface" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::fitModel(torus(24, 12), {});
    ink::RefineOptions options;
    options.seeds = ink::SeedMode::Grid;
    options.grid = 16;
    options.levels = 1;
    Refined out = refineOnGpu(gpu, model.surface, options);
    CHECK(out.levels[0].kept > 100);
    CHECK(out.levels[0].kept < out.levels[0].candidates);  // cells far from the surface are dropped
    for (const auto& p : out.points) {
        Vector3d x = model.surface.frame.toInput(Vector3d(p.position[0], p.position[1], p.position[2]));
        CHECK(std::abs(torusDistance(x, nullptr)) < 0.008);
    }
    gpu.requireNoValidationErrors();
}

TEST_CASE("refine: requests that cannot fit are refused with the numbers" * doctest::test_suite("unit")) {
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {50});
    ink::RefineOptions options;
    options.levels = 16;
    CHECK_THROWS_WITH_AS(ink::planRefinement(model.surface, options, 1u << 22), doctest::Contains("--levels 16"),
                         ink::Error);
    options.levels = 14;
    CHECK_THROWS_WITH_AS(
        ink::planRefinement(model.surface, options, 1u << 22),
        doctest::Contains("asks for up to 17895697050 points (50 seeds, 14 levels of 4 children, 1 pass), "
                          "but at most 4194304 fit"),
        ink::Error);
}

TEST_CASE("refine: seeds at random get the spacing of seeds spread evenly, not their nearest's half" *
          doctest::test_suite("unit")) {
    // 900 points on a unit sphere, uniformly at random and on a Fibonacci spiral: the same density, so the same ρ₀
    // within its estimate's noise. The random ones' nearest distances average half the spiral's: ρ₀ from them alone
    // left the children of four levels short of the gaps (a sparse scan drew lace and holes).
    std::vector<Vector3d> random, spiral;
    uint32_t state = 7;
    auto normal = [&] {
        double u = 0, v = 0;
        while (!(u > 0)) {
            state = state * 1664525u + 1013904223u;
            u = double(state >> 8) / double(1u << 24);
        }
        state = state * 1664525u + 1013904223u;
        v = double(state >> 8) / double(1u << 24);
        return std::sqrt(-2 * std::log(u)) * std::cos(2 * M_PI * v);
    };
    for (int i = 0; i < 900; ++i) {
        random.push_back(Vector3d(normal(), normal(), normal()).normalized());
        const double y = 1 - 2 * (i + 0.5) / 900, r = std::sqrt(1 - y * y), a = 2.399963229728653 * i;
        spiral.push_back({r * std::cos(a), y, r * std::sin(a)});
    }
    auto rho0 = [](const std::vector<Vector3d>& points) {
        ink::OrientedPoints cloud;
        cloud.positions = points;
        cloud.normals = points;
        const ink::Model model = ink::fitModel(cloud, {});
        return ink::planRefinement(model.surface, {}, 1u << 22).rho0;
    };
    const double even = rho0(spiral), scattered = rho0(random);
    INFO("ρ₀ " << scattered << " for random seeds, " << even << " for a spiral's");
    CHECK(scattered > 0.8 * even);  // 0.62 times before
    CHECK(scattered < 1.25 * even);
}

TEST_CASE("refine: the portable CPU kernel (what ARM64 runs) gives the AVX2 kernel's points, to rounding" *
          doctest::test_suite("unit")) {
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {150});
    ink::RefineOptions options;
    options.levels = 3;
    ink::RefinePlan plan = ink::planRefinement(model.surface, options, 1u << 22);
    std::vector<ink::LevelStats> bestLevels, portableLevels;
    auto best = ink::refineOnCpu(model.surface, options, plan, &bestLevels, 2, ink::CpuKernel::Best);
    auto portable = ink::refineOnCpu(model.surface, options, plan, &portableLevels, 2, ink::CpuKernel::Portable);
    REQUIRE(best.size() > 10000);
    REQUIRE(portable.size() == best.size());
    for (size_t l = 0; l < bestLevels.size(); ++l) CHECK(portableLevels[l].kept == bestLevels[l].kept);
    // The kernels differ only in fused multiply-adds: the same points to float rounding, all but a handful.
    size_t same = 0;
    for (size_t i = 0; i < best.size(); ++i) {
        Eigen::Vector3f a(best[i].position), b(portable[i].position);
        same += (a - b).norm() < 1e-6f && best[i].level == portable[i].level;
    }
    CHECK(double(same) / double(best.size()) > 0.999);
}

TEST_CASE("refine: the partition of unity in float matches the CPU reference, the Hessian's directions too" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {400});
    REQUIRE(model.surface.method == ink::FitMethod::PartitionOfUnity);
    for (auto style : {ink::SampleStyle::Stipple, ink::SampleStyle::Direction}) {
        CAPTURE(int(style));
        ink::RefineOptions options;
        options.style = style;
        options.direction = ink::DirectionField::CurvatureMax;  // the Hessian too
        options.levels = 2;
        auto [refined, close] = compareWithCpu(gpu, model.surface, options, 1e-4f, 0.999f);
        CHECK(close > 0.99);
        // On the surface, as the double-precision model measures it.
        double worst = 0;
        for (const auto& p : refined.points) {
            Eigen::Vector3d x(p.position[0], p.position[1], p.position[2]), g;
            double f = model.surface.eval(x, g);
            worst = std::max(worst, std::abs(f) / g.norm());
        }
        CHECK(worst < 2e-5);  // ε₁ = 1e-5 of the diagonal, and float rounding of the stored position
    }
    gpu.requireNoValidationErrors();
}

// Issue 27's size wall: patch nodes beyond a storage buffer's range (128 MiB on lavapipe, a scan of 10⁶ points
// has 222 MiB) are read by device address, refine_large.comp. Both paths on one small model: the same points.
TEST_CASE("refine: the partition of unity's nodes read by device address give the same points as from a buffer" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    REQUIRE(gpu.ctx.bufferDeviceAddress);  // every Vulkan 1.3 device has it
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {400});
    for (auto style : {ink::SampleStyle::Stipple, ink::SampleStyle::Direction}) {
        CAPTURE(int(style));
        ink::RefineOptions options;
        options.style = style;
        options.direction = ink::DirectionField::CurvatureMax;  // the Hessian's nodes too
        options.levels = 3;
        Refinement buffer(gpu.ctx, model.surface, options);
        options.nodesByAddress = true;
        Refinement address(gpu.ctx, model.surface, options);
        CHECK(!buffer.r.nodesByAddress);
        CHECK(address.r.nodesByAddress);
        const auto a = ink::readPoints(gpu.ctx, buffer.r), b = ink::readPoints(gpu.ctx, address.r);
        REQUIRE(a.size() > 10000);
        REQUIRE(a.size() == b.size());
        CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(ink::PointRecord)) == 0);
    }
    gpu.requireNoValidationErrors();
}

TEST_CASE("refine: without shaderFloat64 the partition of unity refines and draws; the global fit says what it needs" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu(false);
    REQUIRE_FALSE(gpu.ctx.float64);
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {300});
    ink::RefineOptions options;
    options.levels = 3;
    Refinement refined(gpu.ctx, model.surface, options);
    CHECK(ink::readPointCount(gpu.ctx, refined.r) > 1000);
    ink::RenderStyle style;
    ink::OffscreenRenderer renderer(gpu.ctx, 128, 128, style, {&refined.r});
    ink::RgbaImage image = renderer.render(ink::Camera{});
    size_t dark = 0;
    for (size_t i = 0; i < image.pixels.size(); i += 4) dark += image.pixels[i] < 128;
    CHECK(dark > 100);
    gpu.requireNoValidationErrors();

    ink::Model global = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {300, ink::FitMethod::Global});
    CHECK_THROWS_WITH_AS(ink::Refinement(gpu.ctx, global.surface, options), doctest::Contains("lacks shaderFloat64"),
                         ink::Error);
}

TEST_CASE("refine: the report's global fit still refines in double where the device has shaderFloat64" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    if (!gpu.ctx.float64) {  // the test above covers the refusal on such a device
        skipTest(std::string(gpu.ctx.properties.deviceName) + " lacks shaderFloat64");
        return;
    }
    ink::Model model = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {300, ink::FitMethod::Global});
    ink::RefineOptions options;
    options.levels = 2;
    auto [refined, close] = compareWithCpu(gpu, model.surface, options, 1e-4f, 0.999f);
    CHECK(close > 0.99);
    gpu.requireNoValidationErrors();
}
