// validate: built-in scenes through the whole pipeline with validation and synchronization validation on,
// checking the invariants a user relies on (inkwell::selfCheck).
#include "commands.h"
#include "inkwell/diagnostics.h"

#include <cstdio>

namespace app {

namespace {

int runValidate(Options& o) {
    inkwell::Device device = openDevice(o, true);
    inkwell::ModelOptions model;
    model.controlPoints = o.controlPoints ? o.controlPoints : 200;
    const std::vector<inkwell::SelfCheck> checks = inkwell::selfCheck(device, o.model, model, reporter());
    size_t failures = 0, points = 0;
    for (const inkwell::SelfCheck& check : checks) {
        points += check.points;
        for (const auto& f : check.failures) std::printf("FAIL %s\n", f.c_str());
        std::printf("%s %s: %zu points checked\n", check.failures.empty() ? "ok  " : "FAIL", check.scene.c_str(),
                    check.points);
        failures += check.failures.size();
    }
    const uint32_t messages = device.validationErrors();
    std::printf("validate: %zu scenes, %zu points, %zu failed checks, %u validation errors, %u warnings on %s: %s\n",
                checks.size(), points, failures, messages, device.validationWarnings(), device.name().c_str(),
                failures == 0 && messages == 0 ? "OK" : "FAILED");
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
