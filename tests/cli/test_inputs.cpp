// Issue 13's inputs and numbers: hostile .hrbf models, decompression bombs, presets and options checked
// like the command line before any work, the CPU backend's point limit, arithmetic at extreme scales,
// non-regular input files and OBJ blanks (docs/robustness.md). Each case failed before its fix.
#include "base/common.h"
#include "base/image.h"
#include "inkwell/ranges.h"
#include "io/hrbf_io.h"
#include "io/points.h"
#include "run_command.h"
#include "surface/clean.h"
#include "temp_dir.h"

#include <doctest/doctest.h>

#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj";

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A refusal: exit status 1, one line naming the problem (-q: no notes before it). `parser`: refused by
// CLI11's checks instead, with its own exit code and message format.
void refused(const std::string& args, const std::vector<std::string>& words, bool parser = false) {
    CAPTURE(args);
    Run r = runInkwell(args + " -q");
    INFO("output: " << r.output);
    if (parser) {
        CHECK(r.status != 0);
        CHECK(r.status != 2);  // not an internal error
    } else {
        CHECK(r.status == 1);
        CHECK(r.output.rfind("inkwell: ", 0) == 0);
        CHECK(r.output.find('\n') == r.output.size() - 1);
    }
    for (const std::string& w : words) CHECK_MESSAGE(contains(r.output, w), "expected: " << w);
}

bool printable(const std::string& s) {
    for (unsigned char c : s)
        if (c < 0x20 || c >= 0x7f) return false;
    return true;
}

// A PNG of only a signature, an IHDR chunk claiming `width` x `height` RGBA pixels (stb reads the
// header without checking the CRC) and the first bytes of the data.
std::string pngHeader(uint32_t width, uint32_t height) {
    std::string s = "\x89PNG\r\n\x1a\n";
    auto be32 = [&](uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8) s += char((v >> shift) & 0xff);
    };
    be32(13);
    s += "IHDR";
    be32(width);
    be32(height);
    s += std::string("\x08\x06\x00\x00\x00", 5);  // 8 bits, RGBA, deflate, no filter, no interlace
    be32(0);                                      // CRC
    be32(2);                                      // the start of the data: stb's header scan stops there
    s += "IDAT\x78\x9c";
    be32(0);
    return s;
}

// Oriented points on a sphere of `radius` around `centre`, as .xyzn text with 17 digits.
std::string sphereXyzn(double radius, double centre, int count) {
    std::string text;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        double y = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - y * y), t = golden * i;
        double n[3] = {r * std::cos(t), y, r * std::sin(t)};
        char line[256];
        std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g\n", centre + radius * n[0],
                      centre + radius * n[1], centre + radius * n[2], n[0], n[1], n[2]);
        text += line;
    }
    return text;
}

}  // namespace

// ---- Item 6: hostile .hrbf files --------------------------------------------------------------------------

TEST_CASE("inputs: a .hrbf whose coefficients overflow grad f is refused, not believed (sample, validate)" *
          doctest::test_suite("cli")) {
    TempDir dir;
    // 1e300 coefficients: ‖∇f‖ overflows, so |f|/‖∇f‖ = 0 passed and every candidate was kept.
    std::string model = dir.write("huge.hrbf",
                                  "inkwell-hrbf 1\ncenters 2\nframe 0 0 0 1\nlinear 0 0 -2 1\n"
                                  "0 0 0 0 0 1 1e300 1e300 0 0\n0 0 1 0 0 1 -1e300 0 0 0\nend\n");
    refused("sample " + model + " --backend cpu --levels 1 --points " + (dir / "out.ply"),
            {model, "overflows", "the file is inconsistent"});
    CHECK_FALSE(fs::exists(dir / "out.ply"));
}

TEST_CASE("inputs: --seeds grid on a model whose centres coincide is refused (no NaN cast to an integer)" *
          doctest::test_suite("cli")) {
    TempDir dir;
    // f = z: consistent at both centres, which are the same point.
    std::string model = dir.write("same.hrbf",
                                  "inkwell-hrbf 1\ncenters 2\nframe 0 0 0 1\nlinear 0 0 1 0\n"
                                  "0 0 0 0 0 1 0 0 0 0\n0 0 0 0 0 1 0 0 0 0\nend\n");
    refused("sample " + model + " --seeds grid --backend cpu --levels 1 --points " + (dir / "out.ply"),
            {"--seeds grid", "span no volume"});
}

// ---- Item 7: decompression bombs; printable messages ---------------------------------------------------

TEST_CASE("inputs: a PNG claiming 8000x8000 pixels is refused from its header, before decoding" *
          doctest::test_suite("cli")) {
    std::string bomb = pngHeader(8000, 8000);
    CHECK_THROWS_WITH_AS(ink::readPngFromMemory(bomb, "bomb.png"),
                         doctest::Contains("cannot read 'bomb.png' as PNG: 8000x8000 pixels (244 MiB decoded) from "
                                           "47 bytes is a decompression bomb"),
                         ink::Error);
    CHECK_THROWS_WITH_AS(ink::readPngFromMemory(pngHeader(20000, 2), "wide.png"),
                         doctest::Contains("at most 16384 a side"), ink::Error);
    // Within the limits and the ratio, the header passes and the (missing) data is what fails.
    CHECK_THROWS_WITH_AS(ink::readPngFromMemory(pngHeader(100, 100), "small.png"),
                         doctest::Contains("cannot read 'small.png' as PNG: "), ink::Error);
    TempDir dir;
    std::string a = dir.write("a.png", bomb), b = dir.write("b.png", bomb);
    refused("compare " + a + " " + b, {"8000x8000 pixels", "decompression bomb"});
}

TEST_CASE("inputs: PNG messages are printable ASCII whatever the file name or the bytes" *
          doctest::test_suite("unit")) {
    TempDir dir;
    std::string name = dir / "caf\xe9\xff.png";
    std::ofstream(name, std::ios::binary) << "\x89PNG\r\n\x1a\nnot really";
    for (const std::string& path : {name, dir / "missing-\xff.png"}) {
        try {
            ink::readPng(path);
            FAIL("accepted " << path);
        } catch (const ink::Error& e) {
            CHECK(printable(e.what()));
            CHECK(contains(e.what(), "caf??.png") + contains(e.what(), "missing-?.png") == 1);
        }
    }
}

TEST_CASE("inputs: every PNG seed and regression decodes or throws a printable ink::Error naming the file" *
          doctest::test_suite("unit")) {
    size_t files = 0;
    for (const char* root : {INKWELL_SOURCE_DIR "/tests/regressions/png", INKWELL_SOURCE_DIR "/fuzz/corpus/png"}) {
        for (const auto& entry : fs::directory_iterator(root)) {
            std::ifstream in(entry.path(), std::ios::binary);
            std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            std::string name = entry.path().filename().string();
            CAPTURE(name);
            ++files;
            try {
                ink::RgbaImage image = ink::readPngFromMemory(bytes, name);
                CHECK(image.pixels.size() == size_t(image.width) * image.height * 4);
            } catch (const ink::Error& e) {
                CHECK(contains(e.what(), "'" + name + "'"));
                CHECK(printable(e.what()));
            }
        }
    }
    CHECK(files >= 6);
    // fuzz_png's finding: a first IDAT chunk of length 0 made stb_image memcpy from a null pointer.
    CHECK_THROWS_WITH_AS(ink::readPng(INKWELL_SOURCE_DIR "/tests/regressions/png/stb-empty-idat-memcpy-null.png"),
                         doctest::Contains("an empty IDAT chunk before the image data"), ink::Error);
    // And a chunk claiming more bytes than the file has: stb grew its buffer to 2 GiB before reading it.
    CHECK_THROWS_WITH_AS(ink::readPng(INKWELL_SOURCE_DIR "/tests/regressions/png/stb-chunk-length-2gib-alloc.png"),
                         doctest::Contains("truncated: chunk IDAT claims 1229209940 bytes, 16 are left"), ink::Error);
}

// ---- Item 8: presets checked like the command line ------------------------------------------------------

TEST_CASE("inputs: a preset's values are checked for type, size and range, naming the file and the key" *
          doctest::test_suite("cli")) {
    TempDir dir;
    const std::vector<std::tuple<std::string, std::string>> cases = {
        {R"({"light": [1]})", "\"light\" must be an array of 3 numbers"},
        {R"({"light": [1, 2, "x"]})", "\"light\" must be a number"},
        {R"({"light": [0, 0, 0]})", "\"light\" must be a non-zero vector"},
        {R"({"light": [1e300, 0, 0]})", "\"light\" must be a non-zero vector of numbers within float's range"},
        {R"({"levels": 1e20})", "\"levels\" must be an integer from 0 to 15"},
        {R"({"levels": -1})", "\"levels\" must be an integer from 0 to 15"},
        {R"({"levels": 2.5})", "\"levels\" must be an integer from 0 to 15"},
        {R"({"passes": 0})", "\"passes\" must be an integer from 1 to 64"},
        {R"({"tau": 1})", "\"tau\" must be in [0, 1)"},
        {R"({"dot_size": "big"})", "\"dot_size\" must be a number"},
        {R"({"style": "cubist"})", "\"style\" is 'cubist', not parts of stipple, direction, both, contours, hatching"},
        {R"({"style": "contours+"})", "\"style\" is 'contours+', not parts of"},
        {R"({"contour_width": 0})", "\"contour_width\" must be in (0, 32] pixels"},
        {R"({"hatch_spacing": 0.5})", "\"hatch_spacing\" must be in [0.001, 0.1] of the diagonal"},
        {R"({"hatch_families": 4})", "\"hatch_families\" must be an integer from 1 to 3"},
        {R"({"ink": "#12345"})", "\"ink\" is '#12345', not a colour"},
        {R"({"hidden_lines": 1})", "\"hidden_lines\" must be true or false"},
        {R"({"hidden_dot_size": 0})", "\"hidden_dot_size\" must be in (0, 64] pixels"},
        {R"({"hidden_contour_width": 33})", "\"hidden_contour_width\" must be in (0, 32] pixels"},
        {R"({"hidden_opacity": 1.5})", "\"hidden_opacity\" must be in [0, 1]"},
        {R"({"hidden_opacity": "faint"})", "\"hidden_opacity\" must be a number"},
        {R"({"shade": 1})", "unknown key 'shade'"},
        {R"([1, 2])", "must be a JSON object"},
    };
    for (const auto& [json, words] : cases) {
        std::string preset = dir.write("p.json", json);
        refused("render " + kBunny + " --preset " + preset + " -o " + (dir / "out.png"),
                {"preset '" + preset + "'", words});
        CHECK_FALSE(fs::exists(dir / "out.png"));
    }
    // A device or a huge file is not read to the end.
    refused("render " + kBunny + " --preset /dev/zero -o " + (dir / "out.png"), {"not a regular file"});
}

// ---- Item 10: options checked before any work -----------------------------------------------------------

TEST_CASE("inputs: --rho, --control-points, --passes and --grid are refused before the fit" *
          doctest::test_suite("cli")) {
    TempDir dir;
    const std::string sample = "sample " + kBunny + " --backend cpu --levels 1 --points " + (dir / "out.ply") + " ";
    for (const char* rho : {"nan", "-1", "1e9", "0", "inf"})
        refused(sample + "--rho " + rho, {"--rho", "must be in (0, 1]"});
    refused(sample + "--control-points -1", {"--control-points", "must not be negative"}, true);
    refused(sample + "--levels -1", {"--levels", "must not be negative"}, true);
    refused(sample + "--passes 0", {"--passes"}, true);
    refused(sample + "--seeds grid --grid 1", {"--grid 1 must be between 2 and 512"});
    CHECK_FALSE(fs::exists(dir / "out.ply"));
}

TEST_CASE("inputs: --style parts, pen and hidden-line options are refused before the fit, naming what is wrong" *
          doctest::test_suite("cli")) {
    TempDir dir;
    const std::string render = "render " + kBunny + " -o " + (dir / "out.png") + " ";
    refused(render + "--style contours+cubist", {"style 'contours+cubist': 'cubist' is not stipple"});
    refused(render + "--style stipple+both", {"'both' is not stipple", "at most one of stipple, direction and both"});
    refused(render + "--style hatching+hatching", {"given twice"});
    refused(render + "--style contours+", {"style 'contours+' has an empty part"});
    refused(render + "--style contours --contour-width 0", {"pen widths must be in (0, 32] pixels"});
    refused(render + "--style hatching --hatch-spacing 0.5", {"--hatch-spacing must be in [0.001, 0.1]"});
    refused(render + "--style hatching --halo -1", {"--halo must be in [0, 32] pixels"});
    refused(render + "--style hatching --hatch-families 4", {"--hatch-families"}, true);
    refused(render + "--hidden-lines --hidden-dot-size 0", {"dot sizes must be in (0, 64] pixels"});
    refused(render + "--hidden-lines --hidden-dot-size 65", {"dot sizes must be in (0, 64] pixels"});
    refused(render + "--style contours --hidden-lines --hidden-contour-width -1",
            {"pen widths must be in (0, 32] pixels"});
    refused(render + "--hidden-lines --hidden-opacity 1.5", {"--hidden-opacity must be in [0, 1]"});
    refused(render + "--hidden-lines --hidden-opacity nan", {"--hidden-opacity must be in [0, 1]"});
    CHECK_FALSE(fs::exists(dir / "out.png"));
}

TEST_CASE("inputs: the command line and presets check one table of ranges, and quote it" * doctest::test_suite("cli")) {
    // include/inkwell/ranges.h: each value just outside its range (or on an open end) is refused by the option
    // and by the preset key alike, before any work, with the table's text of the range.
    TempDir dir;
    const std::string render = "render " + kBunny + " --style contours+hatching+stipple -o " + (dir / "out.png") + " ";
    struct Case {
        const char *option, *key;
        inkwell::Range range;
    };
    namespace ranges = inkwell::ranges;
    const Case cases[] = {{"--dot-size", "dot_size", ranges::dotSize},
                          {"--tau", "tau", ranges::tau},
                          {"--tone", "tone", ranges::toneGamma},
                          {"--ink-density", "ink_density", ranges::inkDensity},
                          {"--contour-width", "contour_width", ranges::penWidth},
                          {"--halo", "halo", ranges::halo},
                          {"--hatch-spacing", "hatch_spacing", ranges::hatchSpacing},
                          {"--hidden-opacity", "hidden_opacity", ranges::hiddenOpacity}};
    for (const Case& c : cases) {
        const std::string text = c.range.text();
        for (double v : {c.range.openLow ? c.range.lo : c.range.lo - 0.5 * c.range.lo - 0.01,
                         c.range.openHigh ? c.range.hi : c.range.hi * 1.5 + 0.01}) {
            CAPTURE(v);
            CHECK_FALSE(c.range.contains(v));
            std::ostringstream value, json, message;
            value << v;
            json << "{\"" << c.key << "\": " << v << "}";
            message << "\"" << c.key << "\" must be in " << text;
            refused(render + c.option + " " + value.str(), {"must be in " + text});
            const std::string preset = dir.write("p.json", json.str());
            refused(render + "--preset " + preset, {message.str()});
        }
    }
    CHECK(ranges::penWidth.text() == "(0, 32] pixels");
    CHECK(ranges::tau.text() == "[0, 1)");
    CHECK(ranges::hatchSpacing.text() == "[0.001, 0.1] of the diagonal");
    CHECK(ranges::hatchSpacing.contains(0.1f));  // a float's bounds are the floats nearest them
    CHECK_FALSE(ranges::tau.contains(std::nan("")));
    CHECK_FALSE(fs::exists(dir / "out.png"));
}

// ---- Item 9: the CPU backend's limit ----------------------------------------------------------------------

TEST_CASE("inputs: the CPU backend refuses more points than the device would (4,194,304), before refining" *
          doctest::test_suite("cli")) {
    TempDir dir;
    refused("sample " + kBunny + " --backend cpu --levels 8 --points " + (dir / "out.ply"),
            {"at most 4194304 fit", "use --levels"});
    CHECK_FALSE(fs::exists(dir / "out.ply"));
}

// ---- Item 5: numbers at extreme scales ---------------------------------------------------------------------

TEST_CASE("inputs: duplicate merging far from the origin stays linear (cells relative to the data's box)" *
          doctest::test_suite("unit")) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    ink::OrientedPoints points;
    const double offset = 1e10;  // offset/diagonal beyond 2e9: every point fell into one cell
    for (int i = 0; i < 100000; ++i) {
        Eigen::Vector3d p(offset + unit(random), offset + unit(random), offset + unit(random));
        points.positions.push_back(p);
        points.normals.push_back(Eigen::Vector3d::UnitZ());
        if (i % 1000 == 0) {  // and an exact duplicate
            points.positions.push_back(p);
            points.normals.push_back(Eigen::Vector3d::UnitZ());
        }
    }
    auto start = std::chrono::steady_clock::now();
    size_t merged = ink::mergeDuplicates(points, 1e-9);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(merged == 100);
    CHECK(points.positions.size() == 100000);
    CHECK(seconds < 2.0);  // quadratic before: 5e9 distance checks
}

TEST_CASE("inputs: sample keeps the input's precision: spheres at 1e7, of radius 1e300 and of 1e-300" *
          doctest::test_suite("cli")) {
    TempDir dir;
    struct Case {
        double radius, centre;
        const char* type;
    };
    for (const Case& c :
         {Case{1.0, 1e7, "double"}, Case{1e300, 0.0, "double"}, Case{1e-300, 0.0, "double"}, Case{1.0, 0.0, "float"}}) {
        CAPTURE(c.radius);
        CAPTURE(c.centre);
        std::string input = dir.write("sphere.xyzn", sphereXyzn(c.radius, c.centre, 400));
        std::string out = dir / "out.ply";
        Run r = runInkwell("sample " + input + " --backend cpu --control-points 100 --levels 2 -q --points " + out);
        INFO(r.output);
        REQUIRE(r.status == 0);
        std::ifstream in(out, std::ios::binary);
        std::string header, line;
        while (std::getline(in, line) && line != "end_header") header += line + "\n";
        CHECK(contains(header, std::string("property ") + c.type + " x\n"));
        ink::OrientedPoints points = ink::loadPoints(out);
        REQUIRE(points.positions.size() >= 100);
        std::set<std::tuple<double, double, double>> distinct;
        double worst = 0;
        for (const Eigen::Vector3d& p : points.positions) {
            REQUIRE(p.allFinite());
            distinct.insert({p.x(), p.y(), p.z()});
            worst = std::max(worst, std::abs(((p - Eigen::Vector3d::Constant(c.centre)) / c.radius).norm() - 1.0));
        }
        CHECK(distinct.size() == points.positions.size());
        CHECK(worst < 0.01);  // on the sphere, in the input's units
    }
}

// ---- Item 10: non-regular inputs, OBJ blanks ---------------------------------------------------------------

TEST_CASE("inputs: a symlink to /dev/zero is refused before it is read" * doctest::test_suite("unit")) {
    TempDir dir;
    for (const char* name : {"zero.obj", "zero.hrbf", "zero.png"}) {
        fs::create_symlink("/dev/zero", dir.path / name);
        std::string path = dir / name;
        auto start = std::chrono::steady_clock::now();
        if (std::string(name) == "zero.png")
            CHECK_THROWS_WITH_AS(ink::readPng(path), doctest::Contains("not a regular file (a character device)"),
                                 ink::Error);
        else if (std::string(name) == "zero.hrbf")
            CHECK_THROWS_WITH_AS(ink::loadHrbf(path), doctest::Contains("not a regular file"), ink::Error);
        else
            CHECK_THROWS_WITH_AS(ink::loadPoints(path), doctest::Contains("not a regular file"), ink::Error);
        CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 0.5);
    }
}

TEST_CASE("inputs: OBJ treats a form feed, vertical tab or carriage return after 'v' or 'f' as a blank" *
          doctest::test_suite("unit")) {
    for (const char* blank : {"\f", "\v"}) {
        std::string b = blank;
        std::string obj =
            "v" + b + "0 0 0\nv 1 0 0\nv 0 1 0\nv" + b + "0 0 1\nf" + b + "1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
        ink::OrientedPoints points = ink::parsePoints(obj, "obj", "blank.obj");
        CHECK(points.positions.size() == 4);
    }
    // A lone '\r' ends a line (old Mac files): "v" alone is refused for its missing numbers, not skipped.
    CHECK_THROWS_WITH_AS(ink::parsePoints("v\r0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "obj", "cr.obj"),
                         doctest::Contains("cr.obj: line 1: expected 3 to 7 numbers after 'v', found 0"), ink::Error);
}
