// Presets as the viewer saves them (presetJson) read back by the same parser the command line uses.
#include "../apps/preset.h"

#include <doctest/doctest.h>

TEST_CASE("preset: what presetJson writes, parsePreset reads back to the same values") {
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
    REQUIRE(q.light);
    for (int i = 0; i < 3; ++i) CHECK((*q.light)[i] == doctest::Approx((*p.light)[i]));
    CHECK(q.up == p.up);
    // Numbers to 4 decimals, keys in the order docs/usage.md lists them; an empty preset is an empty object.
    CHECK(text.find("\"tau\": 0.12,") != std::string::npos);
    CHECK(text.find("\"style\"") < text.find("\"up\""));
    CHECK(app::presetJson(app::Preset{}) == "{}\n");
}
