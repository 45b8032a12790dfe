// validate: built-in scenes through the whole pipeline with validation and synchronization validation on,
// checking the invariants a user relies on.
#include "commands.h"
#include "lines/contour_device.h"
#include "surface/shapes.h"

#include <cstdio>

namespace app {

namespace {

struct Check {
    std::string scene;
    std::vector<std::string> failures;
    size_t points = 0;
    void require(bool ok, const std::string& what) {
        if (!ok) failures.push_back(what);
    }
};

void checkScene(ink::Context& ctx, const std::string& name, const ink::Model& model, Check& check) {
    for (ink::SampleStyle style : {ink::SampleStyle::Stipple, ink::SampleStyle::Direction}) {
        ink::RefineOptions options;
        options.style = style;
        options.levels = 3;
        std::string label = name + (style == ink::SampleStyle::Stipple ? " stipple" : " direction");
        {
            ink::Refinement refinement(ctx, model.surface, options);
            ink::GpuRefinement& r = refinement.gpu();
            ink::runRefinement(ctx, r);
            auto points = ink::readPoints(ctx, r);
            auto levels = ink::readLevelStats(ctx, r);
            uint64_t kept = 0;
            for (const auto& l : levels) {
                kept += l.kept;
                uint64_t accounted = l.kept;
                for (uint32_t d : l.dropped) accounted += d;
                check.require(accounted == l.candidates, label + ": level " + std::to_string(l.level) +
                                                             " loses candidates (" + std::to_string(accounted) +
                                                             " of " + std::to_string(l.candidates) + ")");
            }
            check.require(kept == points.size(), label + ": drawn points differ from the kept count");
            check.require(levels.back().kept > levels.front().kept, label + ": the last level added no points");
            size_t off = 0;
            for (const auto& p : points) {
                Eigen::Vector3d x(p.position[0], p.position[1], p.position[2]), g;
                double f = model.surface.eval(x, g);
                if (!(std::abs(f) / g.norm() < 2.0 * options.eps1)) ++off;
            }
            check.require(off == 0, label + ": " + std::to_string(off) + " points off the surface");
            check.points += points.size();
            if (r.selection) {
                // The stipples: a subset of the points, each ranked in [0, 1).
                auto stipples = ink::readDrawnPoints(ctx, r);
                size_t badRanks = 0;
                for (const auto& p : stipples) badRanks += !(p.tone >= 0.0f && p.tone < 1.0f);
                check.require(!stipples.empty() && stipples.size() < points.size(),
                              label + ": " + std::to_string(stipples.size()) + " stipples selected from " +
                                  std::to_string(points.size()) + " points");
                check.require(badRanks == 0,
                              label + ": " + std::to_string(badRanks) + " stipples ranked outside [0, 1)");
            }

            // The contour traced on the device from the default view: every vertex on both of its equations.
            if (style == ink::SampleStyle::Stipple && ink::DeviceContours::supports(r)) {
                const glm::vec3 e = ink::Camera{}.eye();
                const Eigen::Vector3d eye(e.x, e.y, e.z);
                ink::DeviceContours tracer(ctx, r, uint32_t(ink::readDrawnPoints(ctx, r).size()), {});
                ink::ContourStats stats;
                const auto pieces = tracer.trace(model.surface, eye, &stats);
                size_t offContour = 0;
                for (const ink::PenStroke& s : pieces)
                    for (const Eigen::Vector3f& p : s.points) {
                        Eigen::Vector3d x = p.cast<double>(), g;
                        const double f = model.surface.eval(x, g);
                        offContour += !(std::abs(f) / g.norm() < 1e-4 &&
                                        std::abs(g.normalized().dot((x - eye).normalized())) < 1e-2);
                    }
                check.require(!pieces.empty(), label + ": the device traced no contour");
                check.require(offContour == 0,
                              label + ": " + std::to_string(offContour) + " vertices of the device's contour off it");
            }

            ink::RgbaImage image;
            {
                ink::RenderStyle renderStyle;
                renderStyle.hiddenLines = true;
                ink::OffscreenRenderer renderer(ctx, 256, 256, renderStyle, {&r});
                image = renderer.render(ink::Camera{});
            }
            size_t dark = 0;
            for (size_t i = 0; i < image.pixels.size(); i += 4) dark += image.pixels[i] < 128;
            check.require(dark > 300, label + ": the image is blank (" + std::to_string(dark) + " dark pixels)");
            check.require(image.pixels[0] == 255, label + ": the image corner is not paper");
        }
    }
}

int runValidate(Options& o) {
    Options validated = o;
    validated.validation = true;
    Session session(validated);
    struct SceneSource {
        std::string name;
        ink::Model model;
    };
    std::vector<SceneSource> scenes;
    scenes.push_back({"sphere", ink::fitModel(ink::spherePoints(64), {})});
    scenes.push_back({"torus", ink::fitModel(ink::torusPoints(24, 12), {})});
    if (!o.model.empty())
        scenes.push_back({o.model, ink::loadModel(o.model, {o.controlPoints ? o.controlPoints : 200})});

    size_t failures = 0, points = 0;
    for (auto& s : scenes) {
        Check check{s.name, {}, 0};
        checkScene(session.ctx, s.name, s.model, check);
        points += check.points;
        for (const auto& f : check.failures) std::printf("FAIL %s\n", f.c_str());
        std::printf("%s %s: %zu points checked\n", check.failures.empty() ? "ok  " : "FAIL", s.name.c_str(),
                    check.points);
        failures += check.failures.size();
    }
    uint32_t messages = session.ctx.validationErrors.load();
    std::printf("validate: %zu scenes, %zu points, %zu failed checks, %u validation errors, %u warnings on %s: %s\n",
                scenes.size(), points, failures, messages, session.ctx.validationWarnings.load(),
                session.ctx.properties.deviceName, failures == 0 && messages == 0 ? "OK" : "FAILED");
    return failures == 0 && messages == 0 ? 0 : 1;
}

}  // namespace

void addValidateCommand(CLI::App& cli, Options& o, Commands& commands) {
    CLI::App* validate = cli.add_subcommand(
        "validate", "Run built-in scenes (and MODEL, if given) through the pipeline with validation and check them");
    validate->add_option("model", o.model, "Also validate this model (200 control points unless given)");
    validate->add_option("--control-points", o.controlPoints, "Control points for MODEL")->check(nonNegativeInteger());
    validate->add_option("--device", o.device, "Vulkan device: an index or part of its name");
    commands.emplace_back(validate, [&o] { return runValidate(o); });
}

}  // namespace app
