// The inkwell executable as a user meets it: exit codes and one-line messages.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>

namespace {

struct Run {
    int status;
    std::string output;  // stdout and stderr together
};

Run run(const std::string& args) {
    std::string command = std::string(INKWELL_BINARY) + " " + args + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe);
    std::string out;
    std::array<char, 4096> buffer;
    while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) out.append(buffer.data(), n);
    int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, out};
}

}  // namespace

TEST_CASE("cli: --help lists the commands") {
    Run r = run("--help");
    CHECK(r.status == 0);
    CHECK(r.output.find("render") != std::string::npos);
    CHECK(r.output.find("devices") != std::string::npos);
}

TEST_CASE("cli: render of a missing file prints one line and exits non-zero, writing nothing") {
    std::string out = (std::filesystem::temp_directory_path() / "inkwell-missing.png").string();
    std::filesystem::remove(out);
    Run r = run("render /nonexistent/model.obj -o " + out);
    CHECK(r.status == 1);
    CHECK(r.output == "inkwell: cannot open '/nonexistent/model.obj': No such file or directory\n");
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("cli: render of an unreadable file (a directory) fails cleanly") {
    Run r = run("render " INKWELL_SOURCE_DIR "/assets -o /tmp/inkwell-dir.png");
    CHECK(r.status == 1);
    CHECK(r.output.rfind("inkwell: ", 0) == 0);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
}

TEST_CASE("cli: render with validation writes the bunny PNG and reports its points") {
    std::string out = (std::filesystem::temp_directory_path() / "inkwell-cli-bunny.png").string();
    std::filesystem::remove(out);
    Run r = run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 100 --levels 2 --validation -o " + out);
    CHECK(r.status == 0);
    CHECK(r.output.find("validation error") == std::string::npos);
    CHECK(r.output.find("100 control points") != std::string::npos);
    CHECK(std::filesystem::file_size(out) > 1000);
}
