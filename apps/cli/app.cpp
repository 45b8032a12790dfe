#include "app.h"

#include "inkwell/ranges.h"
#include "preset.h"

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

inkwell::ModelOptions modelOptions(const Options& o) {
    inkwell::ModelOptions m;
    m.controlPoints = o.controlPoints;
    m.method = o.fit == "global" ? inkwell::FitMethod::Global : inkwell::FitMethod::PartitionOfUnity;
    m.creaseAngleDeg = o.creaseAngle;
    m.trim = o.trim;
    // The .hrbf keeps the surface alone (a model read from it has no support and no rims; only its far field is
    // trimmed): fit does not build them (support 2.5 s and rims 0.4 s of a 10⁶-point scan's fit).
    m.support = !(o.command && o.command->get_name() == "fit");
    m.removeOutliers = o.removeOutliers;
    m.smoothNoise = o.smoothNoise;
    // A point cloud's creases (estimated, 2 s for a 10⁶-point scan) only with the style's pen lines, where asked
    // for (--creases on), or in the viewer, whose panel turns them on: fit, sample and a render of dots alone skip
    // them. A mesh's lines are always found, and drawn in every style (below).
    const bool pen = o.drawing.contours || o.drawing.hatching;
    m.features = o.creases == "on" || (o.creases == "auto" && pen) || (o.command && o.command->get_name() == "view");
    return m;
}

void addModelOptions(CLI::App* cmd, Options& o) {
    cmd->add_option("model", o.model,
                    "Mesh, points (with normals or without) or fitted model (.obj, .ply, .off, .stl, .gltf/.glb, "
                    ".pts/.xyz/.xyzn/.pwn/.txt, .hrbf)")
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
    cmd->add_flag("!--keep-outliers", o.removeOutliers,
                  "Fit every point of a point cloud (by default points that stand alone, off the surface their "
                  "neighbours sample, are left out: a scan's stray returns, each drawn as a floating blob)");
    cmd->add_flag("!--keep-noise", o.smoothNoise,
                  "Fit a noisy point cloud's points as they are (by default a cloud whose noise is over 0.15 of its "
                  "point spacing is smoothed first: the fit interpolates every point, and drew the noise as relief)");
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
    inkwell::DrawingOptions& r = o.drawing;
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
    cmd->add_option("--rho", r.rho, "ρ₀ as a fraction of the bounding-box diagonal (default: half the seed spacing)");
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
    inkwell::Look& s = o.look;
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
    cmd->add_option("--halo", s.halo, "Paper kept clear each side of an interior contour, in pixels")
        ->capture_default_str();
    cmd->add_option("--creases", o.creases,
                    "Crease lines (a mesh's or a point cloud's sharp edges), on their own pen: auto draws a mesh's in "
                    "every style, a point cloud's with contours or hatching")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    cmd->add_option("--boundaries", o.boundaries,
                    "A mesh's boundary lines (open edges, holes' rims) and a point cloud's open rims, on their own "
                    "pen: auto draws them in every style")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    cmd->add_option("--crease-width", s.creaseWidth, "Crease pen width in pixels")->capture_default_str();
    cmd->add_option("--boundary-width", s.boundaryWidth, "Boundary pen width in pixels")->capture_default_str();
    cmd->add_option("--hatch-spacing", o.drawing.hatchSpacing,
                    "Spacing of the finest hatching, as a fraction of the bounding-box diagonal")
        ->capture_default_str();
    cmd->add_option("--hatch-families", o.drawing.hatchFamilies,
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
    cmd->add_option("--dot-size", s.dotSize, "Dot diameter in pixels")->capture_default_str();
    cmd->add_option("--silhouette-size", s.silhouetteSize, "Silhouette dot diameter in pixels")->capture_default_str();
    cmd->add_option("--tau", s.tau,
                    "Silhouette threshold τ on |n·v| (the dots' outline; none with contours, whose pen draws it)")
        ->capture_default_str();
    cmd->add_option("--tone", s.toneGamma, "Tone curve exponent γ; 0 draws every front dot")->capture_default_str();
    cmd->add_option("--ink-density", s.inkDensity, "Scales how many dots the tone draws")->capture_default_str();
    cmd->add_option("--light", o.light,
                    "Direction towards the key light, X Y Z as seen from the camera (x right, y up, z out; default "
                    "the upper left, -0.5 0.6 0.65); it follows the camera unless --light-fixed")
        ->expected(3);
    cmd->add_option("--up", o.upName,
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
    cmd->add_option("--hidden-dot-size", s.hiddenDotSize,
                    "With --hidden-lines: hidden silhouette dot diameter in pixels")
        ->capture_default_str();
    cmd->add_option("--hidden-contour-width", s.hiddenPenWidth,
                    "With --hidden-lines: hidden contour pen width in pixels")
        ->capture_default_str();
    cmd->add_option("--hidden-opacity", s.hiddenOpacity,
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
    inkwell::Page& p = o.page;
    cmd->add_option("--page", o.pageName, "SVG/PDF page: A4, A3, A5, letter or WxHmm (e.g. 300x200mm)")
        ->capture_default_str();
    cmd->add_option("--orientation", o.orientation,
                    "SVG/PDF page orientation (auto: landscape for a wide image; a WxHmm page as given)")
        ->check(CLI::IsMember({"auto", "portrait", "landscape"}))
        ->capture_default_str();
    cmd->add_option("--margin", p.marginMm, "SVG/PDF margin on every side, mm")->capture_default_str();
    cmd->add_option("--pen-width", p.penWidthMm, "SVG/PDF pen (stroke) width, mm")->capture_default_str();
    cmd->add_option("--dot-style", o.dotStyle, "SVG/PDF stipples: small closed circles or short ticks")
        ->check(CLI::IsMember({"circle", "tick"}))
        ->capture_default_str();
    cmd->add_flag("!--no-order", p.orderPaths,
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

static inkwell::Color parseColour(const std::string& text, const char* what) {
    std::string hex = text.rfind('#', 0) == 0 ? text.substr(1) : text;
    if (hex.size() != 6 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
        throw inkwell::Error(std::string(what) + " colour '" + text + "' is not of the form #rrggbb");
    unsigned value = unsigned(std::stoul(hex, nullptr, 16));
    return {float((value >> 16) & 255) / 255.0f, float((value >> 8) & 255) / 255.0f, float(value & 255) / 255.0f, 1.0f};
}

// A preset sets what the command line did not: {"style": "both", "ink": "#202040", "dot_size": 1.4, ...}.
// parsePreset (preset.cpp) checks every key like the command line checks its option.
static void applyPreset(Options& o) {
    const Preset p = parsePreset(
        inkwell::readFileCapped(o.preset, kMaxPresetBytes, "file is larger than 1 MiB, far more than any preset"),
        o.preset);
    auto given = [&](const char* option) { return o.command && o.command->count(option) > 0; };
    auto set = [&](auto& target, const auto& value, const char* option) {
        if (value && !given(option)) target = *value;
    };
    set(o.styleName, p.style, "--style");
    set(o.ink, p.ink, "--ink");
    set(o.paper, p.paper, "--paper");
    set(o.look.dotSize, p.dotSize, "--dot-size");
    set(o.look.silhouetteSize, p.silhouetteSize, "--silhouette-size");
    set(o.look.tau, p.tau, "--tau");
    set(o.look.toneGamma, p.tone, "--tone");
    set(o.look.inkDensity, p.inkDensity, "--ink-density");
    set(o.look.hiddenLines, p.hiddenLines, "--hidden-lines");
    set(o.look.screenSpacing, p.screenSpacing, "--no-screen-spacing");
    set(o.look.hiddenDotSize, p.hiddenDotSize, "--hidden-dot-size");
    set(o.look.hiddenPenWidth, p.hiddenContourWidth, "--hidden-contour-width");
    set(o.look.hiddenOpacity, p.hiddenOpacity, "--hidden-opacity");
    set(o.upName, p.up, "--up");
    if (p.lightFixed && !given("--light-fixed") && !given("--light-follows-camera")) o.lightFixed = *p.lightFixed;
    set(o.light, p.light, "--light");
    set(o.drawing.levels, p.levels, "--levels");
    o.presetLevels = bool(p.levels);
    set(o.drawing.passes, p.passes, "--passes");
    set(o.direction, p.direction, "--direction");
    set(o.look.penWidth, p.contourWidth, "--contour-width");
    set(o.look.hatchWidth, p.hatchWidth, "--hatch-width");
    set(o.look.halo, p.halo, "--halo");
    if (p.hatchSpacing && !given("--hatch-spacing")) o.drawing.hatchSpacing = double(*p.hatchSpacing);
    set(o.drawing.hatchFamilies, p.hatchFamilies, "--hatch-families");
    set(o.creases, p.creases, "--creases");
    set(o.boundaries, p.boundaries, "--boundaries");
    set(o.look.creaseWidth, p.creaseWidth, "--crease-width");
    set(o.look.boundaryWidth, p.boundaryWidth, "--boundary-width");
}

// "--style contours+hatching+stipple": at most one dot style (stipple, direction, both) and any pen lines. Without
// dots the stipple set is still refined: its splats give the depth the lines are tested against.
static void parseStyle(Options& o) {
    std::string dots;
    inkwell::DrawingOptions& d = o.drawing;
    d.contours = d.hatching = false;
    if (o.styleName.empty() || o.styleName.back() == '+' || o.styleName.front() == '+' ||
        o.styleName.find("++") != std::string::npos)
        throw inkwell::Error(
            "style '" + o.styleName +
            "' has an empty part: use stipple, direction, both, contours, hatching or parts joined by '+'");
    std::stringstream parts(o.styleName);
    std::string part;
    while (std::getline(parts, part, '+')) {
        if (part == "contours" && !d.contours)
            d.contours = true;
        else if (part == "hatching" && !d.hatching)
            d.hatching = true;
        else if ((part == "stipple" || part == "direction" || part == "both") && dots.empty())
            dots = part;
        else
            throw inkwell::Error("style '" + o.styleName + "': '" + part +
                                 "' is not stipple, direction, both, contours or hatching, or is given twice (parts "
                                 "are joined by '+', at most one of stipple, direction and both)");
    }
    auto where = [](const std::string& w) {
        return w == "device" ? inkwell::Where::Device : w == "cpu" ? inkwell::Where::Cpu : inkwell::Where::Auto;
    };
    d.contourTracer = where(o.contourTracer);
    d.hatchField = where(o.hatchField);
    d.style = dots == "direction" ? inkwell::Style::Direction
              : dots == "both"    ? inkwell::Style::Both
                                  : inkwell::Style::Stipple;
    // A model's creases (its sharp edges) and a mesh's boundaries (its rims, its holes' edges) go with every style,
    // unless asked against: dots alone show neither where an open surface ends nor where two faces of one tone meet
    // (a CAD part's stippled faces ran together, its outline along a sharp edge dashed: CGAL's fandisk, spool,
    // rotor). A point cloud's creases are searched for only with pen lines or when asked for (modelOptions).
    for (auto [setting, on, option] :
         {std::tuple{&o.creases, &d.creases, "--creases"}, std::tuple{&o.boundaries, &d.boundaries, "--boundaries"}}) {
        if (*setting != "auto" && *setting != "on" && *setting != "off")
            throw inkwell::Error(std::string(option) + " '" + *setting + "' is not auto, on or off");
        *on = *setting != "off";
    }
    o.look.dots = !dots.empty();
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

uint32_t defaultLevels(bool dots, uint32_t width, uint32_t height) {
    // A drawing of pen lines alone needs the refined points only for the lines' seeds and the splats' depth: three
    // levels do. Two (the bunny: 21,000 points) gave disks so large that a line's depth test reached past thin walls:
    // CGAL's cheese drew its inner holes' creases across its faces, 2,882 stray ink pixels of 1024², now 703.
    if (!dots) return 3;
    // Dots: 4 levels (341,000 points from the fit's 1,000 seeds), and 5 (1,365,000) from 2²¹ pixels, halfway to 2048²
    // on a log scale, where they give the tone's ink in dots of the intended size: at 2048² the bunny's 4 levels
    // drew 17,878 dots, 98% of them enlarged for too few points, covering 0.03-0.27 of the page where the light asks
    // for 0.03-0.5; 5 draw 36,541 finer dots covering 0.03-0.48 (docs/algorithm.md §3). 6 would pass the 4,194,304
    // points the device and the CPU refine. Fewer for smaller images would not pay: at 512² three levels drew coarse
    // dots and lost the silhouette.
    return uint64_t(width) * height >= (uint64_t(1) << 21) ? 5 : 4;
}

void finishOptions(Options& o) {
    inkwell::checkModelOptions(modelOptions(o));
    if (!o.preset.empty()) applyPreset(o);
    inkwell::DrawingOptions& d = o.drawing;
    // The refinement's numbers, before the model is loaded or fitted (the library checks them again for its
    // other callers).
    const CLI::Option* rho = o.command ? o.command->get_option_no_throw("--rho") : nullptr;
    if ((rho && rho->count() > 0 && d.rho == 0) || !(d.rho == 0 || (d.rho > 0 && d.rho <= 1))) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", d.rho);
        throw inkwell::Error(
            std::string("--rho ") + text +
            " must be in (0, 1]: a fraction of the bounding-box diagonal (above 1 every child is dropped)");
    }
    if (d.passes > 64) throw inkwell::Error("--passes must be between 1 and 64");
    if (d.grid < 2 || d.grid > 512)
        throw inkwell::Error("--grid " + std::to_string(d.grid) + " must be between 2 and 512 cells");
    parseStyle(o);
    if (o.direction == "axis")
        d.direction = inkwell::DirectionField::Axis;
    else if (o.direction == "curvature-min")
        d.direction = inkwell::DirectionField::CurvatureMin;
    else if (o.direction == "curvature-max")
        d.direction = inkwell::DirectionField::CurvatureMax;
    else
        throw inkwell::Error("direction '" + o.direction + "' is not axis, curvature-min or curvature-max");
    d.gridSeeds = o.seeds == "grid";
    if (o.command && o.command->get_name() == "sample")  // sample's --style: the one set it refines
        d.style = o.sampling == "direction" ? inkwell::Style::Direction : inkwell::Style::Stipple;
    if (!o.axis.empty()) d.axis = {o.axis[0], o.axis[1], o.axis[2]};
    const double axisLength = std::hypot(d.axis[0], d.axis[1], d.axis[2]);
    if (!(axisLength > 0) || !std::isfinite(axisLength)) throw inkwell::Error("--axis must be a non-zero vector");
    d.keepAllLevels = o.keepLevels == "all";
    d.distribution =
        o.distribution == "refinement" ? inkwell::Distribution::Refinement : inkwell::Distribution::BlueNoise;
    o.look.ink = parseColour(o.ink, "ink");
    o.look.paper = parseColour(o.paper, "paper");
    o.autoUp = o.upName == "auto";
    if (!o.autoUp) try {
            o.up = inkwell::parseUp(o.upName);
        } catch (const inkwell::Error& e) {
            throw inkwell::Error(std::string("--up: ") + e.what() + " or auto");
        }
    if (o.lightFixed && o.lightFollows)
        throw inkwell::Error("--light-fixed and --light-follows-camera exclude each other");
    o.look.lightFollowsCamera = !o.lightFixed;
    if (!o.light.empty()) {
        const float length = std::hypot(o.light[0], o.light[1], o.light[2]);
        if (!(length > 0) || !std::isfinite(length)) throw inkwell::Error("--light must be a non-zero vector");
        o.look.light = {o.light[0], o.light[1], o.light[2]};
    }
    // The ranges' one table: include/inkwell/ranges.h.
    namespace ranges = inkwell::ranges;
    const inkwell::Look& s = o.look;
    for (float v : {s.dotSize, s.silhouetteSize, s.hiddenDotSize}) ranges::dotSize.check(v, "dot sizes");
    ranges::tau.check(s.tau, "--tau");
    for (float v : {s.penWidth, s.hatchWidth, s.hiddenPenWidth, s.creaseWidth, s.boundaryWidth})
        ranges::penWidth.check(v, "pen widths");
    ranges::hiddenOpacity.check(s.hiddenOpacity, "--hidden-opacity");
    ranges::halo.check(s.halo, "--halo");
    ranges::hatchSpacing.check(d.hatchSpacing, "--hatch-spacing");
    ranges::toneGamma.check(s.toneGamma, "--tone");
    ranges::inkDensity.check(s.inkDensity, "--ink-density");
    // The device-independent limit here, before any work; what fits the device is checked once it is known.
    if (!ranges::levels.contains(d.levels))
        throw inkwell::Error("--levels " + std::to_string(d.levels) + " is too many: at most " +
                             std::to_string(uint32_t(ranges::levels.hi)) + " refinement levels");
    if (o.size.size() == 2 && (o.size[0] < 1 || o.size[1] < 1 || o.size[0] > 8192 || o.size[1] > 8192))
        throw inkwell::Error("--size " + std::to_string(o.size[0]) + " " + std::to_string(o.size[1]) +
                             " is outside 1..8192 pixels a side");
    const bool levelsGiven = o.presetLevels || (o.command && o.command->count("--levels") > 0);
    if (!levelsGiven && o.command && o.size.size() == 2 &&
        (o.command->get_name() == "render" || o.command->get_name() == "capture"))
        d.levels = defaultLevels(o.look.dots, o.size[0], o.size[1]);
    const inkwell::Page named = inkwell::Page::named(o.pageName);
    o.page.widthMm = named.widthMm;
    o.page.heightMm = named.heightMm;
    o.page.dotStyle = o.dotStyle == "tick" ? inkwell::DotStyle::Tick : inkwell::DotStyle::Circle;
    const bool explicitSize = o.pageName.size() > 2 && (o.pageName.back() == 'm' || o.pageName.back() == 'M');
    if (o.orientation == "portrait")
        o.page.orientation = inkwell::Orientation::Portrait;
    else if (o.orientation == "landscape")
        o.page.orientation = inkwell::Orientation::Landscape;
    else  // auto: a page given in millimetres is taken as given
        o.page.orientation = !explicitSize                    ? inkwell::Orientation::Auto
                             : named.widthMm > named.heightMm ? inkwell::Orientation::Landscape
                                                              : inkwell::Orientation::Portrait;
    ranges::simplify.check(o.page.simplify, "--simplify");
    ranges::retrace.check(o.page.retrace, "--retrace");
    ranges::merge.check(o.page.merge, "--merge");
    ranges::plotSpeed.check(o.page.drawSpeed, "--plot-speed");
    ranges::plotSpeed.check(o.page.travelSpeed, "--travel-speed");
    ranges::liftTime.check(o.page.liftSeconds, "--lift-time");
    if (!ranges::penWidthMm.contains(o.page.penWidthMm))
        throw inkwell::Error("--pen-width must be in [0.001, 10] mm (the files give a micrometre)");
    // The view fits within the margins; it must be wider and taller than the pen (the layout checks the view
    // itself once the image's proportions are known).
    if (!(o.page.marginMm >= 0 && 2 * o.page.marginMm + o.page.penWidthMm < std::min(named.widthMm, named.heightMm)))
        throw inkwell::Error("--margin must be at least 0 mm and leave room for the pen on the page");
    if (!o.camera.empty()) {
        if (!std::isfinite(o.camera[0]) || !std::isfinite(o.camera[1]) || !(o.camera[2] > 0.05f && o.camera[2] < 100))
            throw inkwell::Error("--camera needs finite angles and a distance in (0.05, 100) diagonals");
    }
}

static std::string hexColour(const inkwell::Color& c) {
    char text[8];
    auto byte = [](float v) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    std::snprintf(text, sizeof text, "#%02x%02x%02x", byte(c[0]), byte(c[1]), byte(c[2]));
    return text;
}

static const char* directionName(inkwell::DirectionField d) {
    return d == inkwell::DirectionField::Axis           ? "axis"
           : d == inkwell::DirectionField::CurvatureMin ? "curvature-min"
                                                        : "curvature-max";
}

std::string styleName(const Options& o) {
    std::string name = o.look.dots ? inkwell::styleName(o.drawing.style) : "";
    for (auto [on, part] : {std::pair{o.drawing.contours, "contours"}, std::pair{o.drawing.hatching, "hatching"}})
        if (on) name += (name.empty() ? "" : "+") + std::string(part);
    return name.empty() ? "stipple" : name;
}

Preset presetFrom(const Options& o) {
    Preset p;
    p.style = styleName(o);
    p.direction = directionName(o.drawing.direction);
    p.levels = o.drawing.levels;
    if (o.drawing.passes > 0) p.passes = o.drawing.passes;
    p.ink = hexColour(o.look.ink);
    p.paper = hexColour(o.look.paper);
    p.dotSize = o.look.dotSize;
    p.silhouetteSize = o.look.silhouetteSize;
    p.tau = o.look.tau;
    p.tone = o.look.toneGamma;
    p.inkDensity = o.look.inkDensity;
    p.hiddenLines = o.look.hiddenLines;
    p.screenSpacing = o.look.screenSpacing;
    p.hiddenDotSize = o.look.hiddenDotSize;
    p.hiddenContourWidth = o.look.hiddenPenWidth;
    p.hiddenOpacity = o.look.hiddenOpacity;
    p.light = std::vector<float>{o.look.light[0], o.look.light[1], o.look.light[2]};
    p.up = o.autoUp ? "auto" : inkwell::upName(o.up);
    p.lightFixed = !o.look.lightFollowsCamera;
    p.contourWidth = o.look.penWidth;
    p.hatchWidth = o.look.hatchWidth;
    p.halo = o.look.halo;
    p.hatchSpacing = float(o.drawing.hatchSpacing);
    p.hatchFamilies = o.drawing.hatchFamilies;
    p.creases = o.creases;
    p.boundaries = o.boundaries;
    p.creaseWidth = o.look.creaseWidth;
    p.boundaryWidth = o.look.boundaryWidth;
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
    t.upName = *now.up;
    t.light = *now.light;
    t.lightFixed = *now.lightFixed;
    t.lightFollows = false;
    t.command = nullptr;  // no option counts as given: every key of the file wins
    t.preset = path;
    finishOptions(t);
    o = t;
}

inkwell::Camera cameraFrom(const Options& o) {
    inkwell::Camera c;
    if (o.autoView) c = *o.autoView;
    c.up = o.up;
    if (o.camera.size() == 3) {
        c.target = {0, 0, 0};
        c.azimuthDeg = o.camera[0];
        c.elevationDeg = std::clamp(o.camera[1], -89.0f, 89.0f);
        c.distance = o.camera[2];
    }
    return c;
}

ViewReport resolveView(Options& o, const inkwell::Drawing& drawing, float aspect) {
    ViewReport r;
    const auto start = Clock::now();
    if (o.autoUp && o.camera.empty()) {  // the file's convention (glTF: +y), else the shape's; and the view
        r.view = drawing.firstViewReport(aspect);
        o.up = r.view.camera.up;
        r.upReason = r.view.upReason;
    } else if (o.autoUp) {  // the up axis alone: the camera is given
        o.up = drawing.firstUp(&r.upReason);
    } else {
        if (o.camera.empty()) r.view = drawing.firstViewReport(o.up, aspect);
        r.upReason = "--up";
    }
    r.up = inkwell::upName(o.up);
    o.autoView.reset();
    if (o.camera.empty()) {
        o.autoView = r.view.camera;
        r.chosen = true;
    }
    r.milliseconds = 1000.0 * secondsSince(start);
    char text[256];
    if (r.chosen)
        std::snprintf(text, sizeof text,
                      "up %s (%s); view azimuth %.0f, elevation %.0f degrees, distance %.2f (%.0f ms)", r.up.c_str(),
                      r.upReason.c_str(), r.view.camera.azimuthDeg, r.view.camera.elevationDeg, r.view.camera.distance,
                      r.milliseconds);
    else
        std::snprintf(text, sizeof text, "up %s (%s)", r.up.c_str(), r.upReason.c_str());
    note(text);
    return r;
}

json viewJson(const ViewReport& r) {
    json j = {{"up", r.up}, {"up_reason", r.upReason}, {"chosen", r.chosen}};
    if (r.chosen) {
        j["azimuth_deg"] = r.view.camera.azimuthDeg;
        j["elevation_deg"] = r.view.camera.elevationDeg;
        j["entropy_bits"] = float(r.view.entropyBits);
        j["distance"] = r.view.camera.distance;
        if (r.view.frontDeg >= 0) j["front_deg"] = r.view.frontDeg;
    }
    j["milliseconds"] = r.milliseconds;
    return j;
}

inkwell::Reporter terminalReporter(bool quiet) {
    inkwell::Reporter r;
    if (!quiet)
        r.note = [](const std::string& line) { std::fprintf(stderr, "note: %s\n", inkwell::escapeText(line).c_str()); };
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

static inkwell::Reporter gReporter;
const inkwell::Reporter& reporter() { return gReporter; }
void setReporter(inkwell::Reporter r) { gReporter = std::move(r); }
void note(const std::string& line) {
    if (gReporter.note) gReporter.note(line);
}

inkwell::Device openDevice(const Options& o, bool validation, std::vector<const char*> instanceExtensions,
                           bool presentation) {
    inkwell::DeviceOptions options;
    options.validationMessage = [](bool error, const std::string& message) {
        std::fprintf(stderr, "validation %s: %s\n", error ? "error" : "warning", message.c_str());
    };
    options.validation = validation;
    options.device = o.device;
    options.instanceExtensions = std::move(instanceExtensions);
    options.presentation = presentation;
    return inkwell::Device(options);
}

void checkValidation(const inkwell::Device& device) {
    if (device.validationErrors())
        throw inkwell::Error(std::to_string(device.validationErrors()) +
                             " Vulkan validation error(s); first: " + device.firstValidationError());
}

inkwell::Model loadModel(const Options& o) { return inkwell::Model::load(o.model, modelOptions(o), reporter()); }

json deviceJson(const inkwell::Device& device) { return {{"device", device.name()}, {"driver", device.driver()}}; }

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

void printPlot(const inkwell::Plot& plot) {
    for (const inkwell::PenLayer& l : plot.layers())
        std::printf(
            "  pen %u (%s): %zu paths (%zu given), pen-up travel %.0f mm (%.0f mm unordered), pen down %.0f "
            "mm, %zu lifts, about %s to plot\n",
            l.pen, l.name.c_str(), l.paths, l.pathsGiven, l.travelAfterMm, l.travelBeforeMm, l.penDownMm, l.lifts,
            duration(l.plotSeconds).c_str());
}

void writeJson(const std::string& path, const json& j) {
    if (path.empty()) return;
    inkwell::writeFileAtomically(path, j.dump(2) + "\n");  // every write and the close checked
}

}  // namespace app
