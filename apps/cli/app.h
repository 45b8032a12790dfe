// What the inkwell commands share: options, the device, the first view, JSON stats. On the public API alone
// (include/inkwell/): the program is the library's first user.
#pragma once

#include "inkwell/files.h"
#include "inkwell/inkwell.h"

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
inline double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Options;
// --control-points, --fit, --crease-angle and --no-trim as the library takes them.
inkwell::ModelOptions modelOptions(const Options& o);

struct Options {
    std::string model;
    size_t controlPoints = 0;
    std::string fit = "pu";  // --fit: pu (partition of unity) or global
    std::string device;
    bool validation = false;
    std::string statsPath;
    inkwell::DrawingOptions drawing;  // the point sets and the pen lines the style asks for
    std::string backend = "gpu";
    bool fidelity = false;  // sample: measure the refined points against the input mesh
    std::string keepLevels = "all";
    bool presetLevels = false;  // the preset set "levels"
    std::vector<double> axis;
    std::string direction = "axis", seeds = "control", sampling = "stipple", styleName = "stipple";
    std::string distribution = "blue-noise";
    // Rendering
    inkwell::Look look;
    inkwell::Up up = inkwell::Up::Y;  // the up axis the camera orbits (--up, or as resolveView found it)
    // --creases, --boundaries: auto draws a mesh's crease and boundary lines with the pen-line styles
    std::string creases = "auto", boundaries = "auto";
    std::string contourTracer = "auto";  // --contour-tracer: auto, cpu or device
    std::string hatchField = "auto";     // --hatch-field: auto, cpu or device
    double creaseAngle = 60;
    bool trim = true;
    bool removeOutliers = true;
    bool smoothNoise = true;
    std::vector<float> camera;  // azimuth, elevation, distance
    std::vector<uint32_t> size{1024, 1024};
    std::string ink = "#000000", paper = "#ffffff", preset;
    std::vector<float> light;
    std::string upName = "auto";                    // --up: an axis, or auto (resolveView finds it)
    bool autoUp = true;                             // finishOptions: --up auto
    bool lightFixed = false, lightFollows = false;  // --light-fixed, --light-follows-camera (the default)
    // The automatic view resolveView chose (without --camera): angles, distance and target.
    std::optional<inkwell::Camera> autoView;
    // Vector output (SVG, PDF)
    inkwell::Page page;
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
// The refinement levels `render` and `capture` use when neither --levels nor a preset gives them: 3 for pen lines
// alone; for dots, 4, and 5 from 2²¹ pixels (2048 × 1024; a print page), for the tone's ink in finer dots.
uint32_t defaultLevels(bool dots, uint32_t width, uint32_t height);
// Validates and resolves what the parser cannot (axis, colours, preset file); throws inkwell::Error.
void finishOptions(Options& o);
// The camera of the options: --camera, else the automatic view resolveView chose, else inkwell::Camera's
// defaults; about the up axis.
inkwell::Camera cameraFrom(const Options& o);

// The first picture (docs/usage.md): with --up auto, the up axis from the file's convention (glTF: +y) or the
// shape; without --camera, the view by viewpoint entropy at an illustrator's elevation, framed to fill 85% of
// the frame. From the drawing's first set. Notes the choice.
struct ViewReport {
    std::string up, upReason;  // the axis and why ("--up", "the glTF convention", "flat: its thinnest axis", ...)
    bool chosen = false;       // the view was chosen (no --camera)
    inkwell::FirstView view;
    double milliseconds = 0;
};
ViewReport resolveView(Options& o, const inkwell::Drawing& drawing, float aspect);  // aspect: width / height
json viewJson(const ViewReport& r);

// The style as --style names it: the dots (none when Look::dots is off) and the pen lines joined by '+', e.g.
// "contours+hatching+stipple" is written "stipple+contours+hatching".
std::string styleName(const Options& o);

struct Preset;
// The options' style as a preset (every key docs/usage.md lists but `passes` when it is the default), for the
// viewer's "save preset".
Preset presetFrom(const Options& o);
// Reads a preset file over `o`, every key in the file winning (the viewer's "load preset"), and resolves what
// it sets as finishOptions does. Throws inkwell::Error naming the file and the key, leaving `o` unchanged.
void loadPreset(Options& o, const std::string& path);

// Notes on stderr (none when quiet); progress as one self-overwriting line, only when stderr is a terminal, so
// piped and scripted runs stay quiet. main() passes it to the library's long calls.
inkwell::Reporter terminalReporter(bool quiet);
// The reporter main() made, for the commands' calls into the library, and its notes.
const inkwell::Reporter& reporter();
void setReporter(inkwell::Reporter r);
void note(const std::string& line);

// The Vulkan device of a command (--device; validation and synchronization validation with `validation`), its
// validation messages printed on stderr; with a window system's instance extensions and presentation for the
// viewer.
inkwell::Device openDevice(const Options& o, bool validation, std::vector<const char*> instanceExtensions = {},
                           bool presentation = false);
// Throws naming the first validation error, if any: a command that passed with validation errors has failed.
void checkValidation(const inkwell::Device& device);

// The model of the options, loaded or fitted, and a drawing of it as the options ask.
inkwell::Model loadModel(const Options& o);
json deviceJson(const inkwell::Device& device);
// One line a pen on stdout: paths, pen-up travel, pen-down length, lifts and the estimated plot time.
void printPlot(const inkwell::Plot& plot);
// Writes JSON atomically; does nothing for an empty path.
void writeJson(const std::string& path, const json& j);

}  // namespace app
