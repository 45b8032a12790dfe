// libFuzzer target: app::parsePreset, the style preset reader, and app::parseCameraText, the viewer's pasted
// camera (apps/cli/preset.cpp). See docs/robustness.md.
// ink::Error is the answer to a bad preset; anything else (a JSON exception escaping, a crash, a sanitizer
// report, a value outside what the command line accepts) is a finding.
#include "base/common.h"
#include "preset.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

[[noreturn]] void broken(const char* what) {
    std::fprintf(stderr, "fuzz: a preset was accepted but breaks the command line's rules: %s\n", what);
    std::abort();
}

bool inRange(const std::optional<float>& v, float lo, float hi) { return !v || (*v >= lo && *v <= hi); }

}  // namespace

// A camera read from the clipboard: refused with ink::Error, or finite with a distance in (0.05, 100), and written
// back as text that reads back to the same text.
static void camera(const std::string& bytes) {
    app::CameraText c;
    try {
        c = app::parseCameraText(bytes);
    } catch (const ink::Error& e) {
        if (std::string(e.what()).empty()) broken("an empty error message");
        return;
    }
    if (!std::isfinite(c.azimuthDeg) || !std::isfinite(c.elevationDeg)) broken("camera angles not finite");
    if (!(c.distance >= 0.05f && c.distance <= 100)) broken("camera distance outside [0.05, 100]");
    const std::string text = app::cameraJson(c);
    if (app::cameraJson(app::parseCameraText(text)) != text) broken("camera text does not read back to itself");
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    camera(bytes);
    app::Preset p;
    try {
        p = app::parsePreset(bytes, "fuzz.json");
    } catch (const ink::Error& e) {
        if (std::string(e.what()).empty()) broken("an empty error message");
        return 0;
    }
    if (p.light) {
        if (p.light->size() != 3) broken("light is not 3 numbers");
        for (float v : *p.light)
            if (!std::isfinite(v)) broken("light is not finite");
    }
    if (p.levels && *p.levels > 15) broken("levels above 15");
    if (p.passes && (*p.passes < 1 || *p.passes > 64)) broken("passes outside 1..64");
    if (!inRange(p.dotSize, 0, 64) || (p.dotSize && !(*p.dotSize > 0))) broken("dot_size outside (0, 64]");
    if (!inRange(p.silhouetteSize, 0, 64) || (p.silhouetteSize && !(*p.silhouetteSize > 0)))
        broken("silhouette_size outside (0, 64]");
    if (!inRange(p.tau, 0, 1) || (p.tau && *p.tau >= 1)) broken("tau outside [0, 1)");
    if (!inRange(p.tone, 0, 16)) broken("tone outside [0, 16]");
    if (!inRange(p.inkDensity, 0, 100)) broken("ink_density outside [0, 100]");
    return 0;
}
