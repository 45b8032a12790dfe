// How evenly a point set on a surface is spaced (Lagae & Dutré 2008): nearest-neighbour distances over
// r_max = sqrt(2A / (√3 N)), the spacing of N points packed hexagonally over the area A. White noise has a mean
// of about 0.47 and a minimum near 0; well-spaced blue noise a mean of about 0.8 and a minimum above 0.5.
#pragma once

#include "refine/point_record.h"

#include <cstddef>
#include <vector>

namespace ink {

struct SpacingStats {
    double fraction = 1;  // of the set: the prefix of the points whose rank (PointRecord::tone) is below it
    size_t points = 0;
    double rMax = 0;         // normalized units
    double meanNearest = 0;  // mean nearest-neighbour distance / r_max
    double minNearest = 0;   // smallest nearest-neighbour distance / r_max
    double clumped = 0;      // fraction of points closer than 0.5 r_max to another
};

// The surface area a point set covers, from its points alone: Σ π r₁₆² / 15.5 over the points, r₁₆ the distance
// to the 16th nearest neighbour (for a uniform density the disk holds 16 points; 15.5 corrects the bias the
// point at the centre brings). Normalized units; 0 for fewer than 17 points.
double estimateSurfaceArea(const std::vector<PointRecord>& points);

// Spacing of the prefix {rank < fraction} against the area A of the whole set.
SpacingStats measureSpacing(const std::vector<PointRecord>& points, double fraction, double area);

}  // namespace ink
