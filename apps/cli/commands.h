// Each file of apps/ adds its subcommands here: the CLI11 subcommand and what runs when it is chosen.
#pragma once

#include "app.h"

#include <functional>
#include <utility>
#include <vector>

namespace app {

using Commands = std::vector<std::pair<CLI::App*, std::function<int()>>>;

void addModelCommands(CLI::App& app, Options& o, Commands& commands);    // fit, sample, render, devices
void addViewCommand(CLI::App& app, Options& o, Commands& commands);      // view
void addCaptureCommands(CLI::App& app, Options& o, Commands& commands);  // capture, compare
void addValidateCommand(CLI::App& app, Options& o, Commands& commands);  // validate
void addBenchCommand(CLI::App& app, Options& o, Commands& commands);     // bench

}  // namespace app
