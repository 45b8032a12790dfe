// What the inkwell commands share: options, the Vulkan session, the scene (model + refinements), JSON stats.
#pragma once

#include "inkwell/inkwell.h"

#include "api/stats_json.h"
#include "base/common.h"
#include "draw/camera.h"
#include "draw/renderer.h"
#include "draw/scene.h"
#include "gpu/context.h"
#include "refine/refine.h"
#include "surface/model.h"
#include "surface/viewpoint.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace app {

using nlohmann::json;
using Clock = std::chrono::steady_clock;
using ink::secondsSince;

using ink::DrawStyle;
using inkwell::api::deviceJson;
using inkwell::api::fitJson;
using inkwell::api::hostMsJson;
using inkwell::api::levelsJson;
using inkwell::api::linesJson;
using inkwell::api::pageJson;
using inkwell::api::plotJson;
using inkwell::api::spacingJson;

struct Options;
// --control-points and --fit as the engine takes them.
ink::ModelOptions modelOptions(const Options& o);

struct Options {
    std::string model;
    size_t controlPoints = 0;
    std::string fit = "pu";  // --fit: pu (partition of unity) or global
    std::string device;
    bool validation = false;
    std::string statsPath;
    ink::RefineOptions refine;
    std::string backend = "gpu";
    bool fidelity = false;  // sample: measure the refined points against the input mesh
    std::string keepLevels = "all";
    bool presetLevels = false;  // the preset set "levels"
    std::vector<double> axis;
    std::string direction = "axis", seeds = "control", sampling = "stipple", styleName = "stipple";
    std::string distribution = "blue-noise";
    // Rendering
    DrawStyle style = DrawStyle::Stipple;
    ink::RenderStyle render;
    ink::LineOptions lines;  // pen lines the style asks for
    // --creases, --boundaries: auto draws a mesh's crease and boundary lines with the pen-line styles
    std::string creases = "auto", boundaries = "auto";
    std::string contourTracer = "auto";  // --contour-tracer: auto, cpu or device
    std::string hatchField = "auto";     // --hatch-field: auto, cpu or device
    double creaseAngle = ink::kCreaseAngleDeg;
    bool trim = true;
    std::vector<float> camera;  // azimuth, elevation, distance
    std::vector<uint32_t> size{1024, 1024};
    std::string ink = "#000000", paper = "#ffffff", preset;
    std::vector<float> light;
    std::string up = "auto";                        // --up: an axis, or auto (resolveView finds it)
    bool autoUp = true;                             // finishOptions: --up auto
    bool lightFixed = false, lightFollows = false;  // --light-fixed, --light-follows-camera (the default)
    // The automatic view resolveView chose (without --camera): angles, distance and target.
    std::optional<ink::Camera> autoView;
    // Vector output (SVG, PDF)
    ink::PageOptions page;
    std::string pageName = "A4", orientation = "auto", dotStyle = "circle";
    CLI::App* command = nullptr;  // the chosen subcommand (set by main): tells a preset which options were given
};

// For unsigned options: CLI11 would read "-1" as 18446744073709551615.
const CLI::Validator& nonNegativeInteger();
void addModelOptions(CLI::App* cmd, Options& o);
void addDeviceOptions(CLI::App* cmd, Options& o);
void addRefineOptions(CLI::App* cmd, Options& o);
void addRenderOptions(CLI::App* cmd, Options& o);  // style, colours, dots, tone, camera, size, --preset
void addVectorOptions(CLI::App* cmd, Options& o);  // page, orientation, margin, pen width, dot style, order
// Validates and resolves what the parser cannot (axis, colours, preset file); throws ink::Error.
void finishOptions(Options& o);
// The camera of the options: --camera, else the automatic view resolveView chose, else ink::Camera's defaults;
// about the up axis.
ink::Camera cameraFrom(const Options& o);

// The first picture (docs/usage.md): with --up auto, the up axis from the file's convention (glTF: +y) or the
// shape; without --camera, the view by viewpoint entropy at an illustrator's elevation, framed to fill 85% of
// the frame. From the scene's first refined set (read back, at most 20,000 of its points). Notes the choice.
struct ViewReport {
    std::string up, upReason;  // the axis and why ("--up", "the glTF convention", "flat: its thinnest axis", ...)
    bool chosen = false;       // the view was chosen (no --camera)
    ink::ViewChoice view;
    float distance = 0;
    double milliseconds = 0;
};
ViewReport resolveView(Options& o, ink::Scene& scene, float aspect);  // aspect: width / height
json viewJson(const ViewReport& r);

// The style as --style names it: the dots (none when RenderStyle::drawDots is off) and the pen lines joined by
// '+', e.g. "contours+hatching+stipple" is written "stipple+contours+hatching".
std::string styleName(const Options& o);

struct Preset;
// The options' style as a preset (every key docs/usage.md lists but `passes` when it is the default), for the
// viewer's "save preset".
Preset presetFrom(const Options& o);
// Reads a preset file over `o`, every key in the file winning (the viewer's "load preset"), and resolves what
// it sets as finishOptions does. Throws ink::Error naming the file and the key, leaving `o` unchanged.
void loadPreset(Options& o, const std::string& path);

// Notes on stderr (none when quiet); progress as one self-overwriting line, only when stderr is a terminal, so
// piped and scripted runs stay quiet. main() installs it for the whole command.
ink::Reporter terminalReporter(bool quiet);

// The Vulkan device of a command (--device; validation and synchronization validation with `validation`), its
// validation messages printed on stderr.
inkwell::Device openDevice(const Options& o, bool validation);
// Throws naming the first validation error, if any: a command that passed with validation errors has failed.
void checkValidation(const inkwell::Device& device);

// Owns the Vulkan context of one command; validation errors count as a failure, and are printed.
struct Session {
    ink::Context ctx;
    explicit Session(const Options& o, std::vector<const char*> instanceExtensions = {}, bool presentation = false);
    ~Session();
    void checkValidation() const;
};

// The engine's scene (scene.h) made from the command's options: loads, fits, refines.
struct Scene : ink::Scene {
    Scene(ink::Context& ctx, const Options& o);
    void refine(const Options& o) { ink::Scene::refine(o.style, o.refine, o.lines); }
};

// The marks of `renderer`'s frame `frame` (drawn and submitted) laid out on `page` and written as SVG or PDF by
// the extension of `path`: what the viewer's V key and `view --vector` save.
ink::Plot writeVectorView(const ink::PointRenderer& renderer, uint32_t frame, const std::string& path,
                          const ink::PageOptions& page);
// One line a pen on stdout: paths, pen-up travel, pen-down length, lifts and the estimated plot time.
void printPlot(const ink::Plot& plot);
// Writes JSON atomically; does nothing for an empty path.
void writeJson(const std::string& path, const json& j);

}  // namespace app
