// Analytic shapes as oriented points, for built-in scenes (validate, bench) and tests.
#pragma once

#include "io/points.h"

namespace ink {

// Points on a Fibonacci spiral of the sphere of the given radius, with outward normals.
OrientedPoints spherePoints(size_t count, double radius = 0.5);
// The six axis points of a sphere (the report's "simple case").
OrientedPoints sphereAxisPoints(double radius = 0.5);
// A torus around the z axis (major radius R, minor r), nu × nv points.
OrientedPoints torusPoints(int nu, int nv, double R = 0.3, double r = 0.1);

}  // namespace ink
