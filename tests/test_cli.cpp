// The inkwell executable as a user meets it: exit codes and one-line messages.
#include "run_command.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>
#include <string>
#include <sys/wait.h>

namespace {

Run run(const std::string& args) { return runInkwell(args); }

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

TEST_CASE("cli: sample writes a binary PLY in the input's units and stats with per-level counts") {
    std::string dir = std::filesystem::temp_directory_path().string();
    std::string ply = dir + "/inkwell-cli-sample.ply", stats = dir + "/inkwell-cli-sample.json";
    Run r = run("sample " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 64 --levels 2 --passes 1 --points " +
                ply + " --stats " + stats);
    REQUIRE(r.status == 0);
    std::ifstream in(ply, std::ios::binary);
    std::string header, line;
    while (std::getline(in, line) && line != "end_header") header += line + "\n";
    CHECK(header.find("format binary_little_endian 1.0") != std::string::npos);
    CHECK(header.find("property float nz") != std::string::npos);
    size_t at = header.find("element vertex ");
    REQUIRE(at != std::string::npos);
    size_t count = std::stoul(header.substr(at + 15));
    std::vector<float> data(count * 6);
    in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * 4));
    CHECK(in.gcount() == std::streamsize(data.size() * 4));
    // The bunny's own units: its y runs from about 3 to 15 (normalized coordinates would stay within ±0.5).
    float maxY = 0;
    for (size_t i = 0; i < count; ++i) maxY = std::max(maxY, data[6 * i + 1]);
    CHECK(maxY > 5.0f);

    std::ifstream js(stats);
    std::string text((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
    for (const char* key : {"\"control_points\": 64", "\"refine\"", "\"levels\"", "\"candidates\"", "\"kept\"",
                            "\"dropped\"", "\"seconds\"", "\"max_normal_angle_deg\"", "\"points\": " })
        CHECK_MESSAGE(text.find(key) != std::string::npos, key);
    CHECK(text.find("\"points\": " + std::to_string(count)) != std::string::npos);
}

TEST_CASE("cli: absurd requests are refused up front, leaving no output") {
    std::string out = (std::filesystem::temp_directory_path() / "inkwell-cli-absurd.png").string();
    std::filesystem::remove(out);
    Run levels = run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --levels 14 -o " + out);
    CHECK(levels.status == 1);
    CHECK(levels.output.find("asks for up to") != std::string::npos);
    Run size = run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --size 100000 100000 -o " + out);
    CHECK(size.status == 1);
    CHECK(size.output == "inkwell: --size 100000 100000 is outside 1..8192 pixels a side\n");
    Run colour = run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --ink red -o " + out);
    CHECK(colour.status == 1);
    CHECK(colour.output == "inkwell: ink colour 'red' is not of the form #rrggbb\n");
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("cli: validate passes its built-in scenes with zero validation messages") {
    Run r = run("validate");
    CHECK(r.status == 0);
    CHECK(r.output.find("0 failed checks, 0 validation errors") != std::string::npos);
    CHECK(r.output.find(": OK") != std::string::npos);
}

TEST_CASE("cli: bench runs the sphere workload and reports the documented keys") {
    std::string json = (std::filesystem::temp_directory_path() / "inkwell-cli-bench.json").string();
    Run r = run("bench --workload sphere --repeat 1 --frames 3 --json " + json);
    REQUIRE(r.status == 0);
    std::ifstream js(json);
    std::string text((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
    for (const char* key : {"\"workload\": \"sphere\"", "\"candidates\": 65532", "\"points\"", "\"fit_seconds\"",
                            "\"refine_seconds\"", "\"preprocess_seconds\"", "\"frame_ms_median\"",
                            "\"cpu_refine_seconds\"", "\"peak_memory_mb\"", "\"device\"", "\"driver\"",
                            "\"level_gpu_ms\"", "\"frame_passes_ms_median\"", "\"stamp\"",
                            "\"dots_drawn_first_frame\""})
        CHECK_MESSAGE(text.find(key) != std::string::npos, key);
}
