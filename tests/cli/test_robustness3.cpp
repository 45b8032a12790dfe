// The third round of hostile inputs and scenarios (issue 29, docs/robustness.md): deep JSON, the .hrbf grid's
// entry count, resources out of proportion to the file, glTF buffers through symbolic links, capture's outputs,
// misleading success and noise. Each class is refused with one line (or bounded), at its root.
#include "../../apps/cli/preset.h"
#include "base/common.h"
#include "base/image.h"
#include "io/hrbf_io.h"
#include "io/points.h"
#include "io/readers.h"
#include "run_command.h"
#include "surface/pu_hrbf.h"
#include "temp_dir.h"
#include "vector/vector.h"

#include "glb_writer.h"

#include <doctest/doctest.h>

#include <unistd.h>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using ink::Error;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The tetrahedron: 4 float positions (48 bytes), then 12 ushort indices (24 bytes).
std::string tetraBuffer() {
    const float v[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    const uint16_t f[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    std::string b;
    for (const auto& p : v)
        for (float c : p) put(b, c);
    for (uint16_t i : f) put(b, i);
    return b;
}

// glTF JSON of the tetrahedron, with `extra` members added at the top level and `uri` for the buffer ("" for
// a .glb's chunk).
std::string tetraJson(const std::string& uri = "", const std::string& extra = "") {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
              {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
"buffers": [{"byteLength": 72)" +
           (uri.empty() ? std::string() : ", \"uri\": \"" + uri + "\"") + "}]" + extra + "}";
}

void refusedGlb(const std::string& json, const std::string& bin, const std::string& message) {
    CHECK_THROWS_WITH_AS(ink::parsePoints(glb(json, bin), "glb", "x.glb"), doctest::Contains(message.c_str()), Error);
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
}

// A version 2 .hrbf of `large` patches of radius 4 at the origin and `tiny` ones of radius 1e-6 (so the median
// radius, and the grid's cell, is tiny), one node each, and two points. Inconsistent (every coefficient is 0),
// but well formed line by line.
std::string gridBomb(size_t large, size_t tiny) {
    std::string s = "inkwell-hrbf 2\npoints 2\nframe 0 0 0 1\ntau 0.5\ncoarse 2\nlinear 0 0 0 0\n";
    s += "0 0 0 1 0 0 0 0 0 0\n0.5 0 0 1 0 0 0 0 0 0\n";
    s += "patches " + std::to_string(large + tiny) + "\n";
    for (size_t i = 0; i < large; ++i) s += "0 0 0 4 0 0 0 0 1\n";
    for (size_t i = 0; i < tiny; ++i) s += "0.5 0.5 0.5 1e-6 0 0 0 0 1\n";
    s += "nodes " + std::to_string(large + tiny) + "\n";
    for (size_t i = 0; i < large + tiny; ++i) s += "0 0 0 0 0 0 0\n";
    s += "0 0 0 1 0 0\n0.5 0 0 1 0 0\nend\n";
    return s;
}

// inkwell with `args`; stderr apart from stdout.
struct Outcome {
    int status;
    std::string out, err;
};
Outcome run(const TempDir& dir, const std::string& args, const std::string& before = "") {
    std::string errPath = dir / "stderr.txt";
    Run r = runShell(before + " " + INKWELL_BINARY + " " + args + " 2>" + errPath);
    Outcome o{r.status, r.output, slurp(errPath)};
    fs::remove(errPath);
    return o;
}

size_t lineCount(const std::string& s) {
    size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

const std::string kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj";
const std::string kCapture = "capture " + kBunny + " --control-points 100 --levels 1 --size 64 64 ";

}  // namespace

// ---- 1. Deep JSON ---------------------------------------------------------------------------------------

TEST_CASE("robust: glTF JSON nested 20,000 deep is refused before any parser recurses (issue 29)" *
          doctest::test_suite("cli")) {
    std::string deep = ", \"extras\": " + std::string(20000, '[') + std::string(20000, ']');
    const std::string message = "glTF JSON: arrays and objects nest more than 64 levels deep";
    refusedGlb(tetraJson("", deep), tetraBuffer(), message);
    CHECK_THROWS_WITH_AS(
        ink::parsePoints(tetraJson("data:application/octet-stream;base64,AAAA", deep), "gltf", "x.gltf"),
        doctest::Contains(message.c_str()), Error);
    // Brackets inside strings are text, and 64 levels of extras are read (and dropped).
    std::string strings = ", \"extras\": {\"a\": \"" + std::string(1000, '[') + "\\\"[\"}";
    CHECK(ink::parsePoints(glb(tetraJson("", strings), tetraBuffer()), "glb", "s.glb").positions.size() == 4);
    std::string nested = ", \"extras\": " + std::string(62, '[') + std::string(62, ']');
    CHECK(ink::parsePoints(glb(tetraJson("", nested), tetraBuffer()), "glb", "n.glb").positions.size() == 4);
}

// ---- 2. The .hrbf grid ----------------------------------------------------------------------------------

TEST_CASE("robust: a .hrbf whose patches would make billions of grid entries is bounded and refused (issue 29)" *
          doctest::test_suite("cli")) {
    // 5,600 large and 5,600 tiny patches: 1.2e10 entries at the median's cell, which wrapped in 32 bits.
    std::string bytes = gridBomb(5600, 5600);
    CHECK_THROWS_WITH_AS(ink::parseHrbf(bytes, "grid.hrbf"), doctest::Contains("grid.hrbf: "), Error);
    // The grid itself: entries within its bound, and every patch still found at its centre.
    std::vector<ink::PuPatch> patches(11200);
    for (size_t i = 0; i < patches.size(); ++i) {
        patches[i].center = i < 5600 ? Eigen::Vector3d::Zero() : Eigen::Vector3d::Constant(0.5);
        patches[i].radius = i < 5600 ? 4 : 1e-6;
    }
    ink::PuGrid grid = ink::buildPuGrid(patches);
    CHECK(grid.cellPatches.size() <= 1024 * patches.size());
    CHECK(grid.cellStart.back() == grid.cellPatches.size());
    int64_t cell = grid.cellOf(Eigen::Vector3d::Constant(0.5));
    REQUIRE(cell >= 0);
    size_t found = grid.cellStart[size_t(cell) + 1] - grid.cellStart[size_t(cell)];
    CHECK(found >= 5601);  // the large patches and the tiny one there
}

TEST_CASE("robust: a patch of more than 1024 nodes is refused on load (issue 29)" * doctest::test_suite("cli")) {
    std::string s =
        "inkwell-hrbf 2\npoints 2\nframe 0 0 0 1\ntau 0.5\ncoarse 2\nlinear 0 0 0 0\n"
        "0 0 0 1 0 0 0 0 0 0\n0.5 0 0 1 0 0 0 0 0 0\npatches 1\n0 0 0 1 0 0 0 0 1025\nnodes 1025\n";
    for (int i = 0; i < 1025; ++i) s += "0 0 0 0 0 0 0\n";
    s += "0 0 0 1 0 0\n0.5 0 0 1 0 0\nend\n";
    CHECK_THROWS_WITH_AS(
        ink::parseHrbf(s, "big.hrbf"),
        "big.hrbf: line 10: '1025' is not a patch's node count (1 to 1024; a fit makes 12 to a few dozen)", Error);
}

TEST_CASE("robust: a .hrbf over the size limit is refused unread, with the limit the documents give (issue 29)" *
          doctest::test_suite("cli")) {
    TempDir dir;
    std::string path = dir / "huge.hrbf";
    { std::ofstream(path) << "inkwell-hrbf 1\n"; }
    fs::resize_file(path, ink::kMaxHrbfBytes + 1);  // sparse: nothing is written
    CHECK_THROWS_WITH_AS(
        ink::loadHrbf(path),
        (path + ": file is larger than 1 GiB, the limit for an HRBF model (docs/hrbf-format.md)").c_str(), Error);
    CHECK(ink::kMaxHrbfBytes == size_t(1) << 30);
    for (const char* doc : {"/docs/hrbf-format.md", "/docs/robustness.md"}) {
        std::string text = slurp(std::string(INKWELL_SOURCE_DIR) + doc);
        CHECK_MESSAGE(!contains(text, "64 MiB"), doc);
        CHECK_MESSAGE(contains(text, "1 GiB"), doc);
    }
}

// ---- 3. Resources out of proportion to the file ----------------------------------------------------------

TEST_CASE("robust: glTF primitives reusing one large index accessor count their indices (issue 29)" *
          doctest::test_suite("cli")) {
    // 2,500 primitives, each the same 60,000 indices: 150 million corners from a file of 200 KB.
    std::string bin;
    for (float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(bin, c);
    for (int i = 0; i < 60000; ++i) put(bin, uint16_t(i % 3));
    std::string prims;
    for (int i = 0; i < 2500; ++i)
        prims += std::string(i ? "," : "") + R"({"attributes": {"POSITION": 0}, "indices": 1})";
    std::string json = R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": [)" + prims + R"(]}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
              {"bufferView": 1, "componentType": 5123, "count": 60000, "type": "SCALAR"}],
"bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 120000}],
"buffers": [{"byteLength": 120036}]})";
    refusedGlb(json, bin, "glTF: the scene instances more than");
}

TEST_CASE("robust: 330,000 empty glTF materials are dropped, 600,000 nodes refused (issue 29)" *
          doctest::test_suite("cli")) {
    std::string materials = ", \"materials\": [{}";
    for (int i = 1; i < 330000; ++i) materials += ",{}";
    materials += "]";
    CHECK(ink::parsePoints(glb(tetraJson("", materials), tetraBuffer()), "glb", "m.glb").positions.size() == 4);
    std::string json = tetraJson();
    json = replaced(
        json, R"("nodes": [{"mesh": 0}])", R"("nodes": [{"mesh": 0})" + [] {
            std::string more;
            for (int i = 0; i < 600000; ++i) more += ",{}";
            return more;
        }() + "]");
    refusedGlb(json, tetraBuffer(),
               "scenes, nodes, meshes, primitives, accessors, buffer views and buffers; the limit is 500000");
}

TEST_CASE("robust: one external glTF buffer file named by two buffers is refused (issue 29)" *
          doctest::test_suite("cli")) {
    TempDir dir;
    std::string bin = tetraBuffer();
    bin += bin;
    dir.write("t.bin", bin);
    std::string json =
        replaced(tetraJson("t.bin"), R"("buffers": [{"byteLength": 72, "uri": "t.bin"}])",
                 R"("buffers": [{"byteLength": 144, "uri": "t.bin"}, {"byteLength": 144, "uri": "./t.bin"}])");
    std::string path = dir.write("two.gltf", json);
    CHECK_THROWS_WITH_AS(ink::loadPoints(path), doctest::Contains("is named by more than one buffer"), Error);
}

TEST_CASE("robust: compare refuses PNGs over 8192^2 pixels from their headers (issue 29)" *
          doctest::test_suite("cli")) {
    // A 1-bit 16384x16384 PNG header (its data is never reached).
    auto header = [](uint32_t w, uint32_t h) {
        std::string s = "\x89PNG\r\n\x1a\n";
        std::string ihdr = "IHDR";
        for (uint32_t v : {w, h})
            for (int k = 3; k >= 0; --k) ihdr += char((v >> (8 * k)) & 0xff);
        ihdr += std::string("\x01\x00\x00\x00\x00", 5);
        for (int k = 3; k >= 0; --k) s += char((13u >> (8 * k)) & 0xff);
        s += ihdr + std::string(4, '\0');  // the CRC, unchecked by the header reader
        return s + std::string(300000, '\0');
    };
    CHECK_THROWS_WITH_AS(ink::readPngFromMemory(header(16384, 16384), "big.png"),
                         doctest::Contains("16384x16384 pixels is over the limit"), Error);
    CHECK(ink::kMaxImagePixels == uint64_t(8192) * 8192);
}

// ---- 4. glTF buffers through symbolic links ------------------------------------------------------------

TEST_CASE(
    "robust: a glTF buffer that is a link, or behind a linked directory, to a file outside is refused (issue 29)" *
    doctest::test_suite("cli")) {
    TempDir dir;
    fs::create_directories(dir.path / "outside");
    fs::create_directories(dir.path / "model");
    dir.write("outside/secret.bin", tetraBuffer());
    fs::create_symlink(dir.path / "outside/secret.bin", dir.path / "model/t.bin");
    fs::create_directory_symlink(dir.path / "outside", dir.path / "model/linked");
    std::string viaFile = dir.write("model/a.gltf", tetraJson("t.bin"));
    std::string viaDir = dir.write("model/b.gltf", tetraJson("linked/secret.bin"));
    for (const std::string& path : {viaFile, viaDir})
        CHECK_THROWS_WITH_AS(ink::loadPoints(path),
                             doctest::Contains("is outside the glTF file's directory once symbolic links are resolved"),
                             Error);
    // A link within the directory, and a model reached through a linked directory, are read.
    dir.write("model/real.bin", tetraBuffer());
    fs::create_symlink("real.bin", dir.path / "model/inside.bin");
    CHECK(ink::loadPoints(dir.write("model/c.gltf", tetraJson("inside.bin"))).positions.size() == 4);
    fs::create_directory_symlink(dir.path / "model", dir.path / "alias");
    CHECK(ink::loadPoints(dir / "alias/c.gltf").positions.size() == 4);
    // And from the command line: one line, exit 1, nothing written.
    Outcome r = run(dir, "fit " + viaFile + " -o " + dir / "out.hrbf");
    CHECK(r.status == 1);
    CHECK(lineCount(r.err) == 1);
    CHECK(contains(r.err, "outside the glTF file's directory"));
    CHECK(!fs::exists(dir / "out.hrbf"));
}

// ---- 5. Capture's outputs --------------------------------------------------------------------------------

TEST_CASE(
    "robust: capture never writes through a frame that is a link to its input, nor over a frame with --stats (issue "
    "29)" *
    doctest::test_suite("cli")) {
    TempDir dir;
    std::string model = dir.write("bunny.obj", slurp(kBunny));
    fs::create_directories(dir.path / "cap");
    fs::create_symlink(model, dir.path / "cap/frame_0001.png");
    Outcome r =
        run(dir, "capture " + model + " --control-points 100 --levels 1 --size 64 64 --frames 2 -o " + dir / "cap");
    CHECK(r.status == 1);
    CHECK(lineCount(r.err) == 1);
    CHECK(contains(r.err, "frame_0001.png': it is also an input of this command"));
    CHECK(slurp(model) == slurp(kBunny));
    CHECK(!fs::exists(dir / "cap/manifest.json"));

    r = run(dir, kCapture + "--frames 2 -o " + dir / "c2" + " --stats " + dir / "c2/frame_0001.png");
    CHECK(r.status == 1);
    CHECK(lineCount(r.err) == 1);
    CHECK(contains(r.err, "it is also frame 1 of the capture"));
    CHECK(!fs::exists(dir / "c2"));
}

TEST_CASE("robust: a failing re-capture leaves the old capture, a shorter one removes its stale frames (issue 29)" *
          doctest::test_suite("cli")) {
    TempDir dir;
    std::string cap = dir / "cap";
    REQUIRE(run(dir, kCapture + "--frames 3 -o " + cap).status == 0);
    std::string manifest = slurp(cap + "/manifest.json"), frame = slurp(cap + "/frame_0001.png");
    REQUIRE(!manifest.empty());
    dir.write("cap/notes.txt", "mine\n");
    dir.write("cap/frame_0007.png", "not the manifest's\n");

    // Every byte written to a file fails (EFBIG: a file size limit of 0, its signal ignored; stderr is a pipe)
    // once the first frame is drawn: the old manifest and frames stay as they were, and nothing of the new
    // capture is left.
    Run r = runShell("trap '' XFSZ; ulimit -f 0; " + std::string(INKWELL_BINARY) + " -q " + kCapture +
                     "--frames 2 --orbit 90 -o " + cap + " 2>&1");
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(r.output == "inkwell: cannot write '" + cap + "/frame_0000.png': File too large\n");
    CHECK(slurp(cap + "/manifest.json") == manifest);
    CHECK(slurp(cap + "/frame_0001.png") == frame);
    CHECK(fs::exists(cap + "/frame_0002.png"));
    for (const auto& entry : fs::directory_iterator(cap))
        CHECK_MESSAGE(entry.path().filename().string().rfind(".inkwell", 0) != 0, entry.path().string());

    // Two frames now: frame_0002 of the old manifest goes; what no manifest named stays.
    REQUIRE(run(dir, kCapture + "--frames 2 --orbit 90 -o " + cap).status == 0);
    CHECK(fs::exists(cap + "/frame_0000.png"));
    CHECK(fs::exists(cap + "/frame_0001.png"));
    CHECK(!fs::exists(cap + "/frame_0002.png"));
    CHECK(slurp(cap + "/notes.txt") == "mine\n");
    CHECK(fs::exists(cap + "/frame_0007.png"));
    CHECK(slurp(cap + "/manifest.json") != manifest);
    CHECK(slurp(cap + "/frame_0001.png") != frame);  // another azimuth
}

// ---- 6. Misleading success -------------------------------------------------------------------------------

TEST_CASE("robust: a page with no room for the pen, and a pen under a micrometre, are refused (issue 29)" *
          doctest::test_suite("cli")) {
    ink::VectorDrawing d;
    d.width = 200;
    d.height = 100;
    d.layer("stipple", {0, 0, 0, 1}).dots = {{{100, 50}, 4.0f}};
    ink::PageOptions o;
    o.width = o.height = 100;
    o.margin = 49.8;  // 0.4 mm of room; the wide view is 0.4 x 0.2 mm, under the 0.3 mm pen
    CHECK_THROWS_WITH_AS(ink::layoutPlot(d, o), doctest::Contains("leave no room for a 0.3 mm pen"), Error);
    o.margin = 10;
    o.penWidth = 0.0004;
    CHECK_THROWS_WITH_AS(ink::layoutPlot(d, o), "the pen width 0.0004 mm is not in [0.001, 10] mm", Error);
    o.penWidth = ink::kMinPenWidth;  // the thinnest pen is written as itself, not as 0
    ink::Plot plot = ink::layoutPlot(d, o);
    CHECK(plot.penWidth == ink::kMinPenWidth);
    CHECK(contains(ink::plotSvg(plot), "stroke-width=\"0.001\""));
}

TEST_CASE(
    "robust: glTF indices beyond 2^31, to missing objects, and negative offsets are refused, not truncated (issue "
    "29)" *
    doctest::test_suite("cli")) {
    std::string json = tetraJson();
    std::string bin = tetraBuffer();
    refusedGlb(replaced(json, R"("bufferView": 0, "componentType": 5126)",
                        R"("bufferView": 4294967296, "componentType": 5126)"),
               bin,
               "glTF: accessors[0].bufferView is 4294967296, not an index, count or size (an integer 0 to 2147483647)");
    refusedGlb(replaced(json, R"("indices": 1)", R"("indices": 4294967297)"), bin,
               "meshes[0].primitives[0].indices is 4294967297");
    refusedGlb(replaced(json, R"("nodes": [{"mesh": 0}])", R"("nodes": [{"mesh": 1099511627776}])"), bin,
               "nodes[0].mesh is 1099511627776");
    refusedGlb(replaced(json, R"("byteOffset": 48)", R"("byteOffset": -48)"), bin, "bufferViews[1].byteOffset is -48");
    refusedGlb(replaced(json, R"("POSITION": 0)", R"("POSITION": 2147483648)"), bin,
               "meshes[0].primitives[0].attributes.POSITION is 2147483648");
    refusedGlb(replaced(json, R"("nodes": [0])", R"("nodes": [0.5])"), bin, "scenes[0].nodes[0] is 0.5");
    // An index must name an object the file has, also one Inkwell does not read (a material, a camera).
    refusedGlb(replaced(json, R"("indices": 1)", R"("indices": 1, "material": 3)"), bin,
               "glTF: meshes[0].primitives[0].material is 3, but the file has 0 materials");
    refusedGlb(replaced(json, R"("nodes": [{"mesh": 0}])", R"("nodes": [{"mesh": 0, "camera": 0}])"), bin,
               "glTF: nodes[0].camera is 0, but the file has 0 cameras");
    refusedGlb(replaced(json, R"("POSITION": 0)", R"("POSITION": 0, "NORMAL": 7)"), bin,
               "glTF: meshes[0].primitives[0].attributes.NORMAL is 7, but the file has 2 accessors");
    CHECK(ink::parsePoints(glb(replaced(replaced(json, R"("indices": 1)", R"("indices": 1, "material": 0)"),
                                        R"("buffers": [)", R"("materials": [{}], "buffers": [)"),
                               bin),
                           "glb", "material.glb")
              .positions.size() == 4);
    // Numbers that are not indices are not checked: a matrix, min and max.
    CHECK(ink::parsePoints(glb(replaced(json, R"("nodes": [{"mesh": 0}])",
                                        R"("nodes": [{"mesh": 0, "translation": [-1.5, 3e9, 0]}])"),
                               bin),
                           "glb", "ok.glb")
              .positions.size() == 4);
}

// ---- 7. Noise ---------------------------------------------------------------------------------------------

TEST_CASE("robust: 10,000 unknown PLY header lines make 4 notes, not 10,000 (issue 29)" * doctest::test_suite("cli")) {
    std::string ply = "ply\nformat ascii 1.0\n";
    for (int i = 0; i < 10000; ++i) ply += "Created by SomeScanner " + std::to_string(i) + "\n";
    ply +=
        "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n"
        "property float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n";
    std::vector<std::string> notes;
    ink::Reporter reporter{[&notes](const std::string& line) { notes.push_back(line); }, nullptr};
    ink::ScopedReporter reporting(reporter);
    CHECK(ink::parsePoints(ply, "ply", "w.ply").positions.size() == 1);
    REQUIRE(notes.size() == 4);
    CHECK(contains(notes[0], "w.ply: header line 3: ignored the unknown header line 'Created by SomeScanner 0'"));
    CHECK(notes[3] == "w.ply: and 9997 more unknown header lines ignored");
}

TEST_CASE("robust: a preset's invalid UTF-8 byte is escaped in its message, never echoed (issue 29)" *
          doctest::test_suite("cli")) {
    std::string bytes = "{\"style\": \"\xff\"}";
    std::string message;
    try {
        app::parsePreset(bytes, "p.json");
    } catch (const Error& e) {
        message = e.what();
    }
    REQUIRE(!message.empty());
    CHECK(message.find('\xff') == std::string::npos);
    CHECK(contains(message, "\\xff"));
    CHECK(ink::escapeText("caf\xc3\xa9 \xff\x01") == "caf\xc3\xa9 \\xff\\x01");  // valid UTF-8 stays
    // From the command line: the one line on stderr is valid text.
    TempDir dir;
    std::string preset = dir.write("p.json", bytes);
    Outcome r = run(dir, "render " + kBunny + " --preset " + preset + " -o " + dir / "x.png");
    CHECK(r.status == 1);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err.find('\xff') == std::string::npos);
}
