// `inkwell view` as a user meets it, in a virtual X server (xvfb-run): it draws, saves what it drew, stays
// clean under validation, and says so in one line when there is no display.
#include "image.h"

#include "run_command.h"

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
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        FAIL("xvfb-run is not installed: the viewer tests need it (apt-get install xvfb xauth)");
    return shell("xvfb-run -a -n " + std::to_string(firstDisplay) + " -s \"-screen 0 1280x1024x24\" " +
                 INKWELL_BINARY " view " + args);
}

std::string tempPng(const char* name) {
    std::string path = (std::filesystem::temp_directory_path() / name).string();
    std::filesystem::remove(path);
    return path;
}

const char* kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj --control-points 150 --levels 2";

struct Ink {
    size_t paper = 0, dark = 0, darkInMiddle = 0;
    double centreX = 0, centreY = 0;  // of the dark pixels, as fractions of the image
};

// Paper is near white; ink is dark. The middle is the central 70% of each side.
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
            if (x > image.width * 15 / 100 && x < image.width * 85 / 100 && y > image.height * 15 / 100 &&
                y < image.height * 85 / 100)
                ++ink.darkInMiddle;
        }
    if (ink.dark) {
        ink.centreX /= double(ink.dark);
        ink.centreY /= double(ink.dark);
    }
    return ink;
}

}  // namespace

TEST_CASE("viewer: five validated frames of the bunny, the last saved as a framed drawing") {
    std::string shot = tempPng("inkwell-viewer-bunny.png");
    Run r = view(std::string(kBunny) + " --frames 5 --screenshot " + shot + " --validation", 140);
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("validation error") == std::string::npos);
    CHECK(r.output.find("view: 5 frames, median ") != std::string::npos);

    ink::RgbaImage image = ink::readPng(shot);
    CHECK(image.width == 1024);  // the default window
    CHECK(image.height == 768);
    Ink ink = countInk(image);
    size_t pixels = size_t(image.width) * image.height;
    CHECK(ink.paper > pixels * 9 / 10);
    CHECK(ink.dark >= 300);
    CHECK(ink.darkInMiddle >= ink.dark * 95 / 100);
    CHECK(ink.centreX == doctest::Approx(0.5).epsilon(0.3));
    CHECK(ink.centreY == doctest::Approx(0.5).epsilon(0.3));
}

TEST_CASE("viewer: --size sets the window, and the window shows what render draws, colours included") {
    // A coloured ink catches a swapchain in BGRA order saved without swizzling; one sample per pixel in both.
    std::string shot = tempPng("inkwell-viewer-size.png"), offscreen = tempPng("inkwell-viewer-render.png");
    std::string style = std::string(kBunny) + " --size 640 480 --ink '#c03020'";
    Run r = view(style + " --frames 2 --screenshot " + shot, 160);
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

TEST_CASE("viewer: --vector saves the window's marks as an SVG that draws as its screenshot") {
    // A page of the window's shape without margins, at 2 pixels a millimetre: drawn at the window's size by
    // rsvg-convert, the SVG is the screenshot (the same frame) after a 1-pixel blur.
    std::string shot = tempPng("inkwell-viewer-vector.png"), svg = tempPng("inkwell-viewer-vector.svg");
    std::string drawn = tempPng("inkwell-viewer-vector-svg.png");
    Run r = view(std::string(kBunny) + " --size 400 300 --frames 3 --screenshot " + shot + " --vector " + svg +
                     " --page 200x150mm --margin 0 --pen-width 0.5 --validation",
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

TEST_CASE("viewer: without a display it says so in one line and exits 1") {
    Run r = shell("env -u DISPLAY -u WAYLAND_DISPLAY " INKWELL_BINARY " view " INKWELL_SOURCE_DIR "/assets/bunny.obj");
    CHECK(r.status == 1);
    CHECK(r.output ==
          "inkwell: cannot open a window: no display (set DISPLAY, or run under xvfb-run); "
          "use 'inkwell render' for headless output\n");
}
