// The inkwell executable as a user meets it: exit codes and one-line messages.
#include "base/image.h"
#include "run_command.h"
#include "temp_dir.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace {

Run run(const std::string& args) { return runInkwell(args); }

}  // namespace

TEST_CASE("cli: --help lists the commands" * doctest::test_suite("cli")) {
    Run r = run("--help");
    CHECK(r.status == 0);
    CHECK(r.output.find("render") != std::string::npos);
    CHECK(r.output.find("devices") != std::string::npos);
}

TEST_CASE("cli: render of a missing file prints one line and exits non-zero, writing nothing" *
          doctest::test_suite("cli")) {
    TempDir dir;
    std::string out = dir / "missing.png";
    Run r = run("render /nonexistent/model.obj -o " + out);
    CHECK(r.status == 1);
    CHECK(r.output == "inkwell: cannot open '/nonexistent/model.obj': No such file or directory\n");
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("cli: render of an unreadable file (a directory) fails cleanly" * doctest::test_suite("cli")) {
    TempDir dir;
    Run r = run("render " INKWELL_SOURCE_DIR "/assets -o " + dir / "dir.png");
    CHECK(r.status == 1);
    CHECK(r.output.rfind("inkwell: ", 0) == 0);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
}

TEST_CASE("cli: render with validation writes the bunny PNG and reports its points" * doctest::test_suite("cli")) {
    TempDir dir;
    std::string out = dir / "bunny.png";
    Run r =
        run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 100 --levels 2 --validation -o " + out);
    CHECK(r.status == 0);
    CHECK(r.output.find("validation error") == std::string::npos);
    CHECK(r.output.find("100 control points") != std::string::npos);

    // The picture: the default size, opaque, paper all round the edges, and the bunny's dots (a hundred or so
    // at two levels and 1024 pixels) spread about the middle.
    ink::RgbaImage image = ink::readPng(out);
    REQUIRE(image.width == 1024);
    REQUIRE(image.height == 1024);
    size_t opaque = 0, inked = 0, edgeInk = 0;
    std::array<size_t, 4> quadrantInk{};                           // about the centre: left/right + 2 × top/bottom
    uint32_t x0 = image.width, y0 = image.height, x1 = 0, y1 = 0;  // the inked pixels' bounding box
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const uint8_t* p = &image.pixels[(size_t(y) * image.width + x) * 4];
            opaque += p[3] == 255;
            if (299 * p[0] + 587 * p[1] + 114 * p[2] >= 128'000) continue;  // luma: paper or a faint edge
            ++inked;
            x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
            edgeInk += std::min({x, y, image.width - 1 - x, image.height - 1 - y}) < 64;
            ++quadrantInk[(x >= 512) + 2 * (y >= 512)];
        }
    size_t pixels = size_t(image.width) * image.height;
    CHECK(opaque == pixels);
    CHECK(edgeInk == 0);
    CHECK(inked > 100);
    CHECK(double(inked) / double(pixels) < 0.02);  // dots on paper, not a filled shape
    for (size_t q = 0; q < 4; ++q) CHECK_MESSAGE(quadrantInk[q] > 10, "quadrant " << q);
    // The bunny fills a good part of the frame and is centred in it (the camera looks at the model's centre).
    CHECK(x1 - x0 > 400);
    CHECK(y1 - y0 > 400);
    CHECK(std::abs(int(x0 + x1) / 2 - 512) < 80);
    CHECK(std::abs(int(y0 + y1) / 2 - 512) < 80);
}

TEST_CASE("cli: sample writes ranked stipples as a binary PLY in the input's units, and their spacing in stats" *
          doctest::test_suite("cli")) {
    TempDir dir;
    std::string ply = dir / "sample.ply", stats = dir / "sample.json";
    Run r = run("sample " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 64 --levels 3 --points " + ply +
                " --stats " + stats);
    REQUIRE(r.status == 0);
    std::ifstream in(ply, std::ios::binary);
    std::string header, line;
    while (std::getline(in, line) && line != "end_header") header += line + "\n";
    CHECK(header.find("format binary_little_endian 1.0") != std::string::npos);
    CHECK(header.find("property float nz\nproperty int level\nproperty float rank\n") != std::string::npos);
    size_t at = header.find("element vertex ");
    REQUIRE(at != std::string::npos);
    size_t count = std::stoul(header.substr(at + 15));
    REQUIRE(count > 100);
    std::vector<float> data(count * 8);
    in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * 4));
    CHECK(in.gcount() == std::streamsize(data.size() * 4));
    // The bunny's own units: its y runs from about 3 to 15 (normalized coordinates would stay within ±0.5).
    // Levels 0..3; ranks in [0, 1), a quarter of them below 0.25.
    float maxY = 0;
    size_t quarter = 0;
    std::set<int32_t> levels;
    for (size_t i = 0; i < count; ++i) {
        maxY = std::max(maxY, data[8 * i + 1]);
        int32_t level;
        std::memcpy(&level, &data[8 * i + 6], 4);
        levels.insert(level);
        float rank = data[8 * i + 7];
        CHECK((rank >= 0.0f && rank < 1.0f));
        quarter += rank < 0.25f;
    }
    CHECK(maxY > 5.0f);
    CHECK(*levels.begin() >= 0);
    CHECK(*levels.rbegin() <= 3);
    CHECK(double(quarter) / double(count) == doctest::Approx(0.25).epsilon(0.05));

    std::ifstream js(stats);
    nlohmann::json j = nlohmann::json::parse(js);
    CHECK(j["control_points"] == 64);
    // The partition of unity: interpolating in float, its patches of 8-24 points, each listed in the device's
    // look-up grid at least once.
    CHECK(j["fit"]["method"] == "pu");
    CHECK(j["fit"]["max_distance"].get<double>() < 1e-6);
    const auto& patches = j["fit"]["patches"];
    CHECK(patches["count"].get<size_t>() > 1);
    CHECK(patches["min_points"].get<size_t>() >= 8);
    CHECK(patches["max_points"].get<size_t>() <= 24);
    CHECK(patches["grid_cells"].get<size_t>() > 1);
    CHECK(patches["grid_entries"].get<size_t>() >= patches["count"].get<size_t>());
    CHECK(j["refine"]["points"] == count);
    CHECK(j["refine"]["levels"].size() == 4);
    CHECK(j["select"]["candidates"].get<size_t>() > 3 * count);
    // The whole set and the prefixes 1/2, 1/4, 1/8, each with its size and spacing (estimated area).
    const auto& prefixes = j["spacing"]["prefixes"];
    REQUIRE(prefixes.size() == 4);
    double fraction = 1.0;
    for (const auto& p : prefixes) {
        CHECK(p["fraction"].get<double>() == fraction);
        CHECK(p["points"].get<double>() == doctest::Approx(fraction * double(count)).epsilon(0.1));
        CHECK(p["mean_nn_over_r_max"].get<double>() > 0.65);
        CHECK(p["min_nn_over_r_max"].get<double>() > 0.4);
        fraction /= 2;
    }
}

TEST_CASE("cli: absurd requests are refused up front, leaving no output" * doctest::test_suite("cli")) {
    TempDir dir;
    std::string out = dir / "absurd.png";
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

TEST_CASE("cli: validate passes its built-in scenes with zero validation messages" * doctest::test_suite("cli")) {
    Run r = run("validate");
    CHECK(r.status == 0);
    CHECK(r.output.find("0 failed checks, 0 validation errors") != std::string::npos);
    CHECK(r.output.find(": OK") != std::string::npos);
}

TEST_CASE("cli: bench runs the sphere workload and reports the documented keys" * doctest::test_suite("cli")) {
    TempDir tmp;
    std::string json = tmp / "bench.json";
    Run r = run("bench --workload sphere --repeat 1 --frames 3 --json " + json);
    REQUIRE(r.status == 0);
    std::ifstream js(json);
    std::string text((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
    // The sphere's 6 seeds, 6 levels of 4 children, one pass: 6·(1 + 4 + … + 4⁶) candidates, stipples selected.
    for (const char* key : {"\"workload\": \"sphere\"",
                            "\"candidates\": 32766",
                            "\"points\"",
                            "\"fit_seconds\"",
                            "\"distribution\": \"blue-noise\"",
                            "\"stipples\"",
                            "\"select_ms\"",
                            "\"refine_seconds\"",
                            "\"preprocess_seconds\"",
                            "\"frame_ms_median\"",
                            "\"cpu_refine_seconds\"",
                            "\"peak_memory_mb\"",
                            "\"device\"",
                            "\"driver\"",
                            "\"level_gpu_ms\"",
                            "\"frame_passes_ms_median\"",
                            "\"stamp\"",
                            "\"dots_drawn_first_frame\"",
                            "\"screen_spacing\": true",
                            "\"page\"",
                            "\"mean_nn_over_r_max\""})
        CHECK_MESSAGE(text.find(key) != std::string::npos, key);
    // An unknown workload is refused with the names of all the known ones.
    Run bad = run("bench --workload bunny-lines,bunny-lines-device --repeat 1");
    CHECK(bad.status != 0);
    CHECK(bad.output.find("unknown workload 'bunny-lines,bunny-lines-device'") != std::string::npos);
    for (const char* name : {"bunny-684-lines-device", "bunny-lines-device", "torus-100k"})
        CHECK_MESSAGE(bad.output.find(name) != std::string::npos, name);
}

namespace {

// The inked pixels' count and bounding box.
struct Ink {
    size_t count = 0;
    uint32_t x0 = UINT32_MAX, y0 = UINT32_MAX, x1 = 0, y1 = 0;
};
Ink inkOf(const ink::RgbaImage& image) {
    Ink ink;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x)
            if (image.pixels[(size_t(y) * image.width + x) * 4] < 128) {
                ++ink.count;
                ink.x0 = std::min(ink.x0, x), ink.x1 = std::max(ink.x1, x);
                ink.y0 = std::min(ink.y0, y), ink.y1 = std::max(ink.y1, y);
            }
    return ink;
}

}  // namespace

TEST_CASE("cli: --up z stands a z-up model up as the y-up original, also from a preset" * doctest::test_suite("cli")) {
    namespace fs = std::filesystem;
    TempDir tmp;
    const fs::path dir = tmp.path;
    // The bunny turned z-up: (x, y, z) -> (x, -z, y).
    {
        std::ifstream in(INKWELL_SOURCE_DIR "/assets/bunny.obj");
        std::ofstream out(dir / "bunny-zup.obj");
        std::string line;
        while (std::getline(in, line)) {
            if (line.rfind("v ", 0) == 0 || line.rfind("vn ", 0) == 0) {
                char kind[4];
                double x, y, z;
                REQUIRE(std::sscanf(line.c_str(), "%3s %lf %lf %lf", kind, &x, &y, &z) == 4);
                char text[160];
                std::snprintf(text, sizeof text, "%s %.9g %.9g %.9g", kind, x, -z, y);
                line = text;
            }
            out << line << "\n";
        }
    }
    std::ofstream(dir / "zup.json") << R"({"up": "z"})";
    // One camera for all (the automatic view is chosen from each fit's points, which differ a little).
    const std::string common = " --control-points 200 --levels 3 --camera 30,15,1.6 --size 256 256 -q -o ";
    REQUIRE(run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj" + common + (dir / "yup.png").string()).status == 0);
    REQUIRE(
        run("render " + (dir / "bunny-zup.obj").string() + " --up z" + common + (dir / "zup.png").string()).status ==
        0);
    REQUIRE(run("render " + (dir / "bunny-zup.obj").string() + " --preset " + (dir / "zup.json").string() + common +
                (dir / "preset.png").string())
                .status == 0);
    REQUIRE(run("render " + (dir / "bunny-zup.obj").string() + common + (dir / "lying.png").string()).status == 0);
    Ink yup = inkOf(ink::readPng((dir / "yup.png").string()));
    REQUIRE(yup.count > 500);
    for (const char* name : {"zup.png", "preset.png"}) {
        CAPTURE(std::string(name));
        Ink zup = inkOf(ink::readPng((dir / name).string()));
        // The same view: the same outline within a few pixels (the fit picks other control points, the ear tips
        // move a little), about the same ink.
        CHECK(std::abs(int(zup.x0) - int(yup.x0)) <= 4);
        CHECK(std::abs(int(zup.x1) - int(yup.x1)) <= 4);
        CHECK(std::abs(int(zup.y0) - int(yup.y0)) <= 4);
        CHECK(std::abs(int(zup.y1) - int(yup.y1)) <= 4);
        CHECK(double(zup.count) == doctest::Approx(double(yup.count)).epsilon(0.1));
    }
    // Without --up it lies on its back: wider than tall, unlike the sitting bunny.
    Ink lying = inkOf(ink::readPng((dir / "lying.png").string()));
    CHECK(lying.x1 - lying.x0 > lying.y1 - lying.y0);
    CHECK(yup.x1 - yup.x0 < yup.y1 - yup.y0 + 20);

    Run bad = run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --up w -o " + (dir / "bad.png").string());
    CHECK(bad.status == 1);
    CHECK(bad.output == "inkwell: --up: up axis 'w' is not one of x, -x, y, -y, z, -z or auto\n");
}

TEST_CASE("cli: a point cloud without normals is drawn as the same cloud with its normals" *
          doctest::test_suite("cli")) {
    // A torus of positions alone (.xyz, three numbers a line) and with its normals (.xyzn): the first has its normals
    // estimated (estimateNormals, orientNormals), with a note and its count in the stats, and draws the same torus.
    TempDir tmp;
    std::string bare, full;
    for (int i = 0; i < 96; ++i)
        for (int j = 0; j < 48; ++j) {
            const double u = 2 * M_PI * i / 96, v = 2 * M_PI * j / 48;
            const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)),
                p = 0.3 * Eigen::Vector3d(std::cos(u), std::sin(u), 0) + 0.1 * n;
            char position[100], normal[100];
            std::snprintf(position, sizeof position, "%.9g %.9g %.9g", p.x(), p.y(), p.z());
            std::snprintf(normal, sizeof normal, " %.9g %.9g %.9g\n", n.x(), n.y(), n.z());
            bare += std::string(position) + "\n";
            full += std::string(position) + normal;
        }
    const std::string common = " --levels 3 --camera 30,40,1.6 --size 256 256 -o ";
    const Run estimated =
        run("render " + tmp.write("torus.xyz", bare) + common + (tmp / "bare.png") + " --stats " + (tmp / "bare.json"));
    REQUIRE(estimated.status == 0);
    CHECK(estimated.output.find("note: estimated the normals of all 4608 points (the file gives none, or zero) from "
                                "their 16 nearest neighbours, oriented along the surface\n") != std::string::npos);
    REQUIRE(run("render " + tmp.write("torus.xyzn", full) + common + (tmp / "full.png") + " -q").status == 0);
    std::ifstream stats(tmp / "bare.json");
    CHECK(nlohmann::json::parse(stats)["fit"]["estimated_normals"] == 4608);
    const Ink a = inkOf(ink::readPng(tmp / "bare.png")), b = inkOf(ink::readPng(tmp / "full.png"));
    REQUIRE(b.count > 1000);
    CHECK(std::abs(int(a.x0) - int(b.x0)) <= 2);
    CHECK(std::abs(int(a.x1) - int(b.x1)) <= 2);
    CHECK(std::abs(int(a.y0) - int(b.y0)) <= 2);
    CHECK(std::abs(int(a.y1) - int(b.y1)) <= 2);
    CHECK(double(a.count) == doctest::Approx(double(b.count)).epsilon(0.05));
}

TEST_CASE("cli: the hidden lines' dot size, contour width and opacity take effect, from options and a preset" *
          doctest::test_suite("cli")) {
    namespace fs = std::filesystem;
    TempDir tmp;
    const fs::path dir = tmp.path;
    // The torus seen from above: the far side of its hole is hidden.
    const std::string common =
        "render " INKWELL_SOURCE_DIR "/tests/golden/torus.pts --levels 3 --camera 20,20,1.4 --size 256 256 -q ";
    auto render = [&](const std::string& name, const std::string& options) {
        const std::string out = (dir / (name + ".png")).string();
        Run r = run(common + options + " -o " + out);
        REQUIRE_MESSAGE(r.status == 0, r.output);
        return ink::readPng(out);
    };
    // What the hidden lines add over a drawing without them: the pixels they alone ink, the darkest of those,
    // and the ink added in all (the sum of 255 − red).
    struct Added {
        size_t pixels = 0;
        int darkest = 255;
        long ink = 0;
    };
    auto added = [](const ink::RgbaImage& with, const ink::RgbaImage& without) {
        Added a;
        REQUIRE(with.pixels.size() == without.pixels.size());
        for (size_t i = 0; i < with.pixels.size(); i += 4) {
            a.ink += long(without.pixels[i]) - long(with.pixels[i]);
            if (without.pixels[i] == 255 && with.pixels[i] < 255) {
                ++a.pixels;
                a.darkest = std::min(a.darkest, int(with.pixels[i]));
            }
        }
        return a;
    };
    const ink::RgbaImage none = render("none", "");
    const Added hidden = added(render("hidden", "--hidden-lines"), none);
    const Added big = added(render("big", "--hidden-lines --hidden-dot-size 4"), none);
    const Added black = added(render("black", "--hidden-lines --hidden-opacity 1"), none);
    const ink::RgbaImage clear = render("clear", "--hidden-lines --hidden-opacity 0");
    CAPTURE(hidden.pixels);
    CAPTURE(big.pixels);
    CAPTURE(hidden.ink);
    CAPTURE(black.ink);
    // The default: 1.4 px dots, the ink at 0.45 over white paper: 255 − 0.45 · 255 · c where a share c of a pixel
    // is covered, 140 where it all is. Antialiasing (a GPU's coverage, the supersampling filter) only lightens
    // partly covered pixels, so: never darker than 140 (a higher opacity fails), and somewhere at least half
    // covered (hidden dots missing or a lower opacity fail). 4 px dots and pens cover whole pixels anywhere.
    const auto darkness = [](const Added& a) { return 255 - a.darkest; };  // 0.45 · 255 · c, at most 114.75
    CHECK(hidden.pixels > 50);
    CHECK(darkness(hidden) <= 116);
    CHECK(darkness(hidden) >= 57);
    // 4 px hidden strokes cover far more: measured on lavapipe 621 pixels against 260 (a pixel counts when any of it
    // is inked: a stroke 1.4 px wide touches about 3 pixels across, 4 px about 5 or 6).
    CHECK(2 * big.pixels > 3 * hidden.pixels);
    CHECK(darkness(big) <= 116);
    CHECK(darkness(big) >= 110);
    // Opacity 1: the same dots in the ink itself: the same coverage darkens 1 / 0.45 times as much (and faint
    // antialiased edges that round away at 0.45 may show), 1 / 0.45 times the ink; opacity 0: the paper as it was.
    CHECK(black.pixels >= hidden.pixels);
    CHECK(double(black.pixels) <= 1.1 * double(hidden.pixels));
    CHECK(double(darkness(black)) == doctest::Approx(darkness(hidden) / 0.45).epsilon(0.03));
    CHECK(double(black.ink) / double(hidden.ink) == doctest::Approx(1.0 / 0.45).epsilon(0.1));
    CHECK(clear.pixels == none.pixels);

    // The hidden contours' pen.
    const ink::RgbaImage visible = render("visible", "--style contours");
    const Added thin = added(render("thin", "--style contours --hidden-lines"), visible);
    const Added wide = added(render("wide", "--style contours --hidden-lines --hidden-contour-width 4"), visible);
    CAPTURE(thin.pixels);
    CAPTURE(wide.pixels);
    CHECK(thin.pixels > 30);
    CHECK(wide.pixels > 2 * thin.pixels);
    CHECK(darkness(wide) <= 116);
    CHECK(darkness(wide) >= 110);

    // A preset's keys draw what the options draw.
    std::ofstream(dir / "p.json") << R"({"style": "stipple+contours", "hidden_lines": true, "hidden_dot_size": 4,
                                         "hidden_contour_width": 3, "hidden_opacity": 0.8})";
    const ink::RgbaImage preset = render("preset", "--preset " + (dir / "p.json").string());
    const ink::RgbaImage options = render("options",
                                          "--style stipple+contours --hidden-lines --hidden-dot-size 4 "
                                          "--hidden-contour-width 3 --hidden-opacity 0.8");
    CHECK(preset.pixels == options.pixels);
    // and not the defaults: the larger dots and the wider pen ink pixels the default hidden lines leave white.
    const Added beyond = added(options, render("default", "--style stipple+contours --hidden-lines"));
    CAPTURE(beyond.pixels);
    CHECK(beyond.pixels > 50);
}

TEST_CASE("cli: render refines a level more for an image of 2^21 pixels or more, unless --levels says otherwise" *
          doctest::test_suite("cli")) {
    // A sphere of 200 points (its 200 seeds): the levels `render --stats` reports, by image size and style.
    TempDir tmp;
    std::string xyzn;
    for (int i = 0; i < 200; ++i) {
        const double z = 1 - 2 * (i + 0.5) / 200, r = std::sqrt(1 - z * z), a = i * 2.399963;
        char line[120];
        std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g\n", r * std::cos(a), r * std::sin(a), z,
                      r * std::cos(a), r * std::sin(a), z);
        xyzn += line;
    }
    const std::string model = tmp.write("sphere.xyzn", xyzn);
    const auto levels = [&](const std::string& options) {
        const std::string stats = tmp / "stats.json";
        const Run r = run("render " + model + " --camera 30,20,2 -q -o " + (tmp / "out.png") + " --stats " + stats +
                          " " + options);
        CAPTURE(options);
        CAPTURE(r.output);
        REQUIRE(r.status == 0);
        std::ifstream in(stats);
        const nlohmann::json sets = nlohmann::json::parse(in)["refine"]["sets"];
        REQUIRE(sets.size() == 1);
        return int(sets[0].size()) - 1;  // the seeds' level is the first
    };
    CHECK(levels("--size 1448 1448") == 4);  // 2,096,704 pixels
    CHECK(levels("--size 2048 1024") == 5);
    CHECK(levels("--size 2048 1024 --levels 2") == 2);
    CHECK(levels("--size 2048 1024 --style contours") == 3);
}

TEST_CASE("cli: with the contour drawn by the pen the dots have no outline of their own; without it they do" *
          doctest::test_suite("cli")) {
    // The stats' outline_dots: the silhouette class's dots (|n·v| < τ) drawn. Beside the pen's contour they drew a
    // second outline, a heavy wedge where the band is wide on the screen (lines.md); --tau applies to dots alone.
    TempDir dir;
    const auto outlineDots = [&](const std::string& options) {
        const std::string stats = dir / "stats.json";
        const Run r = run("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 300 --size 256 256 -q -o " +
                          (dir / "out.png") + " --stats " + stats + " " + options);
        CAPTURE(options);
        CAPTURE(r.output);
        REQUIRE(r.status == 0);
        std::ifstream in(stats);
        const nlohmann::json sets = nlohmann::json::parse(in)["stipples"];
        REQUIRE(sets.size() == 1);
        CHECK(sets[0]["front_dots"].get<size_t>() > 500);
        return sets[0]["outline_dots"].get<size_t>();
    };
    CHECK(outlineDots("--style stipple") > 200);
    CHECK(outlineDots("--style contours+stipple") == 0);
    CHECK(outlineDots("--style contours+hatching+stipple --tau 0.3") == 0);
    CHECK(outlineDots("--style hatching+stipple") > 200);
}
