#include "surface/viewpoint.h"

#include "base/common.h"
#include "base/point_tree.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

namespace ink {

ViewSamples viewSamples(const std::vector<PointRecord>& all, size_t maxCount, uint32_t maxLevel) {
    ViewSamples s;
    std::vector<PointRecord> points;
    for (const PointRecord& p : all)
        if (p.level <= maxLevel) points.push_back(p);
    if (points.empty() || maxCount == 0) return s;
    const double stride = std::max(1.0, double(points.size()) / double(maxCount));
    for (double i = 0; size_t(i) < points.size(); i += stride) {
        const PointRecord& p = points[size_t(i)];
        glm::vec3 position(p.position[0], p.position[1], p.position[2]), normal(p.normal[0], p.normal[1], p.normal[2]);
        const float length = glm::length(normal);
        if (!std::isfinite(length) || !(length > 0) || !std::isfinite(glm::length(position))) continue;
        s.positions.push_back(position);
        s.normals.push_back(normal / length);
    }
    return s;
}

static std::string lowerExtension(const std::string& path) {
    const size_t dot = path.find_last_of('.'), slash = path.find_last_of("/\\");
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string e = path.substr(dot + 1);
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

std::optional<UpAxis> formatUpAxis(const std::string& path) {
    const std::string e = lowerExtension(path);
    if (e == "gltf" || e == "glb") return UpAxis::PosY;
    return std::nullopt;
}

static UpAxis axisOf(int coordinate, bool negative) { return UpAxis(2 * coordinate + (negative ? 1 : 0)); }

// Along coordinate `c`: the third standardized moment, and the area fractions facing straight out (n within
// 25° of the axis) in the lowest and the highest 5% of the extent (feet, a plinth, a flat bottom or top).
struct AxisProfile {
    double skew = 0, baseBelow = 0, baseAbove = 0;
    // A mirror plane across the axis leaves both ends alike: no skew, equal bases. Gravity makes up and down
    // differ, so such an axis is left and right (an animal's flank to flank), not up.
    bool mirrored() const {
        return std::abs(skew) < 0.05 &&
               std::abs(baseBelow - baseAbove) <= 0.25 * std::max(baseBelow, baseAbove) + 0.001;
    }
};

static AxisProfile profile(const ViewSamples& samples, int c) {
    AxisProfile a;
    const size_t n = samples.positions.size();
    float low = std::numeric_limits<float>::max(), high = -low;
    double mean = 0;
    for (const glm::vec3& p : samples.positions) {
        low = std::min(low, p[c]);
        high = std::max(high, p[c]);
        mean += p[c];
    }
    mean /= double(n);
    const float band = 0.05f * (high - low);
    double second = 0, third = 0;
    size_t below = 0, above = 0;
    for (size_t i = 0; i < n; ++i) {
        const float h = samples.positions[i][c], facing = samples.normals[i][c];
        below += h <= low + band && facing < -0.9f;
        above += h >= high - band && facing > 0.9f;
        const double d = double(h) - mean;
        second += d * d;
        third += d * d * d;
    }
    second /= double(n);
    a.skew = second > 0 ? third / double(n) / std::pow(second, 1.5) : 0.0;
    a.baseBelow = double(below) / double(n);
    a.baseAbove = double(above) / double(n);
    return a;
}

// Standing shapes (detectUpAxis): the longest axis' spread over the middle one's, at least; and the share of the
// samples facing out at one end of it.
constexpr float kStanding = 1.8f;
constexpr double kStandingBase = 0.005;

UpChoice detectUpAxis(const ViewSamples& samples) {
    UpChoice choice;
    const size_t n = samples.positions.size();
    if (n < 16) {
        choice.reason = "too few samples: y";
        return choice;
    }
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const glm::vec3& p : samples.positions) mean += Eigen::Vector3d(p.x, p.y, p.z);
    mean /= double(n);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const glm::vec3& p : samples.positions) {
        const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
        covariance += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance / double(n));  // ascending
    const Eigen::Vector3d values = solver.eigenvalues().cwiseMax(0.0);
    for (int k = 0; k < 3; ++k) choice.sigma[k] = float(std::sqrt(values[2 - k]));
    AxisProfile axes[3];
    for (int c = 0; c < 3; ++c) axes[c] = profile(samples, c);
    // Flat: the thinnest axis, snapped to a coordinate axis, unless a mirror plane lies across it while y is
    // lopsided (a camel is thin from flank to flank). Otherwise +y: a figure's up and front axes are both
    // lopsided, and nothing in the shape alone told them apart reliably.
    int thinnest = 0, longest = 0;
    solver.eigenvectors().col(0).cwiseAbs().maxCoeff(&thinnest);
    solver.eigenvectors().col(2).cwiseAbs().maxCoeff(&longest);
    if (choice.sigma[2] < 0.55f * choice.sigma[1] &&
        !(axes[thinnest].mirrored() && thinnest != 1 && !axes[1].mirrored())) {
        // Standing, though flat: also much longer along one axis than across, with a base at its low end (flat area
        // facing down there, not up at the other: feet, a plinth): that axis up. A figure is thin from front to back,
        // which this test takes for up (CGAL's man.off lay on his back); a plank lying has like faces at both ends.
        // Only the axis's positive direction: a flat top larger than the feet (a box-shaped body) would otherwise
        // stand a figure on its head. A shape that is not flat is left alone (a foot's bones stood on their heel).
        const AxisProfile& along = axes[longest];
        if (choice.sigma[0] > kStanding * choice.sigma[1] && along.baseBelow >= kStandingBase &&
            along.baseBelow >= 2 * along.baseAbove) {
            choice.up = axisOf(longest, false);
            choice.reason = "standing: its longest axis, a base at its low end";
            return choice;
        }
        choice.up = axisOf(thinnest, false);
        choice.reason = "flat: its thinnest axis";
        return choice;
    }
    choice.up = UpAxis::PosY;
    choice.reason = "not flat: y";
    return choice;
}

// An orthonormal image basis for looking along -towardsEye.
static void imageBasis(const glm::vec3& towardsEye, const glm::vec3& up, glm::vec3& right, glm::vec3& upInImage) {
    glm::vec3 r = glm::cross(up, towardsEye);
    if (glm::length(r) < 1e-6f) r = glm::cross(glm::vec3(1, 0, 0), towardsEye);
    if (glm::length(r) < 1e-6f) r = glm::cross(glm::vec3(0, 1, 0), towardsEye);
    right = glm::normalize(r);
    upInImage = glm::cross(towardsEye, right);
}

std::vector<float> sampleDetail(const ViewSamples& samples) {
    constexpr size_t k = 16;
    const size_t n = samples.positions.size();
    std::vector<float> detail(n, 0.0f);
    if (n < k) return detail;
    std::vector<Eigen::Vector3d> points(n);
    for (size_t i = 0; i < n; ++i) points[i] = {samples.positions[i].x, samples.positions[i].y, samples.positions[i].z};
    const PointCloud cloud{points};
    PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    uint32_t nearest[k];
    double distances[k];
    for (size_t i = 0; i < n; ++i) {
        const size_t found = tree.knnSearch(points[i].data(), k, nearest, distances);
        glm::vec3 mean(0);
        for (size_t j = 0; j < found; ++j) mean += samples.normals[nearest[j]];
        detail[i] = found > 0 ? std::max(0.0f, 1.0f - glm::length(mean) / float(found)) : 0.0f;
    }
    return detail;
}

ViewScore scoreView(const ViewSamples& samples, const glm::vec3& towardsEye, const std::vector<float>* detail) {
    constexpr int G = 96;  // the depth buffer's side: about 1% of the diagonal a pixel
    const size_t n = samples.positions.size();
    if (n == 0) return {};
    glm::vec3 right, upInImage;
    imageBasis(towardsEye, glm::vec3(0, 1, 0), right, upInImage);
    float radius = 0;
    for (const glm::vec3& p : samples.positions) radius = std::max(radius, glm::length(p));
    if (!(radius > 0)) return {};
    const float pixel = 2 * radius / G;
    std::vector<float> nearest(G * G, -std::numeric_limits<float>::max());
    // The nearest sample of each 3×3 block of pixels (several samples a block: a closed surface's nearest one
    // faces the eye but at its outline).
    constexpr int B = G / 3;
    std::vector<float> blockNearest(B * B, -std::numeric_limits<float>::max());
    std::vector<size_t> blockSample(B * B, n);
    std::vector<int> cell(n);
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3& p = samples.positions[i];
        const int x = std::clamp(int((glm::dot(p, right) + radius) / pixel), 0, G - 1);
        const int y = std::clamp(int((glm::dot(p, upInImage) + radius) / pixel), 0, G - 1);
        cell[i] = y * G + x;
        const float depth = glm::dot(p, towardsEye);
        nearest[cell[i]] = std::max(nearest[cell[i]], depth);
        const int block = (y / 3) * B + x / 3;
        if (depth > blockNearest[block]) blockNearest[block] = depth, blockSample[block] = i;
    }
    // A visible sample faces the eye and lies within two pixels of the nearest surface in its pixel. Each
    // sample stands for the same area, which is the covered pixels' area over the visible samples' Σ n·v.
    double facing = 0, seen = 0;
    size_t front = 0, hidden = 0;
    std::vector<float> projected;
    projected.reserve(n);
    // A surface drawn two-sided is seen facing either way (a sheet, a terrain, a map from whichever side the
    // orbit reaches: CGAL's poste_france.xyz, its normals pointing down, was shown edge-on); what hides itself
    // (ViewScore::hidden, the front's cue) still counts the front-facing samples only.
    for (size_t i = 0; i < n; ++i) {
        const float toward = glm::dot(samples.normals[i], towardsEye);
        const float c = samples.twoSided ? std::abs(toward) : toward;
        if (c <= 0) continue;
        const bool behind = glm::dot(samples.positions[i], towardsEye) < nearest[cell[i]] - 2 * pixel;
        if (toward > 0) {
            ++front;
            hidden += behind;
        }
        if (behind) continue;
        projected.push_back(c);
        facing += c;
        if (detail) seen += (*detail)[i];
    }
    size_t covered = 0, blocks = 0, blocksFacing = 0;
    for (float d : nearest) covered += d > -std::numeric_limits<float>::max();
    for (size_t i : blockSample) {
        if (i == n) continue;
        ++blocks;
        const float toward = glm::dot(samples.normals[i], towardsEye);
        blocksFacing += (samples.twoSided ? std::abs(toward) : toward) > 0;
    }
    if (facing <= 0) return {};
    // Areas relative to the image square's: the covered part split over the visible samples, the rest
    // background. The entropy of that split, in bits.
    const double total = double(G) * G, scale = double(covered) / facing / total;
    double h = 0;
    for (float c : projected) {
        const double p = c * scale;
        if (p > 0) h -= p * std::log2(p);
    }
    const double background = 1.0 - double(covered) / total;
    if (background > 0) h -= background * std::log2(background);
    return {float(h), front > 0 ? float(double(hidden) / double(front)) : 0.0f, float(seen),
            float(double(blocksFacing) / double(blocks))};
}

// A sheet: its thinnest principal spread under this fraction of the middle one (a quarter: a map, a terrain, a relief;
// not a spider, which detectUpAxis's 0.55 calls flat and whose front a view should show).
constexpr double kSheet = 0.25;
// Whether the samples are a sheet (kSheet).
static bool isSheet(const ViewSamples& samples) {
    const size_t n = samples.positions.size();
    if (n < 16) return false;
    glm::dvec3 mean(0.0);
    for (const glm::vec3& p : samples.positions) mean += glm::dvec3(p);
    mean /= double(n);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const glm::vec3& p : samples.positions) {
        const Eigen::Vector3d d(p.x - mean.x, p.y - mean.y, p.z - mean.z);
        covariance += d * d.transpose();
    }
    const Eigen::Vector3d values =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues();  // ascending
    return std::sqrt(std::max(values[0], 0.0)) < kSheet * std::sqrt(std::max(values[1], 0.0));
}

static float candidateAzimuth(int k) { return std::fmod(30.0f + 360.0f * float(k) / kViewAzimuths, 360.0f); }

ViewChoice chooseView(const ViewSamples& samples, UpAxis up) {
    ViewChoice best;
    best.score = -1;
    const glm::mat3 basis = upBasis(up);
    // The samples in the y-up frame the orbit is written in (the basis is a rotation: its transpose inverts).
    ViewSamples local;
    // A sheet drawn two-sided (a terrain, a map, a relief: an open surface much thinner than it is wide) is seen
    // from either side alike, and has no front: what it hides of itself seen edge-on is its own curl. Drawn
    // one-sided only its normals' side counted, and the three-quarter rule kept CGAL's poste_france.xyz (a map of
    // France, its estimated normals pointing down) to views along it. Other open surfaces (a mask, an open box)
    // keep their normals' side: seen two-sided the views chose a mask's inside.
    const bool sheet = samples.twoSided && isSheet(samples);
    local.twoSided = sheet;
    local.positions.reserve(samples.positions.size());
    local.normals.reserve(samples.normals.size());
    const glm::mat3 toLocal = glm::transpose(basis);
    for (size_t i = 0; i < samples.positions.size(); ++i) {
        local.positions.push_back(toLocal * samples.positions[i]);
        local.normals.push_back(toLocal * samples.normals[i]);
    }
    const std::vector<float> detail = sampleDetail(local);
    constexpr int E = int(std::size(kViewElevations));
    ViewScore scores[E][kViewAzimuths];
    glm::vec2 front(0), detailed(0);
    double detailSum = 0;
    float mostFacing = 0;
    for (int e = 0; e < E; ++e)
        for (int k = 0; k < kViewAzimuths; ++k) {
            const float az = glm::radians(candidateAzimuth(k)), el = glm::radians(kViewElevations[e]);
            scores[e][k] = scoreView(
                local, glm::vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)), &detail);
            mostFacing = std::max(mostFacing, scores[e][k].facing);
            const glm::vec2 towards(std::sin(az), std::cos(az));
            // What an open surface's back hides behind it is not the shape hiding itself: only the share of
            // the view that sees the front counts.
            front += scores[e][k].hidden * scores[e][k].facing * towards;
            detailed += scores[e][k].detail * towards;
            detailSum += scores[e][k].detail;
        }
    // The front: where the shape hides the most of itself (limbs, a head, arms before the body), the resultant
    // of the hidden fractions around the circle. Where the side that shows the most detail (a face, hands; the
    // resultant of the visible detail, against its mean) is clearly on the same half of the circle, the front
    // turns halfway towards it: self-occlusion finds the front's half, detail where in it the face is (the
    // bunny's hidden-side front is about 40° off its face, its detail side about 20°).
    const float mean = float(detailSum / (E * kViewAzimuths));  // a candidate's visible detail, on average
    const float contrast = mean > 0 ? glm::length(detailed) / mean : 0.0f;
    const float clear = 0.02f * kViewAzimuths;
    // A sheet: entropy alone chooses, the view that sees most of it.
    const bool hiddenSided = !sheet && glm::length(front) > clear;
    // Whether detail found (or helped find) the front, and so also chooses between its three-quarter views.
    bool faced = false;
    if (hiddenSided && contrast > 1.0f && glm::dot(front, detailed) > 0) {
        front = glm::normalize(front) + glm::normalize(detailed);
        faced = true;
    } else if (!sheet && glm::length(front) < 0.5f * clear && contrast > 3.0f) {
        // No side hides itself (a head, a bust: nearly convex), but one clearly shows the detail.
        front = detailed;
        faced = true;
    }
    const bool sided = hiddenSided || faced;
    best.frontDeg = sided ? std::fmod(glm::degrees(std::atan2(front.x, front.y)) + 360.0f, 360.0f) : -1.0f;
    // Where the front is clear, only three-quarter views of it compete, by entropy; where detail told the front,
    // by entropy plus log₂ of the detail a view shows against a candidate's mean (as maximizing 2^entropy ×
    // detail: the number of evenly seen areas, weighted by what is in them, after the saliency-guided views of
    // Lee et al. 2005): of the two three-quarter sides, the one with the face.
    float bestMerit = -std::numeric_limits<float>::max();
    for (int e = 0; e < E; ++e)
        for (int k = 0; k < kViewAzimuths; ++k) {
            const float azimuth = candidateAzimuth(k);
            const float off = std::abs(std::remainder(azimuth - best.frontDeg, 360.0f));
            if (sided && (off < kThreeQuarterMinDeg || off > kThreeQuarterMaxDeg)) continue;
            const ViewScore& score = scores[e][k];
            if (!(score.entropy > 0) || score.facing < kLeastFacingShare * mostFacing) continue;
            const float merit = score.entropy + (faced ? std::log2(std::max(score.detail, 1e-3f * mean) / mean) : 0.0f);
            if (merit > bestMerit + 1e-4f) {
                bestMerit = merit;
                best.azimuthDeg = azimuth;
                best.elevationDeg = kViewElevations[e];
                best.score = score.entropy;
            }
        }
    if (best.score < 0) best = ViewChoice{};
    return best;
}

void frameSamples(Camera& camera, const ViewSamples& samples, float aspect, float fill) {
    if (samples.positions.empty() || !(aspect > 0) || !(fill > 0)) return;
    const float t = std::tan(glm::radians(camera.fovyDeg) / 2);
    // Iterate: project at the current distance and target, then scale the distance by how much the extent
    // over- or under-fills, and move the target to centre it. Converges in a few rounds (perspective is mild).
    camera.target = glm::vec3(0);
    for (int round = 0; round < 8; ++round) {
        const glm::mat4 view = camera.view();
        glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const glm::vec3& p : samples.positions) {
            const glm::vec4 q = view * glm::vec4(p, 1.0f);
            const float depth = std::max(-q.z, 1e-4f);
            const glm::vec2 ndc(q.x / (depth * t * aspect), q.y / (depth * t));
            lo = glm::min(lo, ndc);
            hi = glm::max(hi, ndc);
        }
        const glm::vec2 size = hi - lo, centre = 0.5f * (hi + lo);
        const float reach = std::max(size.x, size.y) / 2;  // of the half-frame's 1
        if (!(reach > 0)) return;
        // Move the target in the image plane to the extent's centre (at the target's depth), then scale.
        const glm::mat3 rotation = glm::transpose(glm::mat3(view));  // view to model
        camera.target +=
            rotation * glm::vec3(centre.x * camera.distance * t * aspect, centre.y * camera.distance * t, 0);
        camera.distance = std::clamp(camera.distance * reach / fill, 0.06f, 99.0f);
    }
}

}  // namespace ink
