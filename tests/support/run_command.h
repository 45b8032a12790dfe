// Running the inkwell executable (or any shell command) from tests, as a user would.
#pragma once

#include <doctest/doctest.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>

struct Run {
    int status;          // the exit code, or 128 + the signal that ended it
    std::string output;  // what it printed on stdout (and on stderr where the command line sends it there)
};

inline Run runShell(const std::string& commandLine) {
    FILE* pipe = popen(commandLine.c_str(), "r");
    REQUIRE(pipe);
    std::string out;
    std::array<char, 4096> buffer;
    while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) out.append(buffer.data(), n);
    int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

// inkwell with `args`, stdout and stderr together.
// (Appended in place: GCC 12 at -O3 warns falsely of an out-of-bounds copy in the chained `+` form.)
inline Run runInkwell(const std::string& args) {
    std::string command = INKWELL_BINARY;
    command.append(" ").append(args).append(" 2>&1");
    return runShell(command);
}
