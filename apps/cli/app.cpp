#include "app.h"

#include "base/files.h"
#include "base/image.h"
#include "draw/page_metrics.h"
#include "inkwell/ranges.h"
#include "preset.h"
#include "refine/spacing.h"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

namespace app {

// A range of the one table (include/inkwell/ranges.h) for CLI11, as it checks an option's text (closed
// ranges only): of counts, and of numbers.
static CLI::Range countRange(const inkwell::Range& range) { return CLI::Range(uint32_t(range.lo), uint32_t(range.hi)); }
static CLI::Range numberRange(const inkwell::Range& range) { return CLI::Range(float(range.lo), float(range.hi)); }

ink::ModelOptions modelOptions(const Options& o) {
    ink::ModelOptions m{o.controlPoints, o.fit == "global" ? ink::FitMethod::Global : ink::FitMethod::PartitionOfUnity,
                        o.creaseAngle, o.trim};
    // The feature lines only where they may be drawn: by the style's pen lines, or in the viewer, whose panel
    // turns them on (fit, sample and a render of dots alone skip them).
    m.features = o.lines.creases || o.lines.boundaries || (o.command && o.command->get_name() == "view");
    return m;
}

void addModelOptions(CLI::App* cmd, Options& o) {
    cmd->add_option("model", o.model, "Mesh, oriented points or fitted model (.obj, .ply, .pts/.xyzn/.txt, .hrbf)")
        ->required();
    cmd->add_option("--control-points", o.controlPoints,
                    "Control points chosen by farthest-point sampling (default: all; at most 1000 for --fit global)")
        ->check(nonNegativeInteger());
    cmd->add_option("--crease-angle", o.creaseAngle,
                    "Crease lines: a mesh's edges whose faces, or a point cloud's neighbours whose normals, turn by "
                    "more than this, degrees (0-180); a mesh's surface stays sharp there")
        ->capture_default_str();
    cmd->add_flag("!--no-trim", o.trim,
                  "Keep the surface the input does not support (by default an open scan's holes stay open, the "
                  "fit's caps over them dropped, and so are its stray sheets away from the data)");
    cmd->add_option("--fit", o.fit,
                    "pu: local HRBFs blended by a partition of unity (any size, float on the device); global: the "
                    "report's single dense HRBF (at most 4000 points, needs shaderFloat64)")
        ->check(CLI::IsMember({"pu", "global"}))
        ->capture_default_str();
    cmd->add_option("--stats", o.statsPath, "Write statistics as JSON to this file");
}

void addDeviceOptions(CLI::App* cmd, Options& o) {
    cmd->add_option("--device", o.device,
                    "Vulkan device: an index or part of its name (default: a GPU, else lavapipe)");
    cmd->add_flag("--validation", o.validation, "Enable Vulkan validation and synchronization validation");
}

void addRefineOptions(CLI::App* cmd, Options& o) {
    ink::RefineOptions& r = o.refine;
    cmd->add_option("--levels", r.levels, "Refinement levels after the seeds")
        ->check(nonNegativeInteger())
        ->capture_default_str();
    cmd->add_option(
           "--passes", r.passes,
           "Independent sets of children of the seeds (default: 1 for blue-noise stipples, else the report's 2)")
        ->check(countRange(inkwell::ranges::passes));
    cmd->add_option("--direction", o.direction, "Direction field of direction sampling")
        ->check(CLI::IsMember({"axis", "curvature-min", "curvature-max"}))
        ->capture_default_str();
    cmd->add_option("--axis", o.axis, "Axis for --direction axis, as X Y Z (default: 0 1 0)")->expected(3);
    cmd->add_option("--seeds", o.seeds, "Seeds: the control points, or a jittered grid projected onto the surface")
        ->check(CLI::IsMember({"control", "grid"}))
        ->capture_default_str();
    cmd->add_option("--grid", r.grid, "Grid cells along the longest side for --seeds grid")
        ->check(nonNegativeInteger())
        ->capture_default_str();
    cmd->add_option("--rho", r.rho0, "ρ₀ as a fraction of the bounding-box diagonal (default: half the seed spacing)");
    cmd->add_option("--rho-divisor", r.rhoDivisor,
                    "ρ of a level over the next's (default: 2 for blue-noise stipples, else the report's 3)")
        ->check(CLI::Range(1.5, 4.0));
    cmd->add_option("--seed", r.seed, "Random seed")->check(nonNegativeInteger())->capture_default_str();
    cmd->add_option("--distribution", o.distribution,
                    "Stipples: selected from the refined points with blue-noise spacing and progressive ranks, or "
                    "every refined point with a random tone value (the report's look)")
        ->check(CLI::IsMember({"blue-noise", "refinement"}))
        ->capture_default_str();
    cmd->add_option("--candidates-per-stipple", r.candidatesPerStipple,
                    "Blue-noise selection: keep about one refined point in this many (2-16)")
        ->check(numberRange(inkwell::ranges::candidatesPerStipple))
        ->capture_default_str();
    cmd->add_option("--keep-levels", o.keepLevels, "Keep all levels or only the last")
        ->check(CLI::IsMember({"all", "last"}))
        ->capture_default_str();
}

void addRenderOptions(CLI::App* cmd, Options& o) {
    ink::RenderStyle& s = o.render;
    cmd->add_option("--style", o.styleName,
                    "What is drawn, parts joined by '+': dots (stipple, direction: hatch-like lines of dots, or both) "
                    "and pen lines (contours, hatching), e.g. contours+hatching+stipple (docs/lines.md)")
        ->capture_default_str();
    cmd->add_option("--contour-width", s.penWidth, "Contour pen width in pixels")->capture_default_str();
    cmd->add_option("--contour-tracer", o.contourTracer,
                    "Where the contour is traced for each view: device (all seeds and marches at once, in float; a "
                    "partition-of-unity fit only), cpu (the reference tracer, in double), or auto: the device where "
                    "it is a GPU, else the CPU (docs/lines.md)")
        ->check(CLI::IsMember({"auto", "cpu", "device"}))
        ->capture_default_str();
    cmd->add_option("--hatch-field", o.hatchField,
                    "Where the hatching's cross field is solved: device (in float, one dispatch a pass; a "
                    "partition-of-unity fit only), cpu (its twin, in double), or auto: the device where it is a "
                    "GPU, else the CPU (docs/lines.md)")
        ->check(CLI::IsMember({"auto", "cpu", "device"}))
        ->capture_default_str();
    cmd->add_option("--hatch-width", s.hatchWidth, "Hatching pen width in pixels")->capture_default_str();
    cmd->add_option("--halo", s.haloWidth, "Paper kept clear each side of an interior contour, in pixels")
        ->capture_default_str();
    cmd->add_option("--creases", o.creases,
                    "Crease lines (a mesh's or a point cloud's sharp edges), on their own pen: auto draws them with "
                    "contours or hatching")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    cmd->add_option("--boundaries", o.boundaries,
                    "A mesh's boundary lines (open edges, holes' rims), on their own pen: auto as --creases")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    cmd->add_option("--crease-width", s.creaseWidth, "Crease pen width in pixels")->capture_default_str();
    cmd->add_option("--boundary-width", s.boundaryWidth, "Boundary pen width in pixels")->capture_default_str();
    cmd->add_option("--hatch-spacing", o.lines.hatch.spacing,
                    "Spacing of the finest hatching, as a fraction of the bounding-box diagonal")
        ->capture_default_str();
    cmd->add_option("--hatch-families", o.lines.hatch.families,
                    "Hatching families: 1; 2 to cross the first in dark tones; 3 to add a diagonal one in the darkest")
        ->check(countRange(inkwell::ranges::hatchFamilies))
        ->capture_default_str();
    cmd->add_option("--size", o.size, "Image width and height in pixels")
        ->expected(2)
        ->check(nonNegativeInteger())
        ->capture_default_str();
    cmd->add_option("--camera", o.camera, "Camera azimuth and elevation in degrees and distance in diagonals")
        ->expected(3)
        ->delimiter(',');
    cmd->add_option("--ink", o.ink, "Ink colour, #rrggbb")->capture_default_str();
    cmd->add_option("--paper", o.paper, "Paper colour, #rrggbb")->capture_default_str();
    cmd->add_option("--dot-size", s.frontSize, "Dot diameter in pixels")->capture_default_str();
    cmd->add_option("--silhouette-size", s.silhouetteSize, "Silhouette dot diameter in pixels")->capture_default_str();
    cmd->add_option("--tau", s.tau, "Silhouette threshold τ on |n·v|")->capture_default_str();
    cmd->add_option("--tone", s.toneGamma, "Tone curve exponent γ; 0 draws every front dot")->capture_default_str();
    cmd->add_option("--ink-density", s.inkDensity, "Scales how many dots the tone draws")->capture_default_str();
    cmd->add_option("--light", o.light,
                    "Direction towards the key light, X Y Z as seen from the camera (x right, y up, z out; default "
                    "the upper left, -0.5 0.6 0.65); it follows the camera unless --light-fixed")
        ->expected(3);
    cmd->add_option("--up", o.up,
                    "The model's up axis, which the camera orbits: auto (the file's convention, else the shape's; "
                    "docs/usage.md), x, -x, y, -y, z or -z")
        ->capture_default_str();
    auto* fixed = cmd->add_flag("--light-fixed", o.lightFixed,
                                "Fix the light to the model instead, --light given as seen from azimuth 30, "
                                "elevation 15 (the shading, and the dots, stay on the model as the camera moves)");
    cmd->add_flag("--light-follows-camera", o.lightFollows,
                  "The light follows the camera, keeping the lit side towards the eye (the default)")
        ->excludes(fixed);
    cmd->add_flag("--hidden-lines", s.hiddenLines, "Draw occluded silhouettes faint");
    cmd->add_option("--hidden-dot-size", s.hiddenSize, "With --hidden-lines: hidden silhouette dot diameter in pixels")
        ->capture_default_str();
    cmd->add_option("--hidden-contour-width", s.hiddenPenWidth,
                    "With --hidden-lines: hidden contour pen width in pixels")
        ->capture_default_str();
    cmd->add_option("--hidden-opacity", s.hiddenInk.a,
                    "With --hidden-lines: how much of the ink the hidden lines take, 0-1 (over the paper)")
        ->capture_default_str();
    cmd->add_flag("!--no-occlusion", s.occlusion, "Skip the splat depth pre-pass (dots behind the surface show)");
    cmd->add_flag("!--no-screen-spacing", s.screenSpacing,
                  "Draw the tone's stipples as ranked on the surface, without spacing them on the page (they crowd "
                  "where the surface turns away)");
    cmd->add_option("--supersample", s.supersample, "Render this many times larger and filter down (1-4)")
        ->check(countRange(inkwell::ranges::supersample))
        ->capture_default_str();
    cmd->add_option("--preset", o.preset, "Style preset, a JSON file (docs/usage.md, Presets); options given win");
}

void addVectorOptions(CLI::App* cmd, Options& o) {
    ink::PageOptions& p = o.page;
    cmd->add_option("--page", o.pageName, "SVG/PDF page: A4, A3, A5, letter or WxHmm (e.g. 300x200mm)")
        ->capture_default_str();
    cmd->add_option("--orientation", o.orientation,
                    "SVG/PDF page orientation (auto: landscape for a wide image; a WxHmm page as given)")
        ->check(CLI::IsMember({"auto", "portrait", "landscape"}))
        ->capture_default_str();
    cmd->add_option("--margin", p.margin, "SVG/PDF margin on every side, mm")->capture_default_str();
    cmd->add_option("--pen-width", p.penWidth, "SVG/PDF pen (stroke) width, mm")->capture_default_str();
    cmd->add_option("--dot-style", o.dotStyle, "SVG/PDF stipples: small closed circles or short ticks")
        ->check(CLI::IsMember({"circle", "tick"}))
        ->capture_default_str();
    cmd->add_flag("!--no-order", p.order,
                  "SVG/PDF: keep the paths in the device's order (no travel ordering, no end-to-end merging)");
    cmd->add_option("--simplify", p.simplify,
                    "SVG/PDF pen lines: simplification tolerance, a fraction of --pen-width (0: none)")
        ->capture_default_str();
    cmd->add_option(
           "--retrace", p.retrace,
           "SVG/PDF pen lines: a stretch this close (fraction of --pen-width) to one drawn is dropped (0: none)")
        ->capture_default_str();
    cmd->add_option("--merge", p.merge, "SVG/PDF pen lines: join ends this close, a fraction of --pen-width (0: none)")
        ->capture_default_str();
    cmd->add_option("--plot-speed", p.drawSpeed, "Plot-time estimate (--stats): pen-down speed, mm/s")
        ->capture_default_str();
    cmd->add_option("--travel-speed", p.travelSpeed, "Plot-time estimate (--stats): pen-up speed, mm/s")
        ->capture_default_str();
    cmd->add_option("--lift-time", p.liftSeconds, "Plot-time estimate (--stats): seconds a pen lift takes")
        ->capture_default_str();
}

static glm::vec4 parseColour(const std::string& text, const char* what) {
    std::string hex = text.rfind('#', 0) == 0 ? text.substr(1) : text;
    if (hex.size() != 6 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
        throw ink::Error(std::string(what) + " colour '" + text + "' is not of the form #rrggbb");
    unsigned value = unsigned(std::stoul(hex, nullptr, 16));
    return {float((value >> 16) & 255) / 255.0f, float((value >> 8) & 255) / 255.0f, float(value & 255) / 255.0f, 1.0f};
}

// A preset sets what the command line did not: {"style": "both", "ink": "#202040", "dot_size": 1.4, ...}.
// parsePreset (preset.cpp) checks every key like the command line checks its option.
static void applyPreset(Options& o) {
    const Preset p = parsePreset(
        ink::readFileCapped(o.preset, kMaxPresetBytes, "file is larger than 1 MiB, far more than any preset"),
        o.preset);
    auto given = [&](const char* option) { return o.command && o.command->count(option) > 0; };
    auto set = [&](auto& target, const auto& value, const char* option) {
        if (value && !given(option)) target = *value;
    };
    set(o.styleName, p.style, "--style");
    set(o.ink, p.ink, "--ink");
    set(o.paper, p.paper, "--paper");
    set(o.render.frontSize, p.dotSize, "--dot-size");
    set(o.render.silhouetteSize, p.silhouetteSize, "--silhouette-size");
    set(o.render.tau, p.tau, "--tau");
    set(o.render.toneGamma, p.tone, "--tone");
    set(o.render.inkDensity, p.inkDensity, "--ink-density");
    set(o.render.hiddenLines, p.hiddenLines, "--hidden-lines");
    set(o.render.screenSpacing, p.screenSpacing, "--no-screen-spacing");
    set(o.render.hiddenSize, p.hiddenDotSize, "--hidden-dot-size");
    set(o.render.hiddenPenWidth, p.hiddenContourWidth, "--hidden-contour-width");
    set(o.render.hiddenInk.a, p.hiddenOpacity, "--hidden-opacity");
    set(o.up, p.up, "--up");
    if (p.lightFixed && !given("--light-fixed") && !given("--light-follows-camera")) o.lightFixed = *p.lightFixed;
    set(o.light, p.light, "--light");
    set(o.refine.levels, p.levels, "--levels");
    o.presetLevels = bool(p.levels);
    set(o.refine.passes, p.passes, "--passes");
    set(o.direction, p.direction, "--direction");
    set(o.render.penWidth, p.contourWidth, "--contour-width");
    set(o.render.hatchWidth, p.hatchWidth, "--hatch-width");
    set(o.render.haloWidth, p.halo, "--halo");
    if (p.hatchSpacing && !given("--hatch-spacing")) o.lines.hatch.spacing = double(*p.hatchSpacing);
    set(o.lines.hatch.families, p.hatchFamilies, "--hatch-families");
    set(o.creases, p.creases, "--creases");
    set(o.boundaries, p.boundaries, "--boundaries");
    set(o.render.creaseWidth, p.creaseWidth, "--crease-width");
    set(o.render.boundaryWidth, p.boundaryWidth, "--boundary-width");
}

// "--style contours+hatching+stipple": at most one dot style (stipple, direction, both) and any pen lines. Without
// dots the stipple set is still refined: its splats give the depth the lines are tested against.
static void parseStyle(Options& o) {
    std::string dots;
    o.lines.contours = o.lines.hatching = false;
    if (o.styleName.empty() || o.styleName.back() == '+' || o.styleName.front() == '+' ||
        o.styleName.find("++") != std::string::npos)
        throw ink::Error(
            "style '" + o.styleName +
            "' has an empty part: use stipple, direction, both, contours, hatching or parts joined by '+'");
    std::stringstream parts(o.styleName);
    std::string part;
    while (std::getline(parts, part, '+')) {
        if (part == "contours" && !o.lines.contours)
            o.lines.contours = true;
        else if (part == "hatching" && !o.lines.hatching)
            o.lines.hatching = true;
        else if ((part == "stipple" || part == "direction" || part == "both") && dots.empty())
            dots = part;
        else
            throw ink::Error("style '" + o.styleName + "': '" + part +
                             "' is not stipple, direction, both, contours or hatching, or is given twice (parts are "
                             "joined by '+', at most one of stipple, direction and both)");
    }
    o.lines.contourTracer = o.contourTracer == "device" ? ink::LineOptions::ContourTracer::Device
                            : o.contourTracer == "cpu"  ? ink::LineOptions::ContourTracer::Cpu
                                                        : ink::LineOptions::ContourTracer::Auto;
    o.lines.fieldSolver = o.hatchField == "device" ? ink::LineOptions::FieldSolver::Device
                          : o.hatchField == "cpu"  ? ink::LineOptions::FieldSolver::Cpu
                                                   : ink::LineOptions::FieldSolver::Auto;
    o.style = dots == "direction" ? DrawStyle::Direction : dots == "both" ? DrawStyle::Both : DrawStyle::Stipple;
    // A mesh's creases and boundaries go with the pen lines unless asked for or against.
    const bool pen = o.lines.contours || o.lines.hatching;
    for (auto [setting, on, option] : {std::tuple{&o.creases, &o.lines.creases, "--creases"},
                                       std::tuple{&o.boundaries, &o.lines.boundaries, "--boundaries"}}) {
        if (*setting != "auto" && *setting != "on" && *setting != "off")
            throw ink::Error(std::string(option) + " '" + *setting + "' is not auto, on or off");
        *on = *setting == "on" || (*setting == "auto" && pen);
    }
    o.render.drawDots = !dots.empty();
}

const CLI::Validator& nonNegativeInteger() {
    // CLI11 reads "-1" into an unsigned option as 18446744073709551615; refuse the sign instead.
    static const CLI::Validator validator(
        [](std::string& text) -> std::string {
            size_t start = text.find_first_not_of(" \t");
            if (start != std::string::npos && text[start] == '-') return "must not be negative (got " + text + ")";
            return {};
        },
        "NONNEGATIVE");
    return validator;
}

void finishOptions(Options& o) {
    ink::checkModelOptions(modelOptions(o));
    if (!o.preset.empty()) applyPreset(o);
    // The refinement's numbers, before the model is loaded or fitted (planRefinement checks them again for
    // the library's callers).
    const CLI::Option* rho = o.command ? o.command->get_option_no_throw("--rho") : nullptr;
    if ((rho && rho->count() > 0 && o.refine.rho0 == 0) || !ink::validRho(o.refine.rho0)) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", o.refine.rho0);
        throw ink::Error(
            std::string("--rho ") + text +
            " must be in (0, 1]: a fraction of the bounding-box diagonal (above 1 every child is dropped)");
    }
    if (o.refine.passes > 64) throw ink::Error("--passes must be between 1 and 64");
    if (o.refine.grid < 2 || o.refine.grid > 512)
        throw ink::Error("--grid " + std::to_string(o.refine.grid) + " must be between 2 and 512 cells");
    parseStyle(o);
    // A drawing of pen lines alone needs the refined points only for the lines' seeds and the splats' depth: two
    // levels do (the bunny: 21,000 points, refined in a fifth of the four levels' time). The viewer keeps four, for
    // the dots its panel can turn on.
    const bool levelsGiven = o.presetLevels || (o.command && o.command->count("--levels") > 0);
    if (!o.render.drawDots && !levelsGiven && o.command && o.command->get_name() != "view")
        o.refine.levels = std::min(o.refine.levels, 2u);
    if (o.direction == "axis")
        o.refine.direction = ink::DirectionField::Axis;
    else if (o.direction == "curvature-min")
        o.refine.direction = ink::DirectionField::CurvatureMin;
    else if (o.direction == "curvature-max")
        o.refine.direction = ink::DirectionField::CurvatureMax;
    else
        throw ink::Error("direction '" + o.direction + "' is not axis, curvature-min or curvature-max");
    o.refine.seeds = o.seeds == "grid" ? ink::SeedMode::Grid : ink::SeedMode::ControlPoints;
    o.refine.style = o.sampling == "direction" ? ink::SampleStyle::Direction : ink::SampleStyle::Stipple;
    if (!o.axis.empty()) o.refine.axis = Eigen::Vector3d(o.axis[0], o.axis[1], o.axis[2]);
    if (!(o.refine.axis.norm() > 0) || !o.refine.axis.allFinite()) throw ink::Error("--axis must be a non-zero vector");
    o.refine.keepAllLevels = o.keepLevels == "all";
    o.refine.distribution =
        o.distribution == "refinement" ? ink::Distribution::Refinement : ink::Distribution::BlueNoise;
    o.render.ink = parseColour(o.ink, "ink");
    o.render.paper = parseColour(o.paper, "paper");
    o.render.hiddenInk = glm::vec4(glm::vec3(o.render.ink), o.render.hiddenInk.a);  // --hidden-opacity
    o.autoUp = o.up == "auto";
    if (!o.autoUp) try {
            o.render.up = ink::parseUpAxis(o.up);
        } catch (const ink::Error& e) {
            throw ink::Error(std::string("--up: ") + e.what() + " or auto");
        }
    if (o.lightFixed && o.lightFollows) throw ink::Error("--light-fixed and --light-follows-camera exclude each other");
    o.render.lightFollowsCamera = !o.lightFixed;
    if (!o.light.empty()) {
        glm::vec3 l(o.light[0], o.light[1], o.light[2]);
        if (!(glm::length(l) > 0) || !std::isfinite(glm::length(l)))
            throw ink::Error("--light must be a non-zero vector");
        o.render.light = l;
    }
    // The ranges' one table: include/inkwell/ranges.h.
    namespace ranges = inkwell::ranges;
    for (float v : {o.render.frontSize, o.render.silhouetteSize, o.render.hiddenSize})
        ranges::dotSize.check(v, "dot sizes");
    ranges::tau.check(o.render.tau, "--tau");
    for (float v : {o.render.penWidth, o.render.hatchWidth, o.render.hiddenPenWidth, o.render.creaseWidth,
                    o.render.boundaryWidth})
        ranges::penWidth.check(v, "pen widths");
    ranges::hiddenOpacity.check(o.render.hiddenInk.a, "--hidden-opacity");
    ranges::halo.check(o.render.haloWidth, "--halo");
    ranges::hatchSpacing.check(o.lines.hatch.spacing, "--hatch-spacing");
    ranges::toneGamma.check(o.render.toneGamma, "--tone");
    ranges::inkDensity.check(o.render.inkDensity, "--ink-density");
    // The device-independent limit here, before any work; what fits the device is checked once it is known.
    if (o.refine.levels >= ink::kMaxLevels)
        throw ink::Error("--levels " + std::to_string(o.refine.levels) + " is too many: at most " +
                         std::to_string(ink::kMaxLevels - 1) + " refinement levels");
    if (o.size.size() == 2 && (o.size[0] < 1 || o.size[1] < 1 || o.size[0] > 8192 || o.size[1] > 8192))
        throw ink::Error("--size " + std::to_string(o.size[0]) + " " + std::to_string(o.size[1]) +
                         " is outside 1..8192 pixels a side");
    const glm::dvec2 page = ink::parsePageSize(o.pageName);
    o.page.width = page.x;
    o.page.height = page.y;
    o.page.dotStyle = o.dotStyle == "tick" ? ink::DotStyle::Tick : ink::DotStyle::Circle;
    const bool explicitSize = o.pageName.size() > 2 && (o.pageName.back() == 'm' || o.pageName.back() == 'M');
    if (o.orientation == "portrait")
        o.page.orientation = ink::Orientation::Portrait;
    else if (o.orientation == "landscape")
        o.page.orientation = ink::Orientation::Landscape;
    else  // auto: a page given in millimetres is taken as given
        o.page.orientation = !explicitSize     ? ink::Orientation::Auto
                             : page.x > page.y ? ink::Orientation::Landscape
                                               : ink::Orientation::Portrait;
    ranges::simplify.check(o.page.simplify, "--simplify");
    ranges::retrace.check(o.page.retrace, "--retrace");
    ranges::merge.check(o.page.merge, "--merge");
    ranges::plotSpeed.check(o.page.drawSpeed, "--plot-speed");
    ranges::plotSpeed.check(o.page.travelSpeed, "--travel-speed");
    ranges::liftTime.check(o.page.liftSeconds, "--lift-time");
    if (!(o.page.penWidth >= ink::kMinPenWidth && o.page.penWidth <= ink::kMaxPenWidth))
        throw ink::Error("--pen-width must be in [0.001, 10] mm (kMinPenWidth: the files give a micrometre)");
    // The view fits within the margins; it must be wider and taller than the pen (layoutPlot checks the view
    // itself once the image's proportions are known).
    if (!(o.page.margin >= 0 && 2 * o.page.margin + o.page.penWidth < std::min(page.x, page.y)))
        throw ink::Error("--margin must be at least 0 mm and leave room for the pen on the page");
    if (!o.camera.empty()) {
        if (!std::isfinite(o.camera[0]) || !std::isfinite(o.camera[1]) || !(o.camera[2] > 0.05f && o.camera[2] < 100))
            throw ink::Error("--camera needs finite angles and a distance in (0.05, 100) diagonals");
    }
}

static std::string hexColour(const glm::vec4& c) {
    char text[8];
    auto byte = [](float v) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    std::snprintf(text, sizeof text, "#%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b));
    return text;
}

static const char* directionName(ink::DirectionField d) {
    return d == ink::DirectionField::Axis           ? "axis"
           : d == ink::DirectionField::CurvatureMin ? "curvature-min"
                                                    : "curvature-max";
}

std::string styleName(const Options& o) {
    std::string name = o.render.drawDots ? ink::drawStyleName(o.style) : "";
    for (auto [on, part] : {std::pair{o.lines.contours, "contours"}, std::pair{o.lines.hatching, "hatching"}})
        if (on) name += (name.empty() ? "" : "+") + std::string(part);
    return name.empty() ? "stipple" : name;
}

Preset presetFrom(const Options& o) {
    Preset p;
    p.style = styleName(o);
    p.direction = directionName(o.refine.direction);
    p.levels = o.refine.levels;
    if (o.refine.passes > 0) p.passes = o.refine.passes;
    p.ink = hexColour(o.render.ink);
    p.paper = hexColour(o.render.paper);
    p.dotSize = o.render.frontSize;
    p.silhouetteSize = o.render.silhouetteSize;
    p.tau = o.render.tau;
    p.tone = o.render.toneGamma;
    p.inkDensity = o.render.inkDensity;
    p.hiddenLines = o.render.hiddenLines;
    p.screenSpacing = o.render.screenSpacing;
    p.hiddenDotSize = o.render.hiddenSize;
    p.hiddenContourWidth = o.render.hiddenPenWidth;
    p.hiddenOpacity = o.render.hiddenInk.a;
    p.light = std::vector<float>{o.render.light.x, o.render.light.y, o.render.light.z};
    p.up = o.autoUp ? "auto" : ink::upAxisName(o.render.up);
    p.lightFixed = !o.render.lightFollowsCamera;
    p.contourWidth = o.render.penWidth;
    p.hatchWidth = o.render.hatchWidth;
    p.halo = o.render.haloWidth;
    p.hatchSpacing = float(o.lines.hatch.spacing);
    p.hatchFamilies = o.lines.hatch.families;
    p.creases = o.creases;
    p.boundaries = o.boundaries;
    p.creaseWidth = o.render.creaseWidth;
    p.boundaryWidth = o.render.boundaryWidth;
    return p;
}

void loadPreset(Options& o, const std::string& path) {
    Options t = o;
    // The text forms of what the preset may set, from the current values (the viewer's panel edits those).
    const Preset now = presetFrom(o);
    t.styleName = *now.style;
    t.direction = *now.direction;
    t.ink = *now.ink;
    t.paper = *now.paper;
    t.up = *now.up;
    t.light = *now.light;
    t.lightFixed = *now.lightFixed;
    t.lightFollows = false;
    t.command = nullptr;  // no option counts as given: every key of the file wins
    t.preset = path;
    finishOptions(t);
    o = t;
}

ink::Camera cameraFrom(const Options& o) {
    ink::Camera c;
    if (o.autoView) c = *o.autoView;
    c.up = o.render.up;
    if (o.camera.size() == 3) {
        c.target = glm::vec3(0);
        c.azimuthDeg = o.camera[0];
        c.elevationDeg = std::clamp(o.camera[1], -89.0f, 89.0f);
        c.distance = o.camera[2];
    }
    return c;
}

ViewReport resolveView(Options& o, ink::Scene& scene, float aspect) {
    ViewReport r;
    const auto start = Clock::now();
    ink::ViewSamples samples;
    if (!scene.sets.empty()) samples = ink::viewSamples(ink::readPoints(scene.ctx, scene.sets.front()->gpu()));
    if (!o.autoUp) {
        r.upReason = "--up";
    } else if (auto convention = ink::formatUpAxis(o.model)) {
        o.render.up = *convention;
        r.upReason = "the glTF convention";
    } else {
        const ink::UpChoice up = ink::detectUpAxis(samples);
        o.render.up = up.up;
        r.upReason = up.reason;
    }
    r.up = ink::upAxisName(o.render.up);
    o.autoView.reset();
    if (o.camera.empty()) {
        ink::Camera c;
        c.up = o.render.up;
        r.view = ink::chooseView(samples, c.up);
        c.azimuthDeg = r.view.azimuthDeg;
        c.elevationDeg = r.view.elevationDeg;
        ink::frameSamples(c, samples, aspect);
        o.autoView = c;
        r.chosen = true;
        r.distance = c.distance;
    }
    r.milliseconds = 1000.0 * secondsSince(start);
    char text[256];
    if (r.chosen)
        std::snprintf(text, sizeof text,
                      "up %s (%s); view azimuth %.0f, elevation %.0f degrees, distance %.2f (%.0f ms)", r.up.c_str(),
                      r.upReason.c_str(), r.view.azimuthDeg, r.view.elevationDeg, r.distance, r.milliseconds);
    else
        std::snprintf(text, sizeof text, "up %s (%s)", r.up.c_str(), r.upReason.c_str());
    ink::note(text);
    return r;
}

json viewJson(const ViewReport& r) {
    json j = {{"up", r.up}, {"up_reason", r.upReason}, {"chosen", r.chosen}};
    if (r.chosen) {
        j["azimuth_deg"] = r.view.azimuthDeg;
        j["elevation_deg"] = r.view.elevationDeg;
        j["entropy_bits"] = r.view.score;
        j["distance"] = r.distance;
        if (r.view.frontDeg >= 0) j["front_deg"] = r.view.frontDeg;
    }
    j["milliseconds"] = r.milliseconds;
    return j;
}

ink::Reporter terminalReporter(bool quiet) {
    ink::Reporter r;
    if (!quiet)
        r.note = [](const std::string& line) { std::fprintf(stderr, "note: %s\n", ink::escapeText(line).c_str()); };
    if (isatty(STDERR_FILENO))
        r.progress = [](const char* task, size_t done, size_t total) {
            if (done < total)
                std::fprintf(stderr, "\r%s: %3d%%", task, int(100.0 * double(done) / double(total)));
            else
                std::fprintf(stderr, "\r%s: done%-10s\n", task, "");
            std::fflush(stderr);
        };
    return r;
}

inkwell::Device openDevice(const Options& o, bool validation) {
    inkwell::DeviceOptions options;
    options.validationMessage = [](bool error, const std::string& message) {
        std::fprintf(stderr, "validation %s: %s\n", error ? "error" : "warning", message.c_str());
    };
    options.validation = validation;
    options.device = o.device;
    return inkwell::Device(options);
}

void checkValidation(const inkwell::Device& device) {
    if (device.validationErrors())
        throw inkwell::Error(std::to_string(device.validationErrors()) +
                             " Vulkan validation error(s); first: " + device.firstValidationError());
}

Session::Session(const Options& o, std::vector<const char*> instanceExtensions, bool presentation) {
    ink::ContextOptions options;
    options.validationMessage = [](bool error, const std::string& message) {
        std::fprintf(stderr, "validation %s: %s\n", error ? "error" : "warning", message.c_str());
    };
    options.validation = o.validation;
    options.device = o.device;
    options.instanceExtensions = std::move(instanceExtensions);
    options.presentation = presentation;
    try {
        ink::createContext(ctx, options);
    } catch (...) {
        ink::destroyContext(ctx);
        throw;
    }
}

Session::~Session() { ink::destroyContext(ctx); }

void Session::checkValidation() const {
    if (ctx.validationErrors)
        throw ink::Error(std::to_string(ctx.validationErrors.load()) +
                         " Vulkan validation error(s); first: " + ctx.firstValidationMessage);
}

Scene::Scene(ink::Context& ctx, const Options& o)
    : ink::Scene(ctx, ink::loadModel(o.model, modelOptions(o)), o.style, o.refine, o.lines) {}

ink::Plot writeVectorView(const ink::PointRenderer& renderer, uint32_t frame, const std::string& path,
                          const ink::PageOptions& page) {
    ink::Plot plot = ink::layoutPlot(renderer.vectorDrawing(frame), page);
    ink::writePlot(path, plot);
    return plot;
}

// "42 s", "12 min 5 s", "2 h 3 min".
static std::string duration(double seconds) {
    const long long s = std::llround(seconds);
    char text[64];
    if (s < 60)
        std::snprintf(text, sizeof text, "%lld s", s);
    else if (s < 3600)
        std::snprintf(text, sizeof text, "%lld min %lld s", s / 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%lld h %lld min", s / 3600, s / 60 % 60);
    return text;
}

void printPlot(const ink::Plot& plot) {
    for (const ink::PlotLayer& l : plot.layers)
        std::printf(
            "  pen %u (%s): %zu paths (%zu given), pen-up travel %.0f mm (%.0f mm unordered), pen down %.0f "
            "mm, %zu lifts, about %s to plot\n",
            l.pen, l.name.c_str(), l.paths.size(), l.pathsBefore, l.travelAfter, l.travelBefore, l.penDown, l.lifts,
            duration(l.plotSeconds).c_str());
}

void writeJson(const std::string& path, const json& j) {
    if (path.empty()) return;
    ink::writeFileAtomically(path, j.dump(2) + "\n");  // every write and the close checked
}

}  // namespace app
