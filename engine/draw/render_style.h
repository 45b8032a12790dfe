// How a frame is drawn: colours, dot and pen sizes, tone, light (renderer.h draws it, strokes.h its pen lines).
#pragma once

#include "draw/camera.h"

#include <cstdint>
#include <glm/glm.hpp>

namespace ink {

struct RenderStyle {
    glm::vec4 ink{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 paper{1.0f, 1.0f, 1.0f, 1.0f};
    glm::vec4 hiddenInk{0.0f, 0.0f, 0.0f, 0.45f};  // blended over the paper once: a grey line
    float frontSize = 2.0f;                        // dot diameter in output pixels
    float silhouetteSize = 2.4f;
    float hiddenSize = 1.4f;
    float tau = 0.1f;          // τ of the silhouette test (report §5)
    bool hiddenLines = false;  // draw occluded silhouettes faint
    bool occlusion = true;     // the splat depth pre-pass; off: every front-facing dot shows
    // Towards the key light, in view space (x right, y up, z to the viewer): the upper left. It follows the camera,
    // so the side facing the eye stays lit as it orbits; fixed to the model instead (lightFollowsCamera false), it
    // is given as seen from the default camera (azimuth 30°, elevation 15°) and the dots tone draws stay put.
    glm::vec3 light{-0.5f, 0.6f, 0.65f};
    bool lightFollowsCamera = true;
    UpAxis up = UpAxis::PosY;  // the default camera's up axis, which a light fixed to the model is given from
    // Tone: a front dot is drawn when its rank (PointRecord::tone: a selected stipple's rank, a refined point's
    // fixed random value) is below
    //   (ambient + (1 − max(0, n·l))^γ) · inkDensity · k,
    // k scaling the expected ink coverage of fully dark regions to about 60% at any zoom and point count.
    float toneGamma = 1.5f;  // 0: no tone, every front dot is drawn
    float inkDensity = 1.0f;
    float ambient = 0.04f;
    // Screen spacing (docs/algorithm.md §4): the candidates of a tone are spaced on the page, no two closer than a
    // radius the tone sets, so that tone is even however the surface turns away; off: the rank prefix alone.
    bool screenSpacing = true;
    // The spaced dots then relaxed (SPACE_RELAX_* in shared/render.h): moved by at most half their radius from the
    // greedy's just-over-a-radius towards even spacing; off (tests): where the greedy chose them.
    bool relaxDots = true;
    float splatScale = 2.0f;  // splat radius in units of the finest level's ρ
    bool drawDots = true;     // off: the point sets only give the depth the pen lines are tested against
    // Pen lines (strokes.h, docs/lines.md), widths in output pixels.
    float penWidth = 2.0f;        // visible contours
    float hiddenPenWidth = 1.2f;  // hidden contours (with hiddenLines, in hiddenInk)
    float hatchWidth = 1.0f;      // hatching, tapering at the ends
    float haloWidth = 4.0f;       // paper kept clear on each side of an interior contour, beyond its pen
    float creaseWidth = 1.5f;     // crease lines (feature_lines.h)
    float boundaryWidth = 2.0f;   // boundary lines: an open surface's rim, drawn like an outline
    // The darkness (ambient + (1 − max(0, n·l))^γ) · inkDensity from which each hatching family and level shows:
    // (along, coarse), (along, fine), (across, coarse), (across, fine).
    glm::vec4 hatchThresholds{0.25f, 0.45f, 0.65f, 0.85f};
    // The same for the third, diagonal family (coarse, fine): only the darkest tones.
    glm::vec2 diagonalThresholds{0.9f, 0.97f};
    float diagonalMinFacing = 0.3f;  // as hatchMinFacing, for the diagonal family
    float hatchMinFacing = 0.1f;     // hatching where |n·v| is below this is not drawn (foreshortened strokes)
    // Where the tone and facing would show a hatching stroke over a shorter run than this (a fraction of the image's
    // shorter side: 40 pixels at 1024²), that run is not drawn: no dashes where a stroke grazes the edge of a tone.
    float hatchMinRun = 0.04f;
    // Contour, crease and boundary lines: each segment shows as visible or hidden as most of its stroke within this
    // fraction of the image's shorter side either way does (15 pixels at 1024²): a median along the stroke, which
    // keeps where visibility truly changes and drops the shorter runs that the depth grid's cells flip (dashes).
    float lineMinRun = 0.015f;
    // How pen lines reach the pixels: antialiased quads in a graphics pipeline (GPUs), or stamped into the
    // coverage bits in compute like the dots (CPU drivers, whose triangle setup is serial); Auto picks by driver.
    enum class LineRaster { Auto, Quads, Stamps } lineRaster = LineRaster::Auto;
    uint32_t supersample = 2;  // offscreen: render this many times larger and filter down
};

// The unit light direction the shaders read: in view space when it follows the camera, else in model space (a
// light fixed to the model is given as seen from the default camera and turned into model space here).
inline glm::vec3 shaderLight(const RenderStyle& s) {
    glm::vec3 l = glm::length(s.light) > 0 ? glm::normalize(s.light) : glm::vec3(0, 0, 1);
    if (s.lightFollowsCamera) return l;
    Camera home;
    home.up = s.up;
    return glm::transpose(glm::mat3(home.view())) * l;
}

}  // namespace ink
