// The partition-of-unity fit (engine/surface/pu_hrbf.h, issue 15): interpolation in float as the device evaluates, the
// blend's derivatives, the far field, and the .hrbf round trips (text version 2, binary version 3).
#include "base/common.h"
#include "base/parallel.h"
#include "io/hrbf_io.h"
#include "io/points.h"
#include "surface/clean.h"
#include "surface/model.h"
#include "surface/pu_hrbf.h"
#include "surface/shapes.h"
#include "temp_dir.h"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

using Eigen::Vector3d;

namespace {

const std::string kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj";

// The worst |F|/‖∇F‖ (diagonals) and angle to the normal (degrees) at the given points, in float as the device.
std::pair<double, double> floatError(const ink::Surface& s, const std::vector<Vector3d>& points,
                                     const std::vector<Vector3d>& normals) {
    ink::PuFloat pu(s.pu);
    double distance = 0, angle = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        Eigen::Vector3f g;
        float f = pu.eval(points[i].cast<float>(), g);
        Vector3d gd = g.cast<double>();
        distance = std::max(distance, std::abs(double(f)) / gd.norm());
        angle = std::max(angle, std::atan2(gd.cross(normals[i]).norm(), gd.dot(normals[i])) * 180 / M_PI);
    }
    return {distance, angle};
}

}  // namespace

TEST_CASE("pu: the bunny and a torus interpolate every point in float: under 1e-6 of the diagonal and 0.01 degree" *
          doctest::test_suite("unit")) {
    ink::Model bunny = ink::loadModel(kBunny, {});
    REQUIRE(bunny.surface.method == ink::FitMethod::PartitionOfUnity);
    // The faces are sampled, and the samples fitted only where the 1,839 vertices alone miss them (measured: 632
    // of 16,939); all of them would put the facets' disagreement with the vertex normals into the curvature.
    CHECK(bunny.faceSamples > 100);
    CHECK(bunny.faceSamples < 3000);
    CHECK(bunny.surface.size() > 1839);
    CHECK(bunny.patches.patches > 100);
    CHECK(bunny.patches.maxPatch <= 64);
    CHECK(bunny.fit.maxDistance < 1e-6);
    CHECK(bunny.fit.maxNormalAngleDeg < 0.01);
    CHECK(bunny.inputMaxDistance < 1e-6);  // at the vertices the file gave
    auto [d, a] = floatError(bunny.surface, bunny.surface.centers, bunny.surface.normals);
    CHECK(d == doctest::Approx(bunny.fit.maxDistance));
    CHECK(a < 0.01);

    // An analytic torus: the fitted zero set lies on it between the samples too.
    ink::Model torus = ink::fitModel(ink::torusPoints(120, 40), {});
    CHECK(torus.fit.maxDistance < 1e-6);
    CHECK(torus.fit.maxNormalAngleDeg < 0.01);
    const ink::Frame& frame = torus.surface.frame;
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
        double u = 2 * M_PI * (i * 0.618034 - std::floor(i * 0.618034)),
               v = 2 * M_PI * (i * 0.7548777 - std::floor(i * 0.7548777));
        Vector3d onTorus((0.3 + 0.1 * std::cos(v)) * std::cos(u), (0.3 + 0.1 * std::cos(v)) * std::sin(u),
                         0.1 * std::sin(v)),
            g;
        double f = torus.surface.eval(frame.toNormalized(onTorus), g);
        worst = std::max(worst, std::abs(f) / g.norm());
    }
    CHECK(worst < 1e-4);  // between samples 1/40 of a turn apart: measured 6e-6
}

TEST_CASE("pu: the blend's gradient and Hessian are the derivatives of F, also where the far field takes over" *
          doctest::test_suite("unit")) {
    ink::Model m = ink::loadModel(kBunny, {500});
    const ink::Surface& s = m.surface;
    const double h = 1e-6;
    // Near the surface, off it, and outside every patch (the far field alone), and in its blend.
    std::vector<Vector3d> probes = {s.centers[10] + 0.01 * s.normals[10], s.centers[200] - 0.02 * s.normals[200],
                                    Vector3d(0.9, 0.9, 0.9), Vector3d(0.0, 0.55, 0.0)};
    for (int k = 0; k < 40; ++k) probes.push_back(s.centers[size_t(k) * 11] + 0.05 * s.normals[size_t(k) * 11]);
    for (const Vector3d& x : probes) {
        CAPTURE(x.transpose());
        Vector3d g;
        Eigen::Matrix3d H;
        s.eval(x, g, &H);
        for (int a = 0; a < 3; ++a) {
            Vector3d e = Vector3d::Unit(a) * h, gp, gm;
            double fd = (s.f(x + e) - s.f(x - e)) / (2 * h);
            CHECK(std::abs(fd - g[a]) < 1e-5 * std::max(1.0, g.norm()));
            s.eval(x + e, gp);
            s.eval(x - e, gm);
            Vector3d column = (gp - gm) / (2 * h);
            CHECK((column - H.col(a)).norm() < 1e-3 * std::max(1.0, H.norm()));
        }
    }
    // Far from the data the sign is right: outside positive, at the centre of the body negative.
    CHECK(s.f(Vector3d(2, 2, 2)) > 0);
    CHECK(s.f(Vector3d(-3, 0, 1)) > 0);
}

TEST_CASE("pu: a version 2 .hrbf file round-trips bit for bit; version 1 files still load" *
          doctest::test_suite("unit")) {
    TempDir dir;
    ink::Model fitted = ink::loadModel(kBunny, {800});
    std::string path = dir / "bunny.hrbf";
    ink::saveHrbf(path, fitted.surface, ink::HrbfFormat::Text);
    std::string text = ink::readFileCapped(path, 1 << 30, "too big");
    CHECK(text.rfind("inkwell-hrbf 2\n", 0) == 0);
    ink::Model loaded = ink::loadModel(path, {});
    const ink::Surface &a = fitted.surface, &b = loaded.surface;
    REQUIRE(b.method == ink::FitMethod::PartitionOfUnity);
    REQUIRE(b.size() == a.size());
    REQUIRE(b.pu.patches.size() == a.pu.patches.size());
    REQUIRE(b.pu.nodes.size() == a.pu.nodes.size());
    CHECK(b.pu.grid.cellPatches == a.pu.grid.cellPatches);
    CHECK(loaded.fit.maxDistance == fitted.fit.maxDistance);
    for (double u : {-0.4, -0.1, 0.0, 0.23, 0.5}) {
        Vector3d x(u, 0.3 * u - 0.05, 0.1 - u), ga, gb;
        double fa = a.eval(x, ga), fb = b.eval(x, gb);
        CHECK(std::memcmp(&fa, &fb, sizeof fa) == 0);
        CHECK(ga == gb);
    }
    // Saving the loaded model again gives the same bytes.
    std::string again = dir / "again.hrbf";
    ink::saveHrbf(again, b, ink::HrbfFormat::Text);
    CHECK(ink::readFileCapped(again, 1 << 30, "too big") == text);

    // A spoilt version 2 file: one line naming the problem.
    std::string bad = text;
    bad.replace(bad.find("patches "), 8, "patches x");
    CHECK_THROWS_WITH_AS(ink::parseHrbf(bad, "m.surface"), doctest::Contains("m.surface: line"), ink::Error);
    std::string shifted = text;
    size_t nodes = shifted.find("\nnodes ");
    shifted.replace(nodes, 7, "\nnodes 1");  // a node count the patches do not hold
    CHECK_THROWS_WITH_AS(ink::parseHrbf(shifted, "m.surface"), doctest::Contains("but the patches hold"), ink::Error);
}

TEST_CASE("pu: the seam figure is small on consistent data, and the roughness finds normals that disagree (issue 24)" *
          doctest::test_suite("unit")) {
    // The analytic torus: its points and normals agree, so the seams add little and the surface is smooth.
    const ink::OrientedPoints exact = ink::torusPoints(64, 24);
    const ink::Model smooth = ink::fitModel(exact, {});
    const ink::PuSeams& a = smooth.patches.seams;
    INFO("exact: tilt p95 " << a.normalDegP95 << "°, seam/patch p95 " << a.curvatureRatioP95 << ", roughness "
                            << a.roughnessMedian << " / " << a.roughnessP95);
    CHECK(a.samples > 200);
    CHECK(a.normalDegP95 < 0.5);
    CHECK(a.curvatureRatioP95 < 0.3);
    CHECK(a.roughnessMedian < 0.1);
    // The same points with every normal tilted by 6° in a direction of its own: data the flat face samples used
    // to give. The surface ripples between the points; the roughness says so.
    ink::OrientedPoints tilted = exact;
    for (size_t i = 0; i < tilted.normals.size(); ++i) {
        const Eigen::Vector3d n = tilted.normals[i], t = n.unitOrthogonal();
        const double turn = 0.7 * double(i), angle = 6.0 * M_PI / 180;
        const Eigen::Vector3d d = std::cos(turn) * t + std::sin(turn) * n.cross(t);
        tilted.normals[i] = (std::cos(angle) * n + std::sin(angle) * d).normalized();
    }
    const ink::PuSeams& b = ink::fitModel(tilted, {}).patches.seams;
    INFO("tilted: roughness " << b.roughnessMedian << " / " << b.roughnessP95);
    CHECK(b.roughnessMedian > 3 * a.roughnessMedian);
}

TEST_CASE("pu: a version 3 .hrbf file loads as the model the device draws, and saves again to the same bytes" *
          doctest::test_suite("unit")) {
    CHECK(ink::crc32c("123456789") == 0xE3069283u);  // CRC-32C's check value
    CHECK(ink::crc32c("6789", ink::crc32c("12345")) == 0xE3069283u);
    TempDir dir;
    ink::Model fitted = ink::loadModel(kBunny, {800});
    const ink::Surface& a = fitted.surface;
    std::string path = dir / "bunny.hrbf";
    ink::saveHrbf(path, a);  // binary by default
    const std::string bytes = ink::readFileCapped(path, 1 << 30, "too big");
    REQUIRE(bytes.size() >= 128);
    CHECK(bytes.compare(0, 8, ink::kHrbf3Magic) == 0);
    CHECK(bytes.size() % 64 == 0);
    // Far smaller than the text: 28 bytes a node, 24 a point, 34 a patch.
    const size_t textBytes = ink::encodeHrbf(a, ink::HrbfFormat::Text).size();
    CHECK(bytes.size() * 4 < textBytes);

    ink::Model loaded = ink::loadModel(path, {});
    const ink::Surface& b = loaded.surface;
    REQUIRE(b.method == ink::FitMethod::PartitionOfUnity);
    REQUIRE(b.size() == a.size());
    REQUIRE(b.pu.patches.size() == a.pu.patches.size());
    REQUIRE(b.pu.nodes.size() == a.pu.nodes.size());
    CHECK(b.seeds == a.seeds);                      // stored, not chosen again
    CHECK(b.pu.coarse.alpha == a.pu.coarse.alpha);  // the far field in double
    // The float evaluation, what the device draws, is the same bit for bit; so are the fit's figures.
    ink::PuFloat fa(a.pu), fb(b.pu);
    for (double u : {-0.4, -0.1, 0.0, 0.23, 0.5}) {
        Eigen::Vector3f x(float(u), float(0.3 * u - 0.05), float(0.1 - u)), ga, gb;
        float va = fa.eval(x, ga), vb = fb.eval(x, gb);
        CHECK(std::memcmp(&va, &vb, sizeof va) == 0);
        CHECK(ga == gb);
    }
    CHECK(loaded.fit.maxDistance == fitted.fit.maxDistance);
    CHECK(std::abs(loaded.fit.maxNormalAngleDeg - fitted.fit.maxNormalAngleDeg) < 1e-5);  // normals in float
    // The double model moved by float rounding only.
    for (size_t j = 0; j < a.size(); j += 37) CHECK(std::abs(b.f(a.centers[j])) < 1e-6);
    // Saving the loaded model again gives the same bytes.
    CHECK(ink::encodeHrbf(b, ink::HrbfFormat::Binary) == bytes);

    // Hostile or damaged files: one line naming the problem.
    auto refused = [&](const std::string& file, const std::string& message) {
        CHECK_THROWS_WITH_AS(ink::parseHrbf(file, "m.hrbf"), doctest::Contains(message.c_str()), ink::Error);
    };
    refused(bytes.substr(0, 100), "m.hrbf: truncated: 100 bytes, shorter than the 128-byte version 3 header");
    refused(bytes.substr(0, bytes.size() - 64), "(truncated)");
    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x10;
    refused(flipped, "m.hrbf: checksum mismatch");
    // Counts and values that the checksum would not stop (a file written to deceive): refused all the same.
    auto sealed = [](std::string file) {
        std::memset(file.data() + ink::kHrbf3ChecksumOffset, 0, 4);
        const uint32_t crc = ink::crc32c(file);
        std::memcpy(file.data() + ink::kHrbf3ChecksumOffset, &crc, 4);
        return file;
    };
    CHECK_NOTHROW(ink::parseHrbf(sealed(bytes), "m.hrbf"));
    auto withU32 = [&](size_t at, uint32_t v) {
        std::string file = bytes;
        std::memcpy(file.data() + at, &v, 4);
        return sealed(file);
    };
    refused(withU32(8, 4), "unsupported binary version 4");
    refused(withU32(12, 7), "unknown model kind 7");
    refused(withU32(32, 0xFFFFFFFFu), "need");  // points: the size does not add up
    refused(withU32(44, 7), "need");            // nodes
    refused(withU32(36, 5000), "5000 far-field centres: a model holds 2 to 4000");
    refused(withU32(48, 0), "0 seeds");
    // Inside the arrays: a NaN, a node count out of range, a node outside its ball.
    const uint32_t farField = 256;  // the arrays' offsets (docs/hrbf-format.md)
    uint32_t counts[6];
    std::memcpy(counts, bytes.data() + 32, sizeof counts);
    REQUIRE(counts[1] <= farField);
    auto up = [](size_t x) { return (x + 63) / 64 * 64; };
    const size_t patches = up(128 + counts[1] * 80), nodeCounts = up(patches + counts[2] * 32),
                 nodes = up(nodeCounts + counts[2] * 2);
    std::string nan = bytes;
    const float quiet = std::nanf("");
    std::memcpy(nan.data() + patches + 12, &quiet, 4);
    refused(sealed(nan), "patch 1: a value is not finite");
    std::string big = bytes;
    const uint16_t many = 1025;
    std::memcpy(big.data() + nodeCounts, &many, 2);
    refused(sealed(big), "patch 1: 1025 is not a patch's node count");
    std::string outside = bytes;
    const float far = 2.0f;
    std::memcpy(outside.data() + nodes, &far, 4);
    refused(sealed(outside), "node 1: it lies outside its patch");
    std::string padded = bytes;
    padded[nodes - 1] = 1;  // padding after the node counts (they end short of 64 bytes here)
    if (counts[2] * 2 % 64 != 0) refused(sealed(padded), "non-zero padding");

    // The writer checks what it wrote with the reader, without copying the arrays out: a model that would make
    // a file that cannot be loaded is refused before anything is written, naming what is wrong.
    auto unsaveable = [&](const ink::Surface& model, const std::string& message) {
        const std::string target = dir / "refused.hrbf";
        CHECK_THROWS_WITH_AS(ink::saveHrbf(target, model), doctest::Contains(message.c_str()), ink::Error);
        CHECK_FALSE(std::filesystem::exists(target));
    };
    ink::Surface overflowing = b;
    overflowing.pu.nodes[5].alpha = 1e39;  // beyond float
    unsaveable(overflowing, "node 6: a value is not finite");
    ink::Surface zeroNormal = b;
    zeroNormal.normals[7] = Eigen::Vector3d::Zero();
    unsaveable(zeroNormal, "point 8: normal is zero");
    ink::Surface outsideBox = b;
    outsideBox.centers[9].x() = 1.5;
    unsaveable(outsideBox, "centre 10 lies outside the normalized box");
    ink::Surface farPatch = b;
    farPatch.pu.patches[3].radius = 5;
    unsaveable(farPatch, "patch 4: a patch's radius must be in (0, 4]");

    // Versions 1 and 2 still read, by content, whatever the name says.
    std::string text = dir / "text.hrbf";
    ink::saveHrbf(text, a, ink::HrbfFormat::Text);
    CHECK(ink::loadHrbf(text).pu.nodes.size() == a.pu.nodes.size());
    ink::Model global = ink::loadModel(kBunny, {300, ink::FitMethod::Global});
    const std::string g3 = ink::encodeHrbf(global.surface, ink::HrbfFormat::Binary);
    ink::Surface g = ink::parseHrbf(g3, "g.hrbf");
    CHECK(g.global.alpha == global.surface.global.alpha);  // the global fit in double: exact
    CHECK(ink::encodeHrbf(g, ink::HrbfFormat::Binary) == g3);
    CHECK(ink::parseHrbf(ink::encodeHrbf(global.surface, ink::HrbfFormat::Text), "g1.hrbf").global.beta ==
          global.surface.global.beta);
}

TEST_CASE("pu: the fit is the same on one thread and on several" * doctest::test_suite("unit")) {
    // The patches, their supports, the seeds and the figures: everything the file holds, bit for bit.
    ink::OrientedPoints bunny = ink::loadPoints(kBunny);
    auto fitOn = [&](unsigned threads) {
        ink::setWorkerThreads(threads);
        ink::Model m = ink::fitModel(bunny, {});
        ink::setWorkerThreads(0);
        return std::make_tuple(ink::encodeHrbf(m.surface, ink::HrbfFormat::Text), m.fit.maxDistance,
                               m.surface.pu.grid.cellStart, m.surface.pu.grid.cellPatches);
    };
    const auto one = fitOn(1), three = fitOn(3);
    CHECK(std::get<0>(one).size() > 1000000);  // the bunny with its face samples: 1,120 patches
    CHECK(std::get<0>(one) == std::get<0>(three));
    CHECK(std::get<1>(one) == std::get<1>(three));
    CHECK(std::get<2>(one) == std::get<2>(three));
    CHECK(std::get<3>(one) == std::get<3>(three));

    // The grid of more patches than one chunk of its work (4096): filled on several threads, each cell's patches
    // then sorted, it lists the same patches in the same order as on one thread, in patch order.
    std::vector<ink::PuPatch> patches(20000);
    uint64_t state = 7;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * 0x1.0p-53;
    };
    for (ink::PuPatch& p : patches) {
        p.center = Vector3d(next(), next(), next());
        p.radius = 0.03 + 0.03 * next();
    }
    ink::setWorkerThreads(1);
    const ink::PuGrid serial = ink::buildPuGrid(patches);
    ink::setWorkerThreads(3);
    const ink::PuGrid parallel = ink::buildPuGrid(patches);
    ink::setWorkerThreads(0);
    CHECK(serial.cellStart == parallel.cellStart);
    CHECK(serial.cellPatches == parallel.cellPatches);
    REQUIRE(serial.cellPatches.size() > 100000);
    for (size_t c = 0; c + 1 < serial.cellStart.size(); ++c)
        CHECK(std::is_sorted(serial.cellPatches.begin() + serial.cellStart[c],
                             serial.cellPatches.begin() + serial.cellStart[c + 1]));
}

// The far field follows a large fit's thin parts with more points (PuOptions::coarsePointsLarge): 256 up to 8192
// points, 384 above (the Spider's legs: 98.4% → 99.4% of the refined points on its mesh, docs/fitting.md).
TEST_CASE("pu: a large fit gets the finer far field" * doctest::test_suite("unit")) {
    auto farField = [](uint32_t u, uint32_t v) {
        ink::OrientedPoints torus = ink::torusPoints(u, v);
        ink::PuStats stats;
        const ink::PuHrbf model = ink::fitPuHrbf(torus.positions, torus.normals, {}, &stats);
        return std::make_pair(torus.positions.size(), model.coarse.size());
    };
    const auto small = farField(80, 40), large = farField(160, 64);
    CHECK(small.first <= 8192);
    CHECK(small.second == 256);
    CHECK(large.first > 8192);
    CHECK(large.second == 384);
}
