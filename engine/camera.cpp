#include "camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace ink {

glm::vec3 Camera::eye() const {
    float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    return target + distance * glm::vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
}

glm::mat4 Camera::view() const { return glm::lookAt(eye(), target, glm::vec3(0, 1, 0)); }

glm::mat4 Camera::projection(float aspect) const {
    glm::mat4 p = glm::perspective(glm::radians(fovyDeg), aspect, 0.01f * distance, 4.0f * distance + 2.0f);
    p[1][1] *= -1.0f;
    return p;
}

}  // namespace ink
