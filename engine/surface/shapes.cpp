#include "surface/shapes.h"

#include <cmath>

namespace ink {

OrientedPoints spherePoints(size_t count, double radius) {
    OrientedPoints pts;
    for (size_t i = 0; i < count; ++i) {
        double z = 1.0 - 2.0 * (double(i) + 0.5) / double(count);
        double s = std::sqrt(1.0 - z * z), phi = double(i) * 2.399963229728653;  // golden angle
        Eigen::Vector3d n(s * std::cos(phi), s * std::sin(phi), z);
        pts.positions.push_back(radius * n);
        pts.normals.push_back(n);
    }
    return pts;
}

OrientedPoints sphereAxisPoints(double radius) {
    OrientedPoints pts;
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {1.0, -1.0}) {
            Eigen::Vector3d n = Eigen::Vector3d::Zero();
            n[axis] = sign;
            pts.positions.push_back(radius * n);
            pts.normals.push_back(n);
        }
    return pts;
}

OrientedPoints torusPoints(int nu, int nv, double R, double r) {
    OrientedPoints pts;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double u = 2 * M_PI * (i + 0.5 * (j % 2)) / nu, v = 2 * M_PI * j / nv;
            Eigen::Vector3d c(std::cos(u), std::sin(u), 0);
            Eigen::Vector3d n = std::cos(v) * c + std::sin(v) * Eigen::Vector3d::UnitZ();
            pts.positions.push_back(R * c + r * n);
            pts.normals.push_back(n);
        }
    return pts;
}

}  // namespace ink
