// `inkwell view` as a user meets it, in a virtual X server (xvfb-run): it draws, saves what it drew, stays
// clean under validation, takes settings from its panel (driven with xdotool), and says so in one line when there
// is no display.
#include "base/image.h"

#include "run_command.h"
#include "skip.h"
#include "temp_dir.h"

#include <doctest/doctest.h>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

Run shell(const std::string& command) { return runShell(command + " 2>&1"); }

// The viewer in a fresh virtual screen larger than its default 1024×768 window. Each test searches for a
// free display from its own number, so that tests run in parallel (ctest -j) do not race for the same one.
Run view(const std::string& args, int firstDisplay) {
    return shell("xvfb-run -a -n " + std::to_string(firstDisplay) + " -s \"-screen 0 1280x1024x24\" " +
                 INKWELL_BINARY " view " + args);
}

// The virtual screen and the input driver the viewer tests use come with scripts/install-deps.sh (xvfb, xauth,
// xdotool). Where one is missing (a machine set up otherwise, as the lent GPU machines are), the test says so and
// counts as skipped (tests/support/skip.h); true then, and the test returns.
bool skipWithoutTools(bool xdotool) {
    std::string missing;
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) missing += " xvfb-run";
    if (xdotool && std::system("command -v xdotool > /dev/null 2>&1") != 0) missing += " xdotool";
    if (missing.empty()) return false;
    skipTest("not installed:" + missing + " (scripts/install-deps.sh installs xvfb, xauth and xdotool)");
    return true;
}

// A file in this process's own temporary directory (removed at exit): tests run in parallel.
std::string tempPng(const char* name) {
    static TempDir dir("inkwell-viewer");
    return dir / name;
}

const char* kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 150 --levels 2";

struct Ink {
    size_t paper = 0, dark = 0, darkInMiddle = 0;
    double centreX = 0, centreY = 0;  // of the dark pixels, as fractions of the image
};

// Paper is near white; ink is dark. The middle is the central 90% of each side (the first picture fills 85%).
Ink countInk(const ink::RgbaImage& image) {
    Ink ink;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const uint8_t* p = &image.pixels[(size_t(y) * image.width + x) * 4];
            int luminance = (p[0] + p[1] + p[2]) / 3;
            if (luminance >= 245) ++ink.paper;
            if (luminance >= 128) continue;
            ++ink.dark;
            ink.centreX += double(x) / image.width;
            ink.centreY += double(y) / image.height;
            if (x > image.width * 5 / 100 && x < image.width * 95 / 100 && y > image.height * 5 / 100 &&
                y < image.height * 95 / 100)
                ++ink.darkInMiddle;
        }
    if (ink.dark) {
        ink.centreX /= double(ink.dark);
        ink.centreY /= double(ink.dark);
    }
    return ink;
}

}  // namespace

TEST_CASE("viewer: five validated frames of the bunny, the last saved as a framed drawing" *
          doctest::test_suite("viewer")) {
    if (skipWithoutTools(false)) return;
    std::string shot = tempPng("inkwell-viewer-bunny.png");
    Run r = view(std::string(kBunny) + " --frames 5 --screenshot " + shot + " --validation", 140);
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("validation error") == std::string::npos);  // the panel drawn too
    CHECK(r.output.find("view: 5 frames, median ") != std::string::npos);
    CHECK(r.output.find("(1024x768 with the panel, ") != std::string::npos);

    ink::RgbaImage image = ink::readPng(shot);
    CHECK(image.width == 1024 - 320);  // the default window, less the panel: the drawing alone is saved
    CHECK(image.height == 768);
    Ink ink = countInk(image);
    size_t pixels = size_t(image.width) * image.height;
    CHECK(ink.paper > pixels * 9 / 10);
    CHECK(ink.dark >= 300);
    CHECK(ink.darkInMiddle >= ink.dark * 95 / 100);
    CHECK(ink.centreX == doctest::Approx(0.5).epsilon(0.3));
    CHECK(ink.centreY == doctest::Approx(0.5).epsilon(0.3));
}

TEST_CASE("viewer: --size sets the window, and the window shows what render draws, colours included" *
          doctest::test_suite("viewer")) {
    if (skipWithoutTools(false)) return;
    // A coloured ink catches a swapchain in BGRA order saved without swizzling; one sample per pixel in both.
    std::string shot = tempPng("inkwell-viewer-size.png"), offscreen = tempPng("inkwell-viewer-render.png");
    std::string style = std::string(kBunny) + " --size 640 480 --ink '#c03020'";
    Run r = view(style + " --frames 2 --no-panel --screenshot " + shot, 160);
    INFO(r.output);
    REQUIRE(r.status == 0);
    Run rendered = shell(INKWELL_BINARY " render " + style + " --supersample 1 -o " + offscreen);
    REQUIRE(rendered.status == 0);

    ink::RgbaImage a = ink::readPng(shot), b = ink::readPng(offscreen);
    REQUIRE(a.width == 640);
    REQUIRE(a.height == 480);
    REQUIRE(b.width == a.width);
    REQUIRE(b.height == a.height);
    size_t inked = 0, reddish = 0, different = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4) {
        const uint8_t* p = &a.pixels[i];
        if (p[0] < 245 || p[1] < 245 || p[2] < 245) {
            ++inked;
            if (p[0] > p[2] + 20) ++reddish;
        }
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(p[c]) - int(b.pixels[i + c])) > 8) {
                ++different;
                break;
            }
    }
    CHECK(inked >= 300);
    CHECK(reddish >= inked * 9 / 10);
    CHECK(different <= inked / 20);  // the same renderer, camera and style: at most a few edge pixels differ
}

TEST_CASE("viewer: --vector saves the window's marks as an SVG that draws as its screenshot" *
          doctest::test_suite("viewer")) {
    if (skipWithoutTools(false)) return;
    // A page of the window's shape without margins, at 2 pixels a millimetre: drawn at the window's size by
    // rsvg-convert, the SVG is the screenshot (the same frame) after a 1-pixel blur.
    std::string shot = tempPng("inkwell-viewer-vector.png"), svg = tempPng("inkwell-viewer-vector.svg");
    std::string drawn = tempPng("inkwell-viewer-vector-svg.png");
    Run r = view(std::string(kBunny) + " --size 400 300 --no-panel --frames 3 --screenshot " + shot + " --vector " +
                     svg + " --page 200x150mm --margin 0 --pen-width 0.5 --validation",
                 180);
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("view: saved " + svg) != std::string::npos);
    REQUIRE(shell("rsvg-convert -w 400 -h 300 -b white -o " + drawn + " " + svg).status == 0);
    ink::RgbaImage a = ink::readPng(shot), b = ink::readPng(drawn);
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    auto blurred = [](const ink::RgbaImage& im) {
        std::vector<float> l(size_t(im.width) * im.height), out(l.size());
        for (size_t i = 0; i < l.size(); ++i)
            l[i] = (float(im.pixels[4 * i]) + float(im.pixels[4 * i + 1]) + float(im.pixels[4 * i + 2])) / 3.0f;
        for (int y = 0; y < int(im.height); ++y)
            for (int x = 0; x < int(im.width); ++x) {
                float sum = 0;
                int n = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        if (x + dx >= 0 && y + dy >= 0 && x + dx < int(im.width) && y + dy < int(im.height)) {
                            sum += l[size_t(y + dy) * im.width + size_t(x + dx)];
                            ++n;
                        }
                out[size_t(y) * im.width + size_t(x)] = sum / float(n);
            }
        return out;
    };
    std::vector<float> la = blurred(a), lb = blurred(b);
    size_t differ = 0;
    for (size_t i = 0; i < la.size(); ++i) differ += std::abs(la[i] - lb[i]) > 64.0f;
    CHECK(countInk(a).dark >= 300);
    CHECK(countInk(b).dark >= countInk(a).dark / 2);
    CHECK(double(differ) / double(la.size()) <= 0.02);
}

// Whether every pixel is the paper (white) or the ink colour: nothing of the panel's greys and blues.
bool onlyPaperAndInk(const ink::RgbaImage& image, std::array<int, 3> inkColour) {
    for (size_t i = 0; i < image.pixels.size(); i += 4) {
        const uint8_t* p = &image.pixels[i];
        bool paper = p[0] == 255 && p[1] == 255 && p[2] == 255;
        bool inked = std::abs(p[0] - inkColour[0]) <= 2 && std::abs(p[1] - inkColour[1]) <= 2 &&
                     std::abs(p[2] - inkColour[2]) <= 2;
        if (!paper && !inked) return false;
    }
    return true;
}

size_t inkedPixels(const ink::RgbaImage& image) {
    size_t n = 0;
    for (size_t i = 0; i < image.pixels.size(); i += 4)
        if (image.pixels[i] < 245 || image.pixels[i + 1] < 245 || image.pixels[i + 2] < 245) ++n;
    return n;
}

// Runs `inkwell view VIEW_ARGS --validation` under Xvfb in `dir` and drives it with xdotool: STEPS is bash with
// hold KEY (held half a second: ImGui 1.86 sees a key that is down when a frame starts), at X Y (the pointer to
// window coordinates) and await TEXT (until the log shows it) defined; q then ends the viewer. Returns the
// viewer's log (stdout and stderr) with "exit N" appended; the driver's own status and output go into `driver`.
std::string driveViewer(TempDir& dir, const std::string& viewArgs, int display, const std::string& steps, Run& driver) {
    std::string script = R"(set -u
cd '{dir}'
timeout 150 {inkwell} view {args} --validation > log.txt 2>&1 &
pid=$!
wid=$(timeout 60 xdotool search --sync --onlyvisible --name 'inkwell view')
timeout 60 xdotool search --sync --onlyvisible --name ' ms$' > /dev/null
xdotool windowfocus --sync $wid
hold() { xdotool keydown $1; sleep 0.5; xdotool keyup $1; sleep 0.5; }
at() { xdotool mousemove --window $wid $1 $2; sleep 0.5; }
await() { for i in $(seq 300); do grep -q "$1" log.txt && return; sleep 0.2; done; echo "no '$1'" >> log.txt; }
{steps}
hold q
wait $pid; echo "exit $?" >> log.txt
)";
    auto replace = [&script](const std::string& token, const std::string& value) {
        script.replace(script.find(token), token.size(), value);
    };
    replace("{dir}", dir.path.string());
    replace("{inkwell}", INKWELL_BINARY);
    replace("{args}", viewArgs);
    replace("{steps}", steps);
    dir.write("drive.sh", script);
    driver = shell("xvfb-run -a -n " + std::to_string(display) + " -s \"-screen 0 1280x1024x24\" bash '" +
                   (dir / "drive.sh") + "'");
    return runShell("cat '" + (dir / "log.txt") + "'").output;
}

TEST_CASE("viewer: settings typed into the panel show in its saved PNG and the screenshot, the panel never does" *
          doctest::test_suite("viewer")) {
    if (skipWithoutTools(true)) return;
    TempDir dir("inkwell-viewer-panel");
    // The panel's layout in the default 1024 x 768 window (the screenshot in docs/viewer.md): window coordinates
    // of the dot size slider, the ink's hex field and the "save PNG" and "SVG" buttons.
    Run r;
    const std::string log = driveViewer(dir, std::string(kBunny) + " --screenshot shot.png", 200, R"(
# dot size 6: ctrl + click on the slider to type a value
at 800 268; xdotool keydown ctrl; sleep 0.5; xdotool click 1; sleep 0.5; xdotool keyup ctrl; sleep 0.5
xdotool type --delay 100 6; hold Return
# ink #c03020: into the hex field, all of it replaced
at 780 408; xdotool click 1; sleep 0.5; hold ctrl+a; xdotool type --delay 100 C03020; hold Return
# save PNG, then SVG
at 743 668; xdotool click 1; await 'saved inkwell-drawing-1.png'
at 798 668; xdotool click 1; await 'saved inkwell-drawing-1.svg'
# + over the drawing: a level more, refined on the worker thread
at 300 300; hold plus; await 'refined stipple at 3 levels')",
                                        r);
    INFO(r.output);
    INFO(log);
    REQUIRE(r.status == 0);
    CHECK(log.find("validation error") == std::string::npos);
    CHECK(log.find("view: saved inkwell-drawing-1.png\n") != std::string::npos);
    CHECK(log.find("view: saved inkwell-drawing-1.svg\n") != std::string::npos);
    CHECK(log.find("view: refined stipple at 3 levels in ") != std::string::npos);
    CHECK(log.find("view: saved shot.png\n") != std::string::npos);
    CHECK(log.find("exit 0") != std::string::npos);

    // The panel's "save PNG": what `render` draws with the settings typed in, at the drawing's size.
    const std::string render = INKWELL_BINARY " render " + std::string(kBunny) + " --size 704 768 -o ";
    REQUIRE(shell(render + dir / "typed.png --ink '#c03020' --dot-size 6").status == 0);
    REQUIRE(shell(render + dir / "default.png").status == 0);
    ink::RgbaImage saved = ink::readPng(dir / "inkwell-drawing-1.png");
    ink::RgbaImage typed = ink::readPng(dir / "typed.png"), plain = ink::readPng(dir / "default.png");
    REQUIRE(saved.width == 704);
    REQUIRE(saved.height == 768);
    size_t inked = inkedPixels(saved), reddish = 0, different = 0;
    for (size_t i = 0; i < saved.pixels.size(); i += 4) {
        const uint8_t* p = &saved.pixels[i];
        if ((p[0] < 245 || p[1] < 245 || p[2] < 245) && p[0] > p[2] + 20) ++reddish;
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(p[c]) - int(typed.pixels[i + c])) > 8) {
                ++different;
                break;
            }
    }
    CHECK(reddish >= inked * 9 / 10);
    CHECK(different <= inked / 20);
    // Dots of 6 pixels, not 2 (the silhouettes' strokes keep their width): measured 24,461 inked pixels against 4,259.
    CHECK(2 * inked >= 5 * inkedPixels(plain));

    // The panel's SVG: the same view's marks on a page, one layer in the typed ink.
    std::string svg = runShell("cat '" + (dir / "inkwell-drawing-1.svg") + "'").output;
    CHECK(svg.find("<svg") != std::string::npos);
    CHECK(svg.find("stroke=\"#c03020\"") != std::string::npos);
    size_t paths = 0;
    for (size_t at = svg.find("<path d=\"M"); at != std::string::npos; at = svg.find("<path d=\"M", at + 1)) ++paths;
    CHECK(paths >= 50);  // a path a dot (circles as two arcs)

    // The window's screenshot at quit: the drawing (3 levels now) in the typed ink, without the panel.
    ink::RgbaImage shot = ink::readPng(dir / "shot.png");
    CHECK(shot.width == 704);
    CHECK(shot.height == 768);
    CHECK(onlyPaperAndInk(shot, {0xc0, 0x30, 0x20}));
    CHECK(inkedPixels(shot) > inked);  // more stipples at 3 levels than at 2, as large
}

// Pixels that differ by more than 8 in a channel.
size_t differentPixels(const ink::RgbaImage& a, const ink::RgbaImage& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4)
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c])) > 8) {
                ++n;
                break;
            }
    return n;
}

TEST_CASE("viewer: the camera copied and pasted through the clipboard, and pen lines ticked in the panel" *
          doctest::test_suite("viewer")) {
    if (skipWithoutTools(true)) return;
    TempDir dir("inkwell-viewer-camera");
    // Window coordinates in the default 1024 x 768 window (docs/viewer.md's first screenshot): the "contours" and
    // "hatching" checkboxes, the file field, the "copy camera" and "paste camera" buttons. S saves the drawing as
    // inkwell-view-N.png.
    Run r;
    const std::string log = driveViewer(dir, std::string(kBunny) + " --camera 120 30 1.3", 220, R"(
# A file name on the clipboard (copied out of the file field): "paste camera" refuses it
at 780 628; xdotool click 1; sleep 0.5; hold ctrl+a; hold ctrl+c; hold Return
at 850 588; xdotool click 1; await 'camera not pasted'
# "copy camera", then orbit by dragging over the drawing, and save that view
at 755 588; xdotool click 1; await 'copied the camera'
at 300 300; xdotool mousedown 1; sleep 0.3
for x in 330 360 390 420; do xdotool mousemove --window $wid $x 340; sleep 0.2; done
xdotool mouseup 1; sleep 0.5
hold s; await 'saved inkwell-view-1.png'
# ctrl + V over the drawing: the copied camera again
at 300 300; hold ctrl+v; await 'pasted the camera'
hold s; await 'saved inkwell-view-2.png'
# contours, then hatching: new lines on the worker thread
at 722 108; xdotool click 1; await 'pen lines: contours'
at 805 108; xdotool click 1; await 'hatching traced'
at 300 300; sleep 1; hold s; await 'saved inkwell-view-3.png')",
                                        r);
    INFO(r.output);
    INFO(log);
    REQUIRE(r.status == 0);
    CHECK(log.find("validation error") == std::string::npos);
    CHECK(log.find("note: camera not pasted: not a camera: expected a JSON object or --camera AZ EL DIST [--up "
                   "AXIS], not 'inkwell-drawing-1.png'") != std::string::npos);
    CHECK(log.find("view: copied the camera {\"azimuth_deg\":120.0,\"elevation_deg\":30.0,\"distance\":1.3,"
                   "\"target\":[0.0,0.0,0.0],\"up\":\"y\",\"fov_deg\":40.0,\"free_orbit\":false}\n") !=
          std::string::npos);
    CHECK(log.find("view: pasted the camera\n") != std::string::npos);
    CHECK(log.find("view: pen lines: contours\n") != std::string::npos);
    CHECK(log.find("view: hatching traced in ") != std::string::npos);
    CHECK(log.find("exit 0") != std::string::npos);

    // What render draws from the copied camera, with the stipples and then with the pen lines too.
    const std::string render =
        INKWELL_BINARY " render " + std::string(kBunny) + " --camera 120 30 1.3 --size 704 768 --supersample 1 -o ";
    REQUIRE(shell(render + dir / "copied.png").status == 0);
    REQUIRE(shell(render + dir / "lines.png --style stipple+contours+hatching").status == 0);
    ink::RgbaImage orbited = ink::readPng(dir / "inkwell-view-1.png");
    ink::RgbaImage pasted = ink::readPng(dir / "inkwell-view-2.png");
    ink::RgbaImage lined = ink::readPng(dir / "inkwell-view-3.png");
    ink::RgbaImage copied = ink::readPng(dir / "copied.png"), lines = ink::readPng(dir / "lines.png");
    for (const ink::RgbaImage* image : {&orbited, &pasted, &lined, &copied, &lines}) {
        REQUIRE(image->width == 704);
        REQUIRE(image->height == 768);
    }
    // The drag moved the camera away from the copied one; the paste brought it back.
    CHECK(differentPixels(orbited, copied) > inkedPixels(copied) / 2);
    CHECK(differentPixels(pasted, copied) <= inkedPixels(copied) / 20);
    // The pen lines ticked in the panel are render's --style stipple+contours+hatching.
    CHECK(inkedPixels(lined) > inkedPixels(pasted) * 5 / 4);
    CHECK(differentPixels(lined, lines) <= inkedPixels(lines) / 20);
}

TEST_CASE("viewer: without a display it says so in one line and exits 1" * doctest::test_suite("viewer")) {
    Run r = shell("env -u DISPLAY -u WAYLAND_DISPLAY " INKWELL_BINARY " view " INKWELL_SOURCE_DIR "/assets/bunny.obj");
    CHECK(r.status == 1);
    CHECK(r.output ==
          "inkwell: cannot open a window: no display (set DISPLAY, or run under xvfb-run); "
          "use 'inkwell render' for headless output\n");
}

TEST_CASE("viewer: opens on the chosen view, R returns to it after an orbit, and U to it through the up axes" *
          doctest::test_suite("viewer")) {
    if (skipWithoutTools(true)) return;
    TempDir dir("inkwell-viewer-reset");
    // Orbit by dragging over the drawing, R, then "copy camera" (window coordinates as in the copy and paste test);
    // then orbit again and press U six times: through the five other up axes and back to auto (the bunny's y),
    // which returns to its first picture; "copy camera" again.
    Run r;
    const std::string log = driveViewer(dir, kBunny, 230, R"SH(
at 300 300; xdotool mousedown 1; sleep 0.3
for x in 330 360 390 420; do xdotool mousemove --window $wid $x 340; sleep 0.2; done
xdotool mouseup 1; sleep 0.5
at 300 300; hold r
at 755 588; xdotool click 1; await 'copied the camera'
at 300 300; xdotool mousedown 1; sleep 0.3
for x in 330 360 390; do xdotool mousemove --window $wid $x 340; sleep 0.2; done
xdotool mouseup 1; sleep 0.5
for k in 1 2 3 4 5 6; do at 300 300; hold u; done
at 755 588; xdotool click 1
for i in $(seq 150); do [ "$(grep -c 'copied the camera' log.txt)" -ge 2 ] && break; sleep 0.2; done)SH",
                                        r);
    INFO(r.output);
    INFO(log);
    REQUIRE(r.status == 0);
    // The note says what was chosen; the copied camera after R is that view.
    const size_t note = log.find("view azimuth ");
    REQUIRE(note != std::string::npos);
    float azimuth = 0, elevation = 0, distance = 0;
    REQUIRE(std::sscanf(log.c_str() + note, "view azimuth %f, elevation %f degrees, distance %f", &azimuth, &elevation,
                        &distance) == 3);
    CHECK(elevation >= 15.0f);
    CHECK(elevation <= 30.0f);
    char expected[128];
    std::snprintf(expected, sizeof expected, "view: copied the camera {\"azimuth_deg\":%.1f,\"elevation_deg\":%.1f,",
                  azimuth, elevation);
    const size_t first = log.find(expected);
    CHECK(first != std::string::npos);
    // After U's round, the same camera again: up auto, the first picture.
    CHECK(log.find(expected, first + 1) != std::string::npos);
    CHECK(log.find("exit 0") != std::string::npos);
}
