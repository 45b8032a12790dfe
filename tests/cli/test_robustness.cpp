// Bad input, as a user or an attacker hands it over (docs/robustness.md): the fuzzers' regression files
// through the readers, and broken models, unwritable outputs, absurd requests and a missing Vulkan driver
// through every command that reads a model. Each refusal is one line on stderr naming the problem, exit
// status 1, and no output left behind.
#include "base/common.h"
#include "base/files.h"
#include "gpu_fixture.h"
#include "io/hrbf_io.h"
#include "io/points.h"
#include "run_command.h"
#include "temp_dir.h"

#include <doctest/doctest.h>

#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// What a command did, with stdout and stderr apart.
struct Outcome {
    int status;
    std::string out, err;
    std::vector<std::string> errLines() const {
        std::vector<std::string> lines;
        size_t start = 0;
        while (start < err.size()) {
            size_t end = err.find('\n', start);
            if (end == std::string::npos) end = err.size();
            lines.push_back(err.substr(start, end - start));
            start = end + 1;
        }
        return lines;
    }
};

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs inkwell with `args`, stderr into a file of `dir` so that it is kept apart from stdout. `env` goes
// before the command (VAR=value ...).
Outcome run(const TempDir& dir, const std::string& args, const std::string& env = "") {
    std::string errPath = dir / "stderr.txt";
    Run r = runShell(env + " " + INKWELL_BINARY + " " + args + " 2>" + errPath);
    Outcome outcome{r.status, r.output, slurp(errPath)};
    fs::remove(errPath);
    return outcome;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// No file whose name has ".tmp" (writeAtomically's temporary files) anywhere under `dir`.
std::vector<std::string> temporaries(const fs::path& dir) {
    std::vector<std::string> found;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (contains(entry.path().filename().string(), ".tmp")) found.push_back(entry.path().string());
    return found;
}

// The one-line refusal: exit status 1, nothing on stdout, exactly one line on stderr that starts with
// "inkwell: " and contains each of `words`.
void checkRefusal(const Outcome& r, const std::vector<std::string>& words) {
    INFO("stderr: ", r.err);
    CHECK(r.status == 1);
    CHECK(r.out.empty());
    std::vector<std::string> lines = r.errLines();
    CHECK(lines.size() == 1);
    CHECK((!r.err.empty() && r.err.back() == '\n'));
    CHECK(r.err.rfind("inkwell: ", 0) == 0);
    for (const std::string& w : words) CHECK_MESSAGE(contains(r.err, w), "expected: " << w);
}

// ---- Broken models ------------------------------------------------------------------------------------

struct BadModel {
    std::string file;  // name in the temporary directory
    std::string bytes;
    std::string words;  // part of the expected message, after the file name
};

std::string binaryPly(uint64_t vertices, size_t floatsWritten) {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(vertices) +
                    "\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
    for (size_t i = 0; i < floatsWritten; ++i) {
        float v = float(i % 7) - 3.0f;
        s.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    return s;
}

std::vector<BadModel> badModels() {
    std::mt19937 random(12345);
    std::string garbage;
    for (int i = 0; i < 4096; ++i) garbage += char(random() & 0xff);
    garbage[1] = '\0';  // certainly binary
    std::string duplicates;
    for (int i = 0; i < 50; ++i) duplicates += "0.5 -2 3 0 0 1\n";
    return {
        {"empty.obj", "", ": no vertices"},
        {"garbage.obj", garbage, ": line 1: binary data (a NUL byte) in a text file"},
        {"garbage.ply", garbage, ": not a PLY file"},
        {"nan.pts", "0 0 0 0 0 1\n1 0 0 1 0 0\n0 nan 1 0 1 0\n", ": line 3: coordinate is not finite"},
        {"zero-normal.pts", "0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 1 0 1 0\n",
         ": 1 point of 3 has no normal, and 3 points are too few to estimate it from (16 are needed)"},
        {"duplicates.pts", duplicates, ": the points span no volume: all positions coincide"},
        {"huge-box.pts", "1.7e308 0 0 1 0 0\n-1.7e308 0 0 -1 0 0\n0 1 0 0 1 0\n",
         ": the points' bounding box is too large or too small to normalize (diagonal inf)"},
        {"huge-count.ply", binaryPly(4000000000ull, 12),
         ": header line 3: element 'vertex' claims 4000000000 entries; the limit is 100000000"},
        {"truncated.ply", binaryPly(10, 6 * 10 - 3), ": truncated: expected 10 vertices, file ends in vertex 9"},
        {"not-a-number.obj", "v 0 0 0\nv 1 0 0\nv 0 1 O\nf 1 2 3\n", ": line 3: 'O' is not a number"},
        {"bad-index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
         ": line 4: face vertex index 4 is out of range (the file has 3 vertices)"},
        {"bad-index.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
         ": line 13 (face 0): vertex index 3 is out of range (the file has 3 vertices)"},
        {"bad.hrbf", "inkwell-hrbf 1\ncenters 3\nframe 0 0 0 1\nlinear 0 0 0 0\n0 0 0 0 0 1 1 0 0 0\nend\n",
         ": line 6: 'end' after 1 of the 3 centres declared"},
        {"not-hrbf.hrbf", "ply\nformat ascii 1.0\n", ": line 1: not an Inkwell HRBF model"},
    };
}

// `command` has MODEL and OUT in it; `output` is the name OUT stands for in the temporary directory.
void checkRefusesBadModels(const std::string& command, const std::string& output) {
    for (const BadModel& bad : badModels()) {
        TempDir dir;
        std::string model = dir.write(bad.file, bad.bytes);
        std::string args = command;
        args.replace(args.find("MODEL"), 5, model);
        args.replace(args.find("OUT"), 3, dir / output);
        CAPTURE(args);
        Outcome r = run(dir, args);
        checkRefusal(r, {model + bad.words});
        CHECK_FALSE(fs::exists(dir / output));
        CHECK_FALSE(fs::exists(dir / fs::path(output).begin()->string()));  // capture's frames/ of frames/sub
        CHECK(temporaries(dir.path).empty());
    }
}

// Options that keep a command that wrongly succeeded quick.
const char* kSmall = "--levels 1 --size 64 64";

}  // namespace

// ---- The readers on the fuzzers' findings and seeds ----------------------------------------------------

TEST_CASE("robust: every fuzz regression and seed file parses or throws ink::Error naming the file" *
          doctest::test_suite("unit")) {
    size_t files = 0, regressions = 0;
    for (const char* root : {INKWELL_SOURCE_DIR "/tests/regressions", INKWELL_SOURCE_DIR "/fuzz/corpus"}) {
        for (const char* format : {"obj", "ply", "pts", "hrbf"}) {
            fs::path folder = fs::path(root) / format;
            if (!fs::exists(folder)) continue;
            for (const auto& entry : fs::directory_iterator(folder)) {
                std::string bytes = slurp(entry.path().string());
                std::string name = entry.path().filename().string();
                CAPTURE(entry.path().string());
                try {
                    if (std::string(format) == "hrbf")
                        ink::parseHrbf(bytes, name);
                    else
                        ink::parsePoints(bytes, format, name);
                } catch (const ink::Error& e) {
                    std::string message = e.what();
                    CHECK(message.rfind(name + ": ", 0) == 0);  // names the file
                    CHECK(message.find('\n') == std::string::npos);
                } catch (const std::exception& e) {
                    FAIL_CHECK("not an ink::Error: " << e.what());
                }
                ++files;
                if (contains(root, "regressions")) ++regressions;
            }
        }
    }
    CHECK(regressions >= 1);
    CHECK(files >= 20);
}

TEST_CASE("robust: PLY elements without properties cost nothing however many entries they claim (fuzz finding)" *
          doctest::test_suite("unit")) {
    // tests/regressions/ply/elements-without-properties-*.ply: the reader counted through the entries of
    // elements that have nothing to read, 50 × 10⁸ of them in a 1 KiB header, for 13 s. Here two runs of 5,000
    // such elements, one between the vertices and the faces and one after, claim 10¹² entries: a reader that
    // visits entries would take 45 minutes at that rate (CTest's timeout of 300 s fails it); one that skips
    // them reads the real elements, which must come out right.
    auto empties = [](const std::string& prefix) {
        std::string lines;
        for (int i = 0; i < 5'000; ++i) lines += "element " + prefix + std::to_string(i) + " 100000000\n";
        return lines;
    };
    const std::string vertices = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\n";
    std::string ascii = "ply\nformat ascii 1.0\n" + vertices + empties("before") + faces + empties("after") +
                        "end_header\n0 0 0\n1 0 0\n0 1 0\n\n3 0 1 2\n";
    std::string binary = "ply\nformat binary_little_endian 1.0\n" + vertices + empties("before") + faces +
                         empties("after") + "end_header\n";
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) binary.append(reinterpret_cast<const char*>(&v), 4);
    binary += char(3);
    for (int32_t index : {0, 1, 2}) binary.append(reinterpret_cast<const char*>(&index), 4);

    for (const std::string* bytes : {&ascii, &binary}) {
        std::string encoding = bytes == &ascii ? "ascii" : "binary";
        CAPTURE(encoding);
        ink::OrientedPoints p = ink::parsePoints(*bytes, "ply", "empties.ply");
        REQUIRE(p.positions.size() == 3);
        CHECK(p.positions[1] == Eigen::Vector3d(1, 0, 0));
        CHECK(p.positions[2] == Eigen::Vector3d(0, 1, 0));
        // The normals come from the face after the empty elements: the triangle in z = 0, counter-clockwise.
        for (const Eigen::Vector3d& n : p.normals) CHECK(n.isApprox(Eigen::Vector3d(0, 0, 1)));
    }
}

TEST_CASE("robust: tinyobjloader never sees the lines we ignore (fuzz finding: vw weight out of int range)" *
          doctest::test_suite("unit")) {
    // Found by fuzz_obj in a minute: tinyobjloader converted a `vw` weight of 1e3080 (infinity) to int, which
    // is undefined behaviour. Only the v, vn and f lines, checked, reach it now.
    std::string bytes = slurp(INKWELL_SOURCE_DIR "/tests/regressions/obj/tinyobjloader-vw-weight-out-of-int-range.obj");
    const ink::OrientedPoints cloud = ink::parsePoints(bytes, "obj", "t.obj");  // its one v line: a point, no normal
    REQUIRE(cloud.positions.size() == 1);
    CHECK(cloud.normals[0] == Eigen::Vector3d::Zero());
    ink::OrientedPoints p = ink::parsePoints(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 0 0 1e3080\nvt 0 0\nvt 1e999 x\nt crease 2/1/0 1 2 0.5\nl 1 9 2\np -7\n"
        "f 1/1 2/2 3/1\n",
        "obj", "t.obj");
    CHECK(p.positions.size() == 3);
}

// ---- Broken models through each command ----------------------------------------------------------------

TEST_CASE("robust: fit refuses broken models with one line naming the file, exit 1, no output" *
          doctest::test_suite("cli")) {
    checkRefusesBadModels("fit MODEL -o OUT", "out.hrbf");
}

TEST_CASE("robust: sample refuses broken models with one line naming the file, exit 1, no output" *
          doctest::test_suite("cli")) {
    checkRefusesBadModels(std::string("sample MODEL --levels 1 --points OUT"), "out.ply");
}

TEST_CASE("robust: render refuses broken models with one line naming the file, exit 1, no output" *
          doctest::test_suite("cli")) {
    checkRefusesBadModels(std::string("render MODEL ") + kSmall + " -o OUT", "out.png");
}

TEST_CASE("robust: capture refuses broken models with one line naming the file, exit 1, no output" *
          doctest::test_suite("cli")) {
    // The output directory does not exist beforehand and must not be left behind, empty or not.
    checkRefusesBadModels(std::string("capture MODEL --frames 2 ") + kSmall + " -o OUT", "frames/sub");
}

TEST_CASE("robust: bench --model refuses broken models with one line naming the file, exit 1, no output" *
          doctest::test_suite("cli")) {
    checkRefusesBadModels("bench --model MODEL --repeat 1 --frames 1 --json OUT", "out.json");
}

// ---- Outputs that cannot be written ---------------------------------------------------------------------

TEST_CASE("robust: an unwritable output path is refused up front with one line, leaving nothing" *
          doctest::test_suite("cli")) {
    const std::string bunny = INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 50 ";
    TempDir dir;
    dir.write("file", "a regular file, where a directory is expected\n");
    fs::create_directory(dir.path / "read-only");
    fs::permissions(dir.path / "read-only", fs::perms::owner_read | fs::perms::owner_exec);
    // Root ignores permission bits: /proc refuses new files to everyone.
    std::string readOnly = geteuid() == 0 ? "/proc/inkwell-robust" : dir / "read-only/x";

    struct Case {
        std::string args, path, words;
    };
    std::vector<Case> cases;
    for (const std::string& bad : {dir / "missing/x", dir / "file/x", readOnly}) {
        cases.push_back({"fit " + bunny + "-o " + bad + ".hrbf", bad + ".hrbf", "cannot write"});
        cases.push_back({"sample " + bunny + "--levels 1 --points " + bad + ".ply", bad + ".ply", "cannot write"});
        cases.push_back({"render " + bunny + kSmall + " -o " + bad + ".png", bad + ".png", "cannot write"});
        cases.push_back({"render " + bunny + kSmall + " -o " + (dir / "ok.png") + " --stats " + bad + ".json",
                         bad + ".json", "cannot write"});
        cases.push_back(
            {"fit " + bunny + "-o " + (dir / "ok.hrbf") + " --stats " + bad + ".json", bad + ".json", "cannot write"});
    }
    // capture creates a missing directory; a file in the way, or a directory it may not write, is refused.
    cases.push_back({"capture " + bunny + kSmall + " --frames 1 -o " + (dir / "file/frames"), dir / "file/frames",
                     "cannot create directory"});
    cases.push_back({"capture " + bunny + kSmall + " --frames 1 -o " + readOnly, readOnly, "cannot create directory"});
    cases.push_back(
        {"capture " + bunny + kSmall + " --frames 1 -o " + (dir / "cap") + " --stats " + dir / "missing/s.json",
         dir / "missing/s.json", "cannot write"});
    cases.push_back({"render " + bunny + kSmall + " -o " + dir.path.string(), dir.path.string(), "Is a directory"});

    // Up front means before the model is read, so before any fit: with a model that cannot be read in place
    // of the bunny, the refusal is still the output's, not the model's.
    std::string broken = dir.write("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 O\nf 1 2 3\n");
    for (const Case& c : cases) {
        for (const std::string& model : {std::string(INKWELL_SOURCE_DIR "/assets/bunny.obj"), broken}) {
            std::string args = c.args;
            args.replace(args.find(INKWELL_SOURCE_DIR "/assets/bunny.obj"),
                         std::strlen(INKWELL_SOURCE_DIR "/assets/bunny.obj"), model);
            CAPTURE(args);
            Outcome r = run(dir, args);
            checkRefusal(r, {c.words, "'" + c.path + "'"});
            CHECK_FALSE(contains(r.err, "broken.obj"));
            // Nothing was written: neither the unwritable output nor the others of the same command.
            for (const char* other : {"ok.png", "ok.hrbf", "cap", "missing"}) CHECK_FALSE(fs::exists(dir / other));
            CHECK(temporaries(dir.path).empty());
        }
    }
}

TEST_CASE("robust: outputs are checked up front, but capture's stats may go into the directory it creates" *
          doctest::test_suite("cli")) {
    TempDir dir;
    Outcome r = run(dir, "capture " INKWELL_SOURCE_DIR
                         "/assets/bunny.obj --control-points 50 --levels 1 "
                         "--size 64 64 --frames 1 -q -o " +
                             (dir / "new/cap") + " --stats " + (dir / "new/cap/stats.json"));
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(fs::exists(dir / "new/cap/frame_0000.png"));
    CHECK(fs::exists(dir / "new/cap/manifest.json"));
    CHECK(fs::exists(dir / "new/cap/stats.json"));
    CHECK(temporaries(dir.path).empty());
}

// ---- Absurd requests ----------------------------------------------------------------------------------

TEST_CASE("robust: absurd sizes, levels and control point counts are refused up front with the limit" *
          doctest::test_suite("cli")) {
    TempDir dir;
    // Refused before the model is even opened: the model does not exist.
    const std::string missing = dir / "missing.obj";
    struct Case {
        std::string args, message;
    };
    std::vector<Case> cases;
    for (const char* command : {"render", "capture --frames 1", "sample", "fit"}) {
        std::string c = std::string(command) + " " + missing + " ";
        std::string out = std::string(command) == "sample" ? "--points " + (dir / "out") : "-o " + (dir / "out");
        cases.push_back({c + "--control-points 100000 --fit global " + out,
                         "inkwell: --control-points 100000 is more than the global fit can hold (at most 4000: the "
                         "system needs (4m+4)² doubles); the default --fit pu takes any number\n"});
        cases.push_back({c + "--control-points 3000000 " + out,
                         "inkwell: --control-points 3000000 is more than the fit takes (at most 2000000)\n"});
        if (std::string(command) == "fit") continue;
        cases.push_back({c + "--levels 16 " + out, "inkwell: --levels 16 is too many: at most 15 refinement levels\n"});
        cases.push_back({c + "--levels 4294967295 " + out,
                         "inkwell: --levels 4294967295 is too many: at most 15 refinement levels\n"});
        if (std::string(command) == "sample") continue;
        cases.push_back(
            {c + "--size 100000 100000 " + out, "inkwell: --size 100000 100000 is outside 1..8192 pixels a side\n"});
        cases.push_back({c + "--size 0 64 " + out, "inkwell: --size 0 64 is outside 1..8192 pixels a side\n"});
    }
    for (const Case& c : cases) {
        CAPTURE(c.args);
        Outcome r = run(dir, c.args);
        CHECK(r.status == 1);
        CHECK(r.err == c.message);
        CHECK_FALSE(fs::exists(dir / "out"));
    }

    // --levels 14 is within 15 but cannot fit the device: refused once the device's limit is known, before
    // any refinement buffer is made, with both numbers.
    Outcome levels = run(dir, "render " INKWELL_SOURCE_DIR
                              "/assets/bunny.obj --control-points 100 --levels 14 "
                              "-q -o " +
                                  (dir / "out.png"));
    checkRefusal(
        levels, {"the refinement asks for up to ", " points (100 seeds, 14 levels of 4 children, 1 pass), but at most ",
                 " fit: use --levels ", " or fewer, or fewer control points"});
    CHECK_FALSE(fs::exists(dir / "out.png"));
    // With grid seeds the advice is the levels and the grid, never the control points (they do not count).
    Outcome grid = run(dir, "render " INKWELL_SOURCE_DIR
                            "/assets/bunny.obj --control-points 100 --seeds grid --levels 9 "
                            "-q -o " +
                                (dir / "out.png"));
    checkRefusal(grid, {"the refinement asks for up to ", " fit: use --levels ", " or fewer, or a coarser --grid"});
    CHECK_FALSE(fs::exists(dir / "out.png"));

    // 16384² pixels need a 256 MiB splat depth grid. On the device the commands pick, when its storage buffers
    // hold less (lavapipe's 128 MiB): refused once the device is known, before the model is read, instead of a
    // validation error; when they hold that (a GPU's), the missing model is what is refused.
    VkDeviceSize storageRange = 0;
    {
        GpuFixture gpu;  // the default device, as the commands choose it
        storageRange = gpu.ctx.properties.limits.maxStorageBufferRange;
        MESSAGE(gpu.ctx.properties.deviceName << ": storage buffers of " << (storageRange >> 20) << " MiB");
    }
    for (const char* command : {"render", "capture --frames 1"}) {
        Outcome huge =
            run(dir, std::string(command) + " " + missing + " --size 8192 8192 --supersample 2 -o " + (dir / "out"));
        if (storageRange < (VkDeviceSize(256) << 20))
            checkRefusal(huge, {"image size 8192x8192 with 2x supersampling needs a 256 MiB depth grid, more than "
                                "this device's ",
                                " MiB storage buffers: use a smaller size or less supersampling"});
        else
            checkRefusal(huge, {"missing.obj"});
        CHECK_FALSE(fs::exists(dir / "out"));
    }
}

// ---- No Vulkan ----------------------------------------------------------------------------------------

TEST_CASE("robust: without a Vulkan driver the device commands say so in one line" * doctest::test_suite("cli")) {
    TempDir dir;
    const std::string noDriver = "VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json";
    const std::string bunny = INKWELL_SOURCE_DIR "/assets/bunny.obj";
    const std::string expected =
        "inkwell: no Vulkan driver found (VK_ERROR_INCOMPATIBLE_DRIVER): install "
        "mesa-vulkan-drivers for lavapipe, or your GPU's Vulkan driver\n";
    for (const std::string& args :
         {"render " + bunny + " -o " + (dir / "out.png"), "sample " + bunny + " --points " + (dir / "out.ply"),
          "capture " + bunny + " --frames 1 -o " + (dir / "frames"),
          "bench --workload sphere --json " + (dir / "out.json"), std::string("devices")}) {
        CAPTURE(args);
        Outcome r = run(dir, args, noDriver);
        CHECK(r.status == 1);
        CHECK(r.err == expected);
        CHECK(fs::is_empty(dir.path));
    }
    // The CPU backend needs no device.
    Outcome cpu =
        run(dir, "sample " + bunny + " --control-points 30 --levels 1 --backend cpu -q --points " + (dir / "cpu.ply"),
            noDriver);
    CHECK(cpu.status == 0);
    CHECK(cpu.err.empty());
    CHECK(fs::file_size(dir / "cpu.ply") > 100);
}
