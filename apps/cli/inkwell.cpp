// inkwell: pen-and-ink drawings of HRBF implicit surfaces. Argument parsing and dispatch; each command is in
// its own file of apps/, the work in engine/.
#include "commands.h"

#include <cstdio>

int main(int argc, char** argv) {
    CLI::App cli{
        "inkwell: pen-and-ink drawings (stipples and hatches) of Hermite RBF implicit surfaces, "
        "fitted to meshes or oriented points and refined on the GPU with Vulkan"};
    cli.require_subcommand(1);
    cli.fallthrough();  // -q may follow the subcommand
    cli.set_version_flag("--version", "inkwell 0.1.0");
    bool quiet = false;
    cli.add_flag("-q,--quiet", quiet, "No notes on stderr");

    app::Options options;
    app::Commands commands;
    app::addModelCommands(cli, options, commands);
    app::addViewCommand(cli, options, commands);
    app::addCaptureCommands(cli, options, commands);
    app::addValidateCommand(cli, options, commands);
    app::addBenchCommand(cli, options, commands);

    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return cli.exit(e);
    }
    app::setReporter(app::terminalReporter(quiet));
    try {
        for (auto& [command, run] : commands)
            if (command->parsed()) {
                options.command = command;  // a --preset asks it which options the user gave
                return run();
            }
    } catch (const inkwell::Error& e) {
        std::fprintf(stderr, "inkwell: %s\n", inkwell::escapeText(e.what()).c_str());  // no raw bytes of a file
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "inkwell: out of memory\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "inkwell: internal error: %s\n", inkwell::escapeText(e.what()).c_str());
        return 2;
    }
    return 0;
}
