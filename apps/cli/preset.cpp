#include "preset.h"

#include "inkwell/files.h"
#include "inkwell/ranges.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

namespace app {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& name, const std::string& key, const std::string& what) {
    throw inkwell::Error("preset '" + name + "': \"" + key + "\" " + what);
}

std::string text(const json& value, const std::string& name, const std::string& key,
                 std::initializer_list<const char*> allowed = {}) {
    if (!value.is_string()) fail(name, key, "must be a string");
    std::string s = value.get<std::string>();
    if (allowed.size() == 0) return s;
    std::string list;
    for (const char* a : allowed) {
        if (s == a) return s;
        list += std::string(list.empty() ? "" : ", ") + a;
    }
    fail(name, key, "is " + inkwell::quoted(s) + ", not one of " + list);
}

double number(const json& value, const std::string& name, const std::string& key) {
    if (!value.is_number()) fail(name, key, "must be a number");
    double v = value.get<double>();
    if (!std::isfinite(v)) fail(name, key, "must be finite");
    return v;
}

// A number within its range of the one table (include/inkwell/ranges.h).
float ranged(const json& value, const std::string& name, const std::string& key, const inkwell::Range& range) {
    double v = number(value, name, key);
    if (!range.contains(v)) fail(name, key, "must be in " + range.text());
    return float(v);
}

uint32_t integer(const json& value, const std::string& name, const std::string& key, uint32_t lo, uint32_t hi) {
    const std::string range = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    if (!value.is_number()) fail(name, key, "must be " + range);
    double v = value.get<double>();  // 1e20 and 2.5 are numbers too: checked before any cast
    if (!(v >= lo && v <= hi) || v != std::floor(v)) fail(name, key, "must be " + range);
    return uint32_t(v);
}

uint32_t integer(const json& value, const std::string& name, const std::string& key, const inkwell::Range& range) {
    return integer(value, name, key, uint32_t(range.lo), uint32_t(range.hi));
}

std::string colour(const json& value, const std::string& name, const std::string& key) {
    std::string s = text(value, name, key);
    std::string hex = s.rfind('#', 0) == 0 ? s.substr(1) : s;
    if (hex.size() != 6 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
        fail(name, key, "is " + inkwell::quoted(s) + ", not a colour of the form #rrggbb");
    return s;
}

}  // namespace

Preset parsePreset(const std::string& bytes, const std::string& name) {
    json j;
    try {
        j = json::parse(bytes);
    } catch (const json::exception& e) {
        // nlohmann quotes the bytes it stopped at, an invalid UTF-8 byte too: escaped, not echoed.
        throw inkwell::Error("preset '" + name + "' is not valid JSON: " + inkwell::escapeText(e.what()));
    }
    if (!j.is_object()) throw inkwell::Error("preset '" + name + "' must be a JSON object");
    Preset p;
    for (auto& [key, value] : j.items()) {
        if (key == "style") {
            // Parts joined by '+' (finishOptions checks how they combine).
            p.style = text(value, name, key);
            std::string rest = *p.style + "+";
            for (size_t at = 0; (at = rest.find('+')) != std::string::npos; rest.erase(0, at + 1)) {
                std::string part = rest.substr(0, at);
                if (part != "stipple" && part != "direction" && part != "both" && part != "contours" &&
                    part != "hatching")
                    fail(name, key,
                         "is " + inkwell::quoted(*p.style) +
                             ", not parts of stipple, direction, both, contours, hatching joined by '+'");
            }
        } else if (key == "contour_width")
            p.contourWidth = ranged(value, name, key, inkwell::ranges::penWidth);
        else if (key == "hatch_width")
            p.hatchWidth = ranged(value, name, key, inkwell::ranges::penWidth);
        else if (key == "crease_width")
            p.creaseWidth = ranged(value, name, key, inkwell::ranges::penWidth);
        else if (key == "boundary_width")
            p.boundaryWidth = ranged(value, name, key, inkwell::ranges::penWidth);
        else if (key == "creases")
            p.creases = text(value, name, key, {"auto", "on", "off"});
        else if (key == "boundaries")
            p.boundaries = text(value, name, key, {"auto", "on", "off"});
        else if (key == "halo")
            p.halo = ranged(value, name, key, inkwell::ranges::halo);
        else if (key == "hatch_spacing")
            p.hatchSpacing = ranged(value, name, key, inkwell::ranges::hatchSpacing);
        else if (key == "hatch_families")
            p.hatchFamilies = integer(value, name, key, inkwell::ranges::hatchFamilies);
        else if (key == "direction")
            p.direction = text(value, name, key, {"axis", "curvature-min", "curvature-max"});
        else if (key == "up")
            p.up = text(value, name, key, {"auto", "x", "-x", "+x", "y", "-y", "+y", "z", "-z", "+z"});
        else if (key == "ink")
            p.ink = colour(value, name, key);
        else if (key == "paper")
            p.paper = colour(value, name, key);
        else if (key == "dot_size")
            p.dotSize = ranged(value, name, key, inkwell::ranges::dotSize);
        else if (key == "silhouette_size")
            p.silhouetteSize = ranged(value, name, key, inkwell::ranges::dotSize);
        else if (key == "tau")
            p.tau = ranged(value, name, key, inkwell::ranges::tau);
        else if (key == "tone")
            p.tone = ranged(value, name, key, inkwell::ranges::toneGamma);
        else if (key == "ink_density")
            p.inkDensity = ranged(value, name, key, inkwell::ranges::inkDensity);
        else if (key == "light_fixed") {
            if (!value.is_boolean()) fail(name, key, "must be true or false");
            p.lightFixed = value.get<bool>();
        } else if (key == "hidden_lines") {
            if (!value.is_boolean()) fail(name, key, "must be true or false");
            p.hiddenLines = value.get<bool>();
        } else if (key == "screen_spacing") {
            if (!value.is_boolean()) fail(name, key, "must be true or false");
            p.screenSpacing = value.get<bool>();
        } else if (key == "hidden_dot_size")
            p.hiddenDotSize = ranged(value, name, key, inkwell::ranges::dotSize);
        else if (key == "hidden_contour_width")
            p.hiddenContourWidth = ranged(value, name, key, inkwell::ranges::penWidth);
        else if (key == "hidden_opacity")
            p.hiddenOpacity = ranged(value, name, key, inkwell::ranges::hiddenOpacity);
        else if (key == "light") {
            if (!value.is_array() || value.size() != 3) fail(name, key, "must be an array of 3 numbers [x, y, z]");
            std::vector<float> l;
            for (const json& v : value) {
                double x = number(v, name, key);
                if (!(std::abs(x) <= double(std::numeric_limits<float>::max())))
                    fail(name, key, "must be a non-zero vector of numbers within float's range");
                l.push_back(float(x));
            }
            double length = std::sqrt(double(l[0]) * l[0] + double(l[1]) * l[1] + double(l[2]) * l[2]);
            if (!(length > 0) || !std::isfinite(length)) fail(name, key, "must be a non-zero vector");
            p.light = l;
        } else if (key == "levels")
            p.levels = integer(value, name, key, 0, uint32_t(inkwell::ranges::levels.hi));
        else if (key == "passes")
            p.passes = integer(value, name, key, inkwell::ranges::passes);
        else
            throw inkwell::Error("preset '" + name + "': unknown key " + inkwell::quoted(key));
    }
    return p;
}

std::string presetJson(const Preset& p) {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    auto rounded = [](float v) { return std::round(double(v) * 1e4) / 1e4; };
    auto put = [&](const char* key, const auto& value) {
        if (value) j[key] = *value;
    };
    auto putNumber = [&](const char* key, const std::optional<float>& value) {
        if (value) j[key] = rounded(*value);
    };
    put("style", p.style);
    put("direction", p.direction);
    put("levels", p.levels);
    put("passes", p.passes);
    put("ink", p.ink);
    put("paper", p.paper);
    putNumber("dot_size", p.dotSize);
    putNumber("silhouette_size", p.silhouetteSize);
    putNumber("tau", p.tau);
    putNumber("tone", p.tone);
    putNumber("ink_density", p.inkDensity);
    put("hidden_lines", p.hiddenLines);
    put("screen_spacing", p.screenSpacing);
    put("light_fixed", p.lightFixed);
    putNumber("hidden_dot_size", p.hiddenDotSize);
    putNumber("hidden_contour_width", p.hiddenContourWidth);
    putNumber("hidden_opacity", p.hiddenOpacity);
    putNumber("contour_width", p.contourWidth);
    putNumber("hatch_width", p.hatchWidth);
    putNumber("halo", p.halo);
    putNumber("hatch_spacing", p.hatchSpacing);
    put("hatch_families", p.hatchFamilies);
    put("creases", p.creases);
    putNumber("crease_width", p.creaseWidth);
    put("boundaries", p.boundaries);
    putNumber("boundary_width", p.boundaryWidth);
    if (p.light) j["light"] = {rounded((*p.light)[0]), rounded((*p.light)[1]), rounded((*p.light)[2])};
    put("up", p.up);
    return j.dump(2) + "\n";
}

namespace {

[[noreturn]] void notCamera(const std::string& why) { throw inkwell::Error("not a camera: " + why); }

double cameraNumber(const json& value, const std::string& key) {
    if (!value.is_number()) notCamera("\"" + key + "\" must be a number");
    double v = value.get<double>();
    if (!(std::abs(v) <= 1e6)) notCamera("\"" + key + "\" must be a finite number");
    return v;
}

bool isUpAxis(const std::string& s) {
    for (const char* a : {"x", "-x", "+x", "y", "-y", "+y", "z", "-z", "+z"})
        if (s == a) return true;
    return false;
}

void checkDistance(double d) {
    if (!(d >= 0.05 && d <= 100)) notCamera("the distance must be in [0.05, 100] diagonals");
}

// "--camera AZ EL DIST [--up AXIS]", the options `inkwell render` takes.
CameraText cameraFromOptions(const std::string& text) {
    std::istringstream in(text);
    CameraText c;
    std::string word;
    bool camera = false;
    while (in >> word) {
        if (word == "--camera") {
            double v[3];
            for (double& x : v) {
                std::string number;
                if (!(in >> number)) notCamera("--camera needs three numbers: azimuth, elevation, distance");
                size_t used = 0;
                try {
                    x = std::stod(number, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (used != number.size() || !(std::abs(x) <= 1e6))
                    notCamera("--camera needs three numbers: azimuth, elevation, distance");
            }
            checkDistance(v[2]);
            c.azimuthDeg = float(v[0]);
            c.elevationDeg = float(v[1]);
            c.distance = float(v[2]);
            camera = true;
        } else if (word == "--up") {
            std::string axis;
            if (!(in >> axis) || !isUpAxis(axis)) notCamera("--up must be x, -x, y, -y, z or -z");
            c.up = axis;
        } else {
            notCamera("expected a JSON object or --camera AZ EL DIST [--up AXIS], not " + inkwell::quoted(word));
        }
    }
    if (!camera) notCamera("no --camera AZ EL DIST");
    return c;
}

}  // namespace

CameraText parseCameraText(const std::string& text) {
    if (text.size() > 4096) notCamera("the text is longer than 4 KiB");
    const size_t start = text.find_first_not_of(" \t\r\n");
    if (start == std::string::npos) notCamera("the text is empty");
    if (text[start] != '{') return cameraFromOptions(text);
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception&) {
        notCamera("the text is not valid JSON");
    }
    if (!j.is_object()) notCamera("the JSON is not an object");
    CameraText c;
    bool seen[3] = {false, false, false};
    for (auto& [key, value] : j.items()) {
        if (key == "azimuth_deg") {
            c.azimuthDeg = float(cameraNumber(value, key));
            seen[0] = true;
        } else if (key == "elevation_deg") {
            c.elevationDeg = float(cameraNumber(value, key));
            seen[1] = true;
        } else if (key == "distance") {
            double d = cameraNumber(value, key);
            checkDistance(d);
            c.distance = float(d);
            seen[2] = true;
        } else if (key == "target") {
            if (!value.is_array() || value.size() != 3) notCamera("\"target\" must be an array of 3 numbers");
            std::array<float, 3> t{};
            for (size_t i = 0; i < 3; ++i) t[i] = float(cameraNumber(value[i], key));
            c.target = t;
        } else if (key == "up") {
            if (!value.is_string() || !isUpAxis(value.get<std::string>()))
                notCamera("\"up\" must be \"x\", \"-x\", \"y\", \"-y\", \"z\" or \"-z\"");
            c.up = value.get<std::string>();
        } else if (key == "fov_deg") {
            double f = cameraNumber(value, key);
            if (!(f >= 1 && f <= 170)) notCamera("\"fov_deg\" must be in [1, 170] degrees");
            c.fovDeg = float(f);
        } else if (key == "free_orbit") {
            if (!value.is_boolean()) notCamera("\"free_orbit\" must be true or false");
            c.freeOrbit = value.get<bool>();
        } else {
            notCamera("unknown key " + inkwell::quoted(key));
        }
    }
    if (!seen[0] || !seen[1] || !seen[2]) notCamera("it needs \"azimuth_deg\", \"elevation_deg\" and \"distance\"");
    return c;
}

std::string cameraJson(const CameraText& c) {
    auto rounded = [](float v) { return std::round(double(v) * 1e4) / 1e4 + 0.0; };  // + 0.0: no "-0.0"
    const std::array<float, 3> target = c.target.value_or(std::array<float, 3>{0, 0, 0});
    nlohmann::ordered_json j = {{"azimuth_deg", rounded(c.azimuthDeg)},
                                {"elevation_deg", rounded(c.elevationDeg)},
                                {"distance", rounded(c.distance)},
                                {"target", {rounded(target[0]), rounded(target[1]), rounded(target[2])}},
                                {"up", c.up.value_or("y")},
                                {"fov_deg", rounded(c.fovDeg.value_or(40.0f))},
                                {"free_orbit", c.freeOrbit.value_or(false)}};
    return j.dump();
}

}  // namespace app
