// An orbit camera around the model (normalized coordinates: centre at the origin, diagonal 1).
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace ink {

// The model's up axis: the camera orbits it, and "above the horizon" is towards it. Scans and CAD models are
// often z-up; meshes from most modelling tools y-up.
enum class UpAxis { PosX, NegX, PosY, NegY, PosZ, NegZ };
// "x", "-x", "y", ... ; throws ink::Error naming the accepted values.
UpAxis parseUpAxis(const std::string& name);
const char* upAxisName(UpAxis up);
// The rotation from the y-up frame the orbit is written in to the model's: its columns are where the y-up
// frame's x, y and z axes point in the model (a proper rotation).
glm::mat3 upBasis(UpAxis up);

struct Camera {
    UpAxis up = UpAxis::PosY;
    float azimuthDeg = 30.0f;    // around the up axis
    float elevationDeg = 15.0f;  // above the horizon
    float distance = 1.6f;       // from the origin, in bounding-box diagonals
    float fovyDeg = 40.0f;
    glm::vec3 target{0.0f};
    // A turntable (false) keeps the up axis up, and its elevation within ±89°; a free orbit (true) tumbles over
    // the poles: any elevation, the view's up following the orbit.
    bool freeOrbit = false;

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;  // Vulkan clip space: y down, depth 0..1
};

}  // namespace ink
