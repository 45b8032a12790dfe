#include "draw/camera.h"

#include "base/common.h"

#include <glm/gtc/matrix_transform.hpp>

namespace ink {

UpAxis parseUpAxis(const std::string& name) {
    static const char* names[] = {"x", "-x", "y", "-y", "z", "-z"};
    for (int i = 0; i < 6; ++i)
        if (name == names[i] || (name.size() == 2 && name[0] == '+' && name.substr(1) == names[i])) return UpAxis(i);
    throw Error("up axis '" + name + "' is not one of x, -x, y, -y, z, -z");
}

const char* upAxisName(UpAxis up) {
    static const char* names[] = {"x", "-x", "y", "-y", "z", "-z"};
    return names[int(up)];
}

glm::mat3 upBasis(UpAxis up) {
    // Columns: the images of x, y (up) and z (towards the default viewer).
    switch (up) {
        case UpAxis::PosX:
            return glm::mat3(glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1));
        case UpAxis::NegX:
            return glm::mat3(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));
        case UpAxis::PosY:
            return glm::mat3(1.0f);
        case UpAxis::NegY:
            return glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, -1));
        case UpAxis::PosZ:
            return glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, -1, 0));
        case UpAxis::NegZ:
            return glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    }
    return glm::mat3(1.0f);
}

glm::vec3 Camera::eye() const {
    float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    glm::vec3 orbit(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    return target + distance * (upBasis(up) * orbit);
}

glm::mat4 Camera::view() const {
    if (!freeOrbit) return glm::lookAt(eye(), target, upBasis(up)[1]);
    // The orbit's tangent towards higher elevation: continuous over the poles, where the up axis is not.
    float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    glm::vec3 tangent(-std::sin(el) * std::sin(az), std::cos(el), -std::sin(el) * std::cos(az));
    return glm::lookAt(eye(), target, upBasis(up) * tangent);
}

glm::mat4 Camera::projection(float aspect) const {
    glm::mat4 p = glm::perspective(glm::radians(fovyDeg), aspect, 0.01f * distance, 4.0f * distance + 2.0f);
    p[1][1] *= -1.0f;
    return p;
}

}  // namespace ink
