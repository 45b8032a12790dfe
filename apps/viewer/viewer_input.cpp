// What the keys, the mouse and the panel ask of the viewer (viewer.h): they set state, which the frame loop
// applies; the camera on the clipboard, and the panel's saves (a PNG or plot as `render` draws it, presets).
#include "../cli/preset.h"
#include "viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace app {

void Viewer::onKey(int key, int scancode, int action, int mods) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_KeyCallback(window_, key, scancode, action, mods);
        if (panel_->wantsKeyboard()) return;  // typing into one of its fields
    }
    bool press = action == GLFW_PRESS, repeat = action == GLFW_REPEAT;
    if (!press && !(repeat && (key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET))) return;
    inkwell::Look& s = o_.look;
    switch (key) {
        case GLFW_KEY_ESCAPE:
        case GLFW_KEY_Q:
            quit_ = true;
            break;
        case GLFW_KEY_1:
            o_.drawing.style = inkwell::Style::Stipple;
            s.dots = true;
            restyle_ = true;
            break;
        case GLFW_KEY_2:
            o_.drawing.style = inkwell::Style::Direction;
            s.dots = true;
            restyle_ = true;
            break;
        case GLFW_KEY_3:
            o_.drawing.style = inkwell::Style::Both;
            s.dots = true;
            restyle_ = true;
            break;
        case GLFW_KEY_EQUAL:  // '+' is shift+'=' on most layouts; '=' alone counts too
        case GLFW_KEY_KP_ADD:
            o_.drawing.levels = std::min(o_.drawing.levels + 1, kMaxLevels);
            break;
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT:
            o_.drawing.levels = o_.drawing.levels > 0 ? o_.drawing.levels - 1 : 0;
            break;
        case GLFW_KEY_LEFT_BRACKET:
            s.tau = std::max(0.0f, s.tau - 0.02f);
            restyle_ = true;
            break;
        case GLFW_KEY_RIGHT_BRACKET:
            s.tau = std::min(0.9f, s.tau + 0.02f);
            restyle_ = true;
            break;
        case GLFW_KEY_T:
            if (s.toneGamma > 0) {
                toneGamma_ = s.toneGamma;
                s.toneGamma = 0;  // every front dot
            } else {
                s.toneGamma = toneGamma_;
            }
            restyle_ = true;
            break;
        case GLFW_KEY_H:
            s.hiddenLines = !s.hiddenLines;
            restyle_ = true;
            break;
        case GLFW_KEY_O:
            s.occlusion = !s.occlusion;
            restyle_ = true;
            break;
        case GLFW_KEY_L:
            light_ = (light_ + 1) % kLights.size();
            s.light = kLights[light_];
            restyle_ = true;
            break;
        case GLFW_KEY_U:  // the next up axis: y, z, x, -y, -z, -x (a z-up scan stands up in one press)
        {
            // With `--up auto` at the start, "auto" takes the place of the axis it found: the cycle goes on from
            // it to the next axis, and back to it (and to its first picture) where that axis would come.
            static constexpr inkwell::Up kOrder[] = {inkwell::Up::Y,    inkwell::Up::Z,    inkwell::Up::X,
                                                     inkwell::Up::NegY, inkwell::Up::NegZ, inkwell::Up::NegX};
            size_t k = 0;
            while (kOrder[k] != o_.up) ++k;
            const inkwell::Up next = kOrder[(k + 1) % 6];
            if (autoHome_ && !o_.autoUp && next == autoHome_->up) {
                o_.up = next;
                camera_ = home_ = *autoHome_;
                o_.autoUp = true;
            } else {
                o_.up = next;
                camera_.up = home_.up = o_.up;
                o_.autoUp = false;  // chosen: a saved preset keeps it
            }
            restyle_ = true;  // the light is fixed to the model as seen from the default camera of this axis
            break;
        }
        case GLFW_KEY_S:
            screenshotKey_ = true;
            break;
        case GLFW_KEY_C:  // ctrl + C, ctrl + V: the camera as text on the clipboard (docs/viewer.md)
            if (mods & GLFW_MOD_CONTROL) copyCamera();
            break;
        case GLFW_KEY_V:
            if (mods & GLFW_MOD_CONTROL)
                pasteCamera();
            else
                vectorKey_ = true;
            break;
        case GLFW_KEY_R:
            camera_ = home_;
            break;
        case GLFW_KEY_TAB:
            if (panel_) panel_->toggle();
            break;
        case GLFW_KEY_F1:
            if (panel_) panel_->showHelp();
            break;
        default:
            break;
    }
    if (stale()) rerefine_ = true;
}

void Viewer::onChar(unsigned int c) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_CharCallback(window_, c);
    }
}

void Viewer::onMouseButton(int button, int action, int mods) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_MouseButtonCallback(window_, button, action, mods);
    }
    if (action == GLFW_PRESS) dragging_ = !(panel_ && panel_->wantsMouse());
}

void Viewer::onCursor(double x, double y) {
    double dx = x - lastX_, dy = y - lastY_;
    lastX_ = x;
    lastY_ = y;
    if (panel_) panel_->inputArrived();  // hovering changes it
    if (!dragging_) return;
    bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    bool shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                 glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    if (right || (left && shift)) {
        camera_.pan(dx, dy, swapchain_.extent.height);
    } else if (left) {
        // Grab-and-turn: dragging right turns the model right, i.e. the camera goes left around it.
        camera_.azimuthDeg = std::fmod(camera_.azimuthDeg - float(dx) * 0.3f, 360.0f);
        camera_.elevationDeg += float(dy) * 0.3f;
        camera_.elevationDeg = camera_.freeOrbit ? std::remainder(camera_.elevationDeg, 360.0f)
                                                 : std::clamp(camera_.elevationDeg, -89.0f, 89.0f);
    }
}

void Viewer::onScroll(double dx, double dy) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_ScrollCallback(window_, dx, dy);
        if (panel_->wantsMouse()) return;  // scrolls the panel
    }
    camera_.distance = std::clamp(camera_.distance * float(std::pow(0.9, dy)), 0.1f, 50.0f);
}

// The camera as one line of JSON on the clipboard (parseCameraText reads it, and `--camera` options, back).
void Viewer::copyCamera() {
    CameraText c;
    c.azimuthDeg = camera_.azimuthDeg;
    c.elevationDeg = camera_.elevationDeg;
    c.distance = camera_.distance;
    c.target = camera_.target;
    c.up = inkwell::upName(o_.up);
    c.fovDeg = camera_.fovyDeg;
    c.freeOrbit = camera_.freeOrbit;
    const std::string text = cameraJson(c);
    glfwSetClipboardString(window_, text.c_str());
    say("copied the camera " + text, false);
}

// The clipboard's camera, if it holds one; else the panel says why and the camera stays.
void Viewer::pasteCamera() {
    const char* clipboard = glfwGetClipboardString(window_);
    try {
        if (!clipboard) throw inkwell::Error("the clipboard holds no text");
        const CameraText c = parseCameraText(clipboard);
        if (c.up) {
            o_.up = inkwell::parseUp(*c.up);
            home_.up = o_.up;
            o_.autoUp = false;
            restyle_ = true;  // the light is given about the up axis
        }
        camera_.up = o_.up;
        if (c.freeOrbit) camera_.freeOrbit = *c.freeOrbit;
        camera_.azimuthDeg = c.azimuthDeg;
        camera_.elevationDeg = camera_.freeOrbit ? c.elevationDeg : std::clamp(c.elevationDeg, -89.0f, 89.0f);
        camera_.distance = std::clamp(c.distance, 0.1f, 50.0f);
        if (c.target) camera_.target = *c.target;
        if (c.fovDeg) camera_.fovyDeg = std::clamp(*c.fovDeg, 10.0f, 100.0f);
        say("pasted the camera", false);
    } catch (const inkwell::Error& e) {
        say(std::string("camera not pasted: ") + e.what(), true);
    }
}

// The panel's notes go to its last line and, as the viewer's other notes, to the terminal.
void Viewer::say(const std::string& line, bool error) {
    message_ = line;
    if (error)
        note(line);
    else
        std::printf("view: %s\n", line.c_str());
    std::fflush(stdout);
}

// The panel's widgets for this frame, and what they asked for.
void Viewer::buildPanel(double frameMs) {
    PanelInfo info;
    info.model = std::filesystem::path(o_.model).filename().string();
    info.controlPoints = controlPoints_;
    info.points = points_;
    info.frameMs = frameMs;
    info.refining = rerefine_ || job_;
    info.refineProgress = job_ ? job_->permille / 1000.0 : 0.0;
    info.task = job_ && job_->tracing ? "tracing the lines" : "refining";
    info.message = message_;
    info.screenshotPath = v_.screenshot.empty() ? "inkwell-view-N.png (the first free N)" : v_.screenshot;
    info.drawing = drawingExtent();
    info.autoUp = autoHome_ ? inkwell::upName(autoHome_->up) : nullptr;
    if (pngDefault_.empty()) pngDefault_ = nextDrawingPath();
    info.pngPath = pngDefault_;
    PanelActions a = panel_->build(o_, camera_, info);
    if (a.restyle) restyle_ = true;
    if (a.rerefine) rerefine_ = true;
    if (a.upChanged) {
        camera_.up = home_.up = o_.up;
        o_.autoUp = false;
    }
    if (a.upAuto && autoHome_) {
        o_.up = autoHome_->up;
        camera_ = home_ = *autoHome_;
        o_.autoUp = true;
    }
    if (a.resetCamera) camera_ = home_;
    if (a.copyCamera) copyCamera();
    if (a.pasteCamera) pasteCamera();
    if (a.saveScreenshot) screenshotKey_ = true;
    if (a.savePng && !job_) {
        try {
            savePng(a.pngPath, a.pngSize[0], a.pngSize[1]);
            say("saved " + a.pngPath, false);
        } catch (const inkwell::Error& e) {
            say(std::string("not saved: ") + e.what(), true);
        }
    }
    if (a.savePreset) {
        try {
            inkwell::checkOutputs({a.presetPath}, {o_.model});
            inkwell::OutputBatch now;  // at once, even inside the --screenshot batch
            inkwell::writeFileAtomically(a.presetPath, presetJson(presetFrom(o_)));
            now.commit();
            say("saved preset " + a.presetPath, false);
        } catch (const inkwell::Error& e) {
            say(std::string("preset not saved: ") + e.what(), true);
        }
    }
    if (a.loadPreset) {
        try {
            loadPreset(o_, a.presetPath);
            camera_.up = home_.up = o_.up;
            restyle_ = true;
            if (stale()) rerefine_ = true;
            say("loaded preset " + a.presetPath, false);
        } catch (const inkwell::Error& e) {
            say(e.what(), true);
        }
    }
}

// What `inkwell render -o path` draws with the same options and camera at width × height: a PNG supersampled as
// it does, or (.svg, .pdf) the frame's marks laid out on the page of the --page options.
void Viewer::savePng(const std::string& path, uint32_t width, uint32_t height) {
    inkwell::checkOutputs({path}, {o_.model, o_.preset});
    device_.checkImageSize(width, height, o_.look.supersample);
    inkwell::Renderer offscreen(drawing_, width, height, o_.look);
    const inkwell::Image image = offscreen.render(camera_);  // the pen lines of this view, as render's
    inkwell::OutputBatch now;                                // at once, even inside the --screenshot batch
    if (inkwell::Plot::isVectorPath(path))
        offscreen.plot(o_.page).write(path);
    else
        image.writePng(path);
    now.commit();
}

}  // namespace app
