// An orbit camera around the model (normalized coordinates: centre at the origin, diagonal 1).
#pragma once

#include <glm/glm.hpp>

namespace ink {

struct Camera {
    float azimuthDeg = 30.0f;    // around the up axis (+y)
    float elevationDeg = 15.0f;  // above the horizon
    float distance = 1.6f;       // from the origin, in bounding-box diagonals
    float fovyDeg = 40.0f;
    glm::vec3 target{0.0f};

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;  // Vulkan clip space: y down, depth 0..1
};

}  // namespace ink
