// Style presets (docs/usage.md, "Presets"): a JSON object of keys that mirror options. Parsed and
// validated on their own, without Vulkan or the command line, so that a fuzz target can call parsePreset
// on bytes (fuzz/fuzz_preset.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct Preset {
    std::optional<std::string> style, ink, paper, up, direction;
    std::optional<std::string> creases, boundaries;  // auto, on, off
    std::optional<float> dotSize, silhouetteSize, tau, tone, inkDensity, contourWidth, hatchWidth, halo, hatchSpacing;
    std::optional<float> creaseWidth, boundaryWidth;
    std::optional<uint32_t> hatchFamilies;
    std::optional<bool> hiddenLines;
    std::optional<bool> screenSpacing;  // the stipples spaced on the page (default: true)
    std::optional<bool> lightFixed;     // the light fixed to the model (default: it follows the camera)
    std::optional<float> hiddenDotSize, hiddenContourWidth, hiddenOpacity;
    std::optional<std::vector<float>> light;  // three finite numbers, not all zero
    std::optional<uint32_t> levels, passes;
};

// A preset is a few hundred bytes; this only stops a wrong file (or /dev/zero) being read.
constexpr size_t kMaxPresetBytes = size_t(1) << 20;

// Checks every key like the command line checks its option (type, size, range) and throws inkwell::Error
// naming `name` and the key. Unknown keys are refused.
Preset parsePreset(const std::string& bytes, const std::string& name);

// The preset as JSON text that parsePreset reads back to the same values (the keys it has, in a fixed order;
// numbers to 4 decimals).
std::string presetJson(const Preset& p);

// A camera as text: what the viewer's "copy camera" puts on the clipboard and "paste camera" reads back
// (docs/viewer.md). One JSON object, the orbit camera of a capture's frames[].camera (docs/capture.md) with the
// view's up axis, field of view and orbit mode:
//   {"azimuth_deg":30.0,"elevation_deg":15.0,"distance":1.6,"target":[0.0,0.0,0.0],"up":"y","fov_deg":40.0,
//    "free_orbit":false}
// The first three keys are needed, the others keep the viewer's current value when absent. The command line's
// form, "--camera AZ EL DIST" with an optional "--up AXIS" (the viewer's "as options"), is read too.
struct CameraText {
    float azimuthDeg = 30, elevationDeg = 15, distance = 1.6f;
    std::optional<std::array<float, 3>> target;
    std::optional<std::string> up;  // x, -x, y, -y, z, -z
    std::optional<float> fovDeg;
    std::optional<bool> freeOrbit;
};
// Throws inkwell::Error saying what is not a camera in `text` (at most a few KiB are looked at).
CameraText parseCameraText(const std::string& text);
// One line of JSON that parseCameraText reads back to the same values (every key; numbers to 4 decimals), and
// that it writes again as the same text.
std::string cameraJson(const CameraText& c);

}  // namespace app
