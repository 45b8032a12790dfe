// Near-coincident points: a mesh's split vertices at creases (normals 90° apart, 10⁻⁷ of the size apart) used
// to make the fit fail as ill-conditioned. They are merged with averaged normals, or dropped where the normals
// cancel, with a note saying how many.
#include "base/common.h"
#include "surface/clean.h"
#include "surface/model.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

using Eigen::Vector3d;

namespace {

// A closed cylinder (radius ½, height 1) as a flat-shaded mesh gives it: the caps' rim vertices sit `offset`
// (relative) inside the side's rim vertices, with the caps' normals. n around, `rings` rings on the side.
ink::OrientedPoints splitCylinder(int n, int rings, double offset) {
    ink::OrientedPoints p;
    for (int r = 0; r <= rings; ++r)
        for (int i = 0; i < n; ++i) {
            double a = 2 * M_PI * i / n, z = -0.5 + double(r) / rings;
            p.positions.emplace_back(0.5 * std::cos(a), 0.5 * std::sin(a), z);
            p.normals.emplace_back(std::cos(a), std::sin(a), 0);
        }
    for (int s : {-1, 1})
        for (int k = 0; k <= 3; ++k)
            for (int i = 0; i < (k == 0 ? 1 : n); ++i) {
                double a = 2 * M_PI * (i + (k == 3 ? 0.0 : 0.5 * k)) / n, radius = 0.5 * k / 3.0;
                double shrink = k == 3 ? 1 - offset : 1;
                p.positions.emplace_back(radius * std::cos(a) * shrink, radius * std::sin(a) * shrink, 0.5 * s);
                p.normals.emplace_back(0, 0, s);
            }
    return p;
}

struct Notes {
    std::vector<std::string> lines;
    ink::Reporter reporter;
    Notes() {
        reporter.note = [this](const std::string& line) { lines.push_back(line); };
    }
};

}  // namespace

TEST_CASE("creases: split vertices 1e-7 to 1e-3 apart fit, merged with averaged normals and a note" *
          doctest::test_suite("unit")) {
    for (double offset : {1e-7, 1e-5, 1e-3}) {
        CAPTURE(offset);
        Notes notes;
        ink::Model model;
        {
            ink::ScopedReporter reporting(notes.reporter);
            model = ink::fitModel(splitCylinder(40, 8, offset), {});
        }
        // 80 rim vertices of the caps each merged into the side's vertex beside it.
        REQUIRE(notes.lines.size() == 1);
        CHECK(notes.lines[0].find("merged 80 control points") == 0);
        CHECK(model.fit.controlPoints == 40 * 9 + 2 * (1 + 3 * 40) - 80);
        CHECK(model.fit.maxDistance < 1e-6);  // evaluated in float, as the device does
        // At a rim, the merged normal is halfway between the side's and the cap's: the edge is rounded.
        Eigen::Vector3d rim = model.surface.frame.toNormalized(Vector3d(0.5, 0, 0.5)), g;
        model.surface.eval(rim, g);
        g.normalize();
        CHECK(std::abs(g.x() - std::sqrt(0.5)) < 0.02);
        CHECK(std::abs(g.z() - std::sqrt(0.5)) < 0.02);
        CHECK(std::abs(model.surface.f(rim)) < 1e-9);
    }
}

TEST_CASE("creases: points far apart are left alone; normals that cancel are dropped, with a note" *
          doctest::test_suite("unit")) {
    ink::OrientedPoints apart = splitCylinder(40, 8, 0.05);
    size_t count = apart.positions.size();
    CHECK(ink::mergeNearPoints(apart, 1e-3).merged == 0);
    CHECK(apart.positions.size() == count);

    // Two sides of a sheet at the same place: normals opposite.
    ink::OrientedPoints sheet;
    for (int i = 0; i < 6; ++i) {
        sheet.positions.emplace_back(i, 0, 0);
        sheet.normals.emplace_back(0, 0, 1);
        sheet.positions.emplace_back(i, 1e-9, 0);
        sheet.normals.emplace_back(0, 0, -1);
    }
    sheet.positions.emplace_back(0, 5, 0);
    sheet.normals.emplace_back(0, 1, 1);
    ink::OrientedPoints plate = sheet;
    ink::NearMerge result = ink::mergeNearPoints(sheet, 1e-6);
    CHECK(result.dropped == 12);
    CHECK(result.merged == 0);
    REQUIRE(sheet.positions.size() == 1);
    CHECK(sheet.positions[0] == Vector3d(0, 5, 0));
    // The two sides of a thin plate, opposed farther apart than opposedTolerance, are no pair: both stay.
    for (size_t i = 1; i < plate.positions.size(); i += 2) plate.positions[i].y() = 1e-7;
    result = ink::mergeNearPoints(plate, 1e-6, 1e-8);
    CHECK(result.dropped == 0);
    CHECK(result.merged == 0);
    CHECK(plate.positions.size() == 13);
    // Within it they are one place, as before.
    result = ink::mergeNearPoints(plate, 1e-6, 1e-6);
    CHECK(result.dropped == 12);

    // Three normals 90° apart (a cube's corner) average to the diagonal.
    ink::OrientedPoints corner;
    for (Vector3d n : {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()}) {
        corner.positions.emplace_back(1, 1, 1);
        corner.normals.push_back(n);
    }
    result = ink::mergeNearPoints(corner, 1e-6);
    CHECK(result.merged == 2);
    REQUIRE(corner.normals.size() == 1);
    CHECK((corner.normals[0] - Vector3d(1, 1, 1).normalized()).norm() < 1e-12);
}
