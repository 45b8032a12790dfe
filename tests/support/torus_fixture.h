// The fitted torus the line tests trace on (torusPoints' default radii, around the z axis), and samples of the
// analytic torus in the model's normalized coordinates.
#pragma once

#include "lines/lines.h"
#include "surface/model.h"
#include "surface/shapes.h"

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

namespace torus_fixture {

inline constexpr double kR = 0.3, kr = 0.1;  // input units

inline const ink::Model& torus() {
    static const ink::Model model = ink::fitModel(ink::torusPoints(48, 16, kR, kr), {});
    return model;
}

// nu × nv samples with their exact normals; `around`, when given, gets the direction around the axis at each.
inline std::vector<ink::SurfaceSample> torusSamples(const ink::Model& m, int nu, int nv,
                                                    std::vector<Eigen::Vector3d>* around = nullptr) {
    std::vector<ink::SurfaceSample> s;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double u = 2 * M_PI * (i + 0.5) / nu, v = 2 * M_PI * (j + 0.25) / nv;
            Eigen::Vector3d c(std::cos(u), std::sin(u), 0),
                n = std::cos(v) * c + std::sin(v) * Eigen::Vector3d::UnitZ();
            s.push_back({m.surface.frame.toNormalized(kR * c + kr * n), n});
            if (around) around->push_back(Eigen::Vector3d(-std::sin(u), std::cos(u), 0));
        }
    return s;
}

// A torus mesh of nu × nv vertices (radii 1 and 0.42, around the z axis) as an OBJ file: the targets' torus
// (the shared tools' targets.sh).
inline void writeTorusMesh(const std::filesystem::path& path, int nu = 64, int nv = 32) {
    std::ofstream obj(path);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            obj << "v " << (1 + 0.42 * std::cos(v)) * std::cos(u) << ' ' << (1 + 0.42 * std::cos(v)) * std::sin(u)
                << ' ' << 0.42 * std::sin(v) << '\n';
        }
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const int a = i * nv + j + 1, b = (i + 1) % nu * nv + j + 1, c = (i + 1) % nu * nv + (j + 1) % nv + 1,
                      d = i * nv + (j + 1) % nv + 1;
            obj << "f " << a << ' ' << b << ' ' << c << "\nf " << a << ' ' << c << ' ' << d << '\n';
        }
}

}  // namespace torus_fixture
