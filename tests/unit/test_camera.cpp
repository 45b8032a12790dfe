// The orbit camera: the turntable and the free orbit (the viewer's two camera modes).
#include "draw/camera.h"

#include <doctest/doctest.h>

#include <cmath>

namespace {

float largestDifference(const glm::mat4& a, const glm::mat4& b) {
    float d = 0;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) d = std::max(d, std::abs(a[c][r] - b[c][r]));
    return d;
}

}  // namespace

TEST_CASE("camera: a free orbit sees what the turntable sees below the poles, and tumbles over them smoothly" *
          doctest::test_suite("unit")) {
    for (ink::UpAxis up : {ink::UpAxis::PosY, ink::UpAxis::PosZ, ink::UpAxis::NegX}) {
        ink::Camera turntable;
        turntable.up = up;
        turntable.azimuthDeg = 35;
        for (float elevation : {-80.0f, -20.0f, 0.0f, 45.0f, 85.0f}) {
            turntable.elevationDeg = elevation;
            ink::Camera free = turntable;
            free.freeOrbit = true;
            CHECK(largestDifference(turntable.view(), free.view()) < 1e-5f);
        }
        // Over the pole: the eye moves on, and the view turns by the small step, without the turntable's flip.
        ink::Camera free = turntable;
        free.freeOrbit = true;
        free.elevationDeg = 89.5f;
        glm::mat4 before = free.view();
        free.elevationDeg = 90.0f;
        glm::mat4 at = free.view();
        free.elevationDeg = 90.5f;
        glm::mat4 after = free.view();
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) REQUIRE(std::isfinite(at[c][r]));
        CHECK(largestDifference(before, at) < 0.02f);
        CHECK(largestDifference(at, after) < 0.02f);
        // Half a turn of elevation later the camera is upside down: its up is the model's down.
        free.elevationDeg = 180.0f;
        glm::mat4 view = free.view();
        glm::vec3 cameraUp(view[0][1], view[1][1], view[2][1]);
        CHECK(glm::dot(cameraUp, ink::upBasis(up)[1]) == doctest::Approx(-1.0f).epsilon(1e-4));
    }
}
