// Style presets (docs/usage.md, "Presets"): a JSON object of keys that mirror options. Parsed and
// validated on their own, without Vulkan or the command line, so that a fuzz target can call parsePreset
// on bytes (fuzz/fuzz_preset.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct Preset {
    std::optional<std::string> style, ink, paper, up, direction;
    std::optional<float> dotSize, silhouetteSize, tau, tone, inkDensity, contourWidth, hatchWidth, halo, hatchSpacing;
    std::optional<uint32_t> hatchFamilies;
    std::optional<bool> hiddenLines;
    std::optional<std::vector<float>> light;  // three finite numbers, not all zero
    std::optional<uint32_t> levels, passes;
};

// A preset is a few hundred bytes; this only stops a wrong file (or /dev/zero) being read.
constexpr size_t kMaxPresetBytes = size_t(1) << 20;

// Checks every key like the command line checks its option (type, size, range) and throws ink::Error
// naming `name` and the key. Unknown keys are refused.
Preset parsePreset(const std::string& bytes, const std::string& name);

// The preset as JSON text that parsePreset reads back to the same values (the keys it has, in a fixed order;
// numbers to 4 decimals).
std::string presetJson(const Preset& p);

}  // namespace app
