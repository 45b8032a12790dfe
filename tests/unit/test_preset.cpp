// Presets as the viewer saves them (presetJson) read back by the same parser the command line uses.
#include "../../apps/cli/preset.h"
#include "base/common.h"

#include <doctest/doctest.h>

TEST_CASE("preset: what presetJson writes, parsePreset reads back to the same values" * doctest::test_suite("unit")) {
    app::Preset p;
    p.style = "both";
    p.direction = "curvature-max";
    p.levels = 5;
    p.passes = 3;
    p.ink = "#1d1a33";
    p.paper = "#f6f1e4";
    p.dotSize = 1.75f;
    p.silhouetteSize = 2.4f;
    p.tau = 0.12f;
    p.tone = 2.0f;
    p.inkDensity = 0.8f;
    p.hiddenLines = true;
    p.hiddenDotSize = 2.25f;
    p.hiddenContourWidth = 0.8f;
    p.hiddenOpacity = 0.3f;
    p.light = std::vector<float>{-0.5f, 0.6f, 0.65f};
    p.up = "-z";
    const std::string text = app::presetJson(p);
    const app::Preset q = app::parsePreset(text, "saved");
    CHECK(q.style == p.style);
    CHECK(q.direction == p.direction);
    CHECK(q.levels == p.levels);
    CHECK(q.passes == p.passes);
    CHECK(q.ink == p.ink);
    CHECK(q.paper == p.paper);
    CHECK(*q.dotSize == doctest::Approx(*p.dotSize));
    CHECK(*q.silhouetteSize == doctest::Approx(*p.silhouetteSize));
    CHECK(*q.tau == doctest::Approx(*p.tau));
    CHECK(*q.tone == doctest::Approx(*p.tone));
    CHECK(*q.inkDensity == doctest::Approx(*p.inkDensity));
    CHECK(q.hiddenLines == p.hiddenLines);
    CHECK(*q.hiddenDotSize == doctest::Approx(*p.hiddenDotSize));
    CHECK(*q.hiddenContourWidth == doctest::Approx(*p.hiddenContourWidth));
    CHECK(*q.hiddenOpacity == doctest::Approx(*p.hiddenOpacity));
    CHECK(text.find("\"hidden_opacity\": 0.3,") != std::string::npos);
    REQUIRE(q.light);
    for (int i = 0; i < 3; ++i) CHECK((*q.light)[i] == doctest::Approx((*p.light)[i]));
    CHECK(q.up == p.up);
    // Numbers to 4 decimals, keys in the order docs/usage.md lists them; an empty preset is an empty object.
    CHECK(text.find("\"tau\": 0.12,") != std::string::npos);
    CHECK(text.find("\"style\"") < text.find("\"up\""));
    CHECK(app::presetJson(app::Preset{}) == "{}\n");
}

TEST_CASE("preset: the pen lines' keys are written and read back" * doctest::test_suite("unit")) {
    app::Preset p;
    p.style = "stipple+contours+hatching";
    p.contourWidth = 2.5f;
    p.hatchWidth = 0.75f;
    p.halo = 0.0f;
    p.hatchSpacing = 0.0123f;
    p.hatchFamilies = 1u;
    const std::string text = app::presetJson(p);
    const app::Preset q = app::parsePreset(text, "saved");
    CHECK(q.style == p.style);
    CHECK(*q.contourWidth == doctest::Approx(2.5));
    CHECK(*q.hatchWidth == doctest::Approx(0.75));
    CHECK(*q.halo == 0.0f);
    CHECK(*q.hatchSpacing == doctest::Approx(0.0123));
    CHECK(q.hatchFamilies == 1u);
    CHECK(text.find("\"hatch_families\": 1") != std::string::npos);
}

// The viewer's copy and paste of the camera (docs/viewer.md).
TEST_CASE("camera text: the JSON the viewer copies reads back to the same camera and the same text" *
          doctest::test_suite("unit")) {
    app::CameraText c;
    c.azimuthDeg = -123.45f;
    c.elevationDeg = 101.5f;  // over the pole: a free orbit
    c.distance = 0.85f;
    c.target = std::array<float, 3>{0.125f, -0.03f, 0.0f};
    c.up = "-z";
    c.fovDeg = 27.5f;
    c.freeOrbit = true;
    const std::string text = app::cameraJson(c);
    CHECK(text ==
          "{\"azimuth_deg\":-123.45,\"elevation_deg\":101.5,\"distance\":0.85,\"target\":[0.125,-0.03,0.0],"
          "\"up\":\"-z\",\"fov_deg\":27.5,\"free_orbit\":true}");
    const app::CameraText d = app::parseCameraText(text);
    CHECK(d.azimuthDeg == c.azimuthDeg);
    CHECK(d.elevationDeg == c.elevationDeg);
    CHECK(d.distance == c.distance);
    REQUIRE(d.target);
    CHECK(*d.target == *c.target);
    CHECK(d.up == c.up);
    CHECK(d.fovDeg == c.fovDeg);
    CHECK(d.freeOrbit == c.freeOrbit);
    CHECK(app::cameraJson(d) == text);  // text -> camera -> the same text

    // A capture's frames[].camera (docs/capture.md) is a camera too: what it lacks stays as it was.
    const app::CameraText e = app::parseCameraText(
        "{\"azimuth_deg\": 150.0, \"elevation_deg\": 15.0, \"distance\": 1.6, \"target\": [0.0, 0.0, 0.0]}");
    CHECK(e.azimuthDeg == 150.0f);
    CHECK(e.target);
    CHECK(!e.up);
    CHECK(!e.fovDeg);
    CHECK(!e.freeOrbit);
    // And the command line's form, as the viewer's "as options" copies it.
    const app::CameraText f = app::parseCameraText("--camera 12.50 -30.00 2.250 --up z\n");
    CHECK(f.azimuthDeg == 12.5f);
    CHECK(f.elevationDeg == -30.0f);
    CHECK(f.distance == 2.25f);
    CHECK(f.up == "z");
}

TEST_CASE("camera text: what is not a camera is refused, saying why" * doctest::test_suite("unit")) {
    auto why = [](const std::string& text) {
        try {
            app::parseCameraText(text);
        } catch (const ink::Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    CHECK(why("") == "not a camera: the text is empty");
    CHECK(why("hello world") == "not a camera: expected a JSON object or --camera AZ EL DIST [--up AXIS], not 'hello'");
    CHECK(why("{\"azimuth_deg\": 1") == "not a camera: the text is not valid JSON");
    CHECK(why("[1, 2, 3]") == "not a camera: expected a JSON object or --camera AZ EL DIST [--up AXIS], not '[1,'");
    CHECK(why("{\"azimuth_deg\": 1, \"elevation_deg\": 2}") ==
          "not a camera: it needs \"azimuth_deg\", \"elevation_deg\" and \"distance\"");
    CHECK(why("{\"azimuth_deg\": 1, \"elevation_deg\": 2, \"distance\": 0}") ==
          "not a camera: the distance must be in [0.05, 100] diagonals");
    CHECK(why("{\"azimuth_deg\": \"1\", \"elevation_deg\": 2, \"distance\": 1}") ==
          "not a camera: \"azimuth_deg\" must be a number");
    CHECK(why("{\"azimuth_deg\": 1, \"elevation_deg\": 2, \"distance\": 1, \"zoom\": 2}") ==
          "not a camera: unknown key 'zoom'");
    CHECK(why("{\"azimuth_deg\": 1, \"elevation_deg\": 2, \"distance\": 1, \"up\": \"w\"}") ==
          "not a camera: \"up\" must be \"x\", \"-x\", \"y\", \"-y\", \"z\" or \"-z\"");
    CHECK(why("{\"azimuth_deg\": 1, \"elevation_deg\": 2, \"distance\": 1, \"target\": [0, 0]}") ==
          "not a camera: \"target\" must be an array of 3 numbers");
    CHECK(why("{\"azimuth_deg\": 1e300, \"elevation_deg\": 2, \"distance\": 1}") ==
          "not a camera: \"azimuth_deg\" must be a finite number");
    CHECK(why("--camera 1 2") == "not a camera: --camera needs three numbers: azimuth, elevation, distance");
    CHECK(why("--camera 1 2 x") == "not a camera: --camera needs three numbers: azimuth, elevation, distance");
    CHECK(why("--up z") == "not a camera: no --camera AZ EL DIST");
    CHECK(why(std::string(5000, ' ')) == "not a camera: the text is longer than 4 KiB");
}
