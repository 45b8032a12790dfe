// The first picture: how a model is shown when the user says nothing about the camera. Its up axis (the file's
// convention, else the shape's principal axes), a view chosen by a viewpoint-quality measure at an illustrator's
// elevation, and a distance that makes the model fill about 85% of the frame (docs/usage.md, "The first picture").
// All of it on the CPU from a few thousand surface samples (the refined points): milliseconds.
#pragma once

#include "draw/camera.h"
#include "refine/point_record.h"

#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

namespace ink {

// Points spread evenly over the surface (equal area each) with unit outward normals, normalized coordinates.
struct ViewSamples {
    std::vector<glm::vec3> positions, normals;
    // A surface that may be open (Model::twoSided), drawn from either side. scoreView then sees it facing either
    // way; chooseView passes it on for a sheet only (its thinnest spread under a quarter of the middle one: a map,
    // a terrain), which has no front either.
    bool twoSided = false;
};
// At most `maxCount` of the refined `points` of levels up to `maxLevel`, taken at an even stride (the refined
// points are spread evenly: so are these). The first levels are the same whatever the style and the number of
// levels, so every style of a model gets the same first picture.
ViewSamples viewSamples(const std::vector<PointRecord>& points, size_t maxCount = 20000, uint32_t maxLevel = 1);

// The up axis a file format fixes: glTF's is +y by its specification. None for the others.
std::optional<UpAxis> formatUpAxis(const std::string& path);
struct UpChoice {
    UpAxis up = UpAxis::PosY;
    std::string reason;          // "flat: its thinnest axis", ... (notes and --stats)
    float sigma[3] = {0, 0, 0};  // the principal standard deviations, largest first
};
// The up axis of a shape (docs/usage.md, "The first picture"), from the principal axes of the samples (PCA)
// and how lopsided each coordinate axis is:
// - flat (thinnest spread under 0.55 of the middle one): that axis, snapped to the nearest coordinate axis (a
//   spider, a plate, a knot lying down), unless it is a mirror axis while y is not (a camel, thin flank to flank);
// - else +y (most modelling tools; a z-up figure needs --up z).
// (A mesh cut flat at one end stands on its cut before this: Model::baseUp.)
// Always the positive direction: files are seldom upside down, and neither a base nor the mass told the sign
// reliably on the test models (docs/usage.md).
UpChoice detectUpAxis(const ViewSamples& samples);

struct ViewChoice {
    float azimuthDeg = 30.0f, elevationDeg = 15.0f;
    float score = 0;         // the viewpoint entropy of the choice (bits)
    float frontDeg = -1.0f;  // the azimuth of the side found to be the front, -1 when none is clear
};
// The candidate views: azimuths every 15°, elevations 15° and 30° above the horizon.
constexpr int kViewAzimuths = 24;
constexpr float kViewElevations[] = {15.0f, 30.0f};
// A three-quarter view: where a front is clear, the candidates lie this far from it in azimuth (the canonical
// views of Palmer et al. 1981 and Blanz et al. 1999: the front and a side at once, neither face-on nor profile).
constexpr float kThreeQuarterMinDeg = 20.0f, kThreeQuarterMaxDeg = 60.0f;
// A candidate view competes when its share of covered 3×3-pixel blocks that see the surface's front
// (ViewScore::facing) is at least this much of the best view's.
constexpr float kLeastFacingShare = 0.75f;
// The view of `samples` about `up` among the three-quarter views of its front, by viewpoint entropy (Vázquez
// et al. 2001) and the detail it shows: the samples are drawn into a small depth buffer from each candidate
// direction, and a visible sample counts with its projected area |n·v|; the entropy of those areas (and the
// background's) is larger the more surface is seen and the more evenly it faces the eye. Views along the
// principal axes of the silhouette, that flatten the shape, score low. The front is the side from which the
// shape hides the most of itself (counted in the views that see the surface's front, not an open surface's
// back), turned towards the side that shows the most detail where the two agree (or
// that side alone, on a nearly convex shape); where detail helped, a view's merit is its entropy + log₂(the
// detail it shows / a candidate's mean), else its entropy (docs/usage.md, "The first picture").
// Views that see much less of the surface's front than the best one (an open scan from behind) do not compete.
// Ties (a symmetric shape) keep the first of the candidate order, which starts at azimuth 30°, elevation 15°.
ViewChoice chooseView(const ViewSamples& samples, UpAxis up);
// How much the surface turns around each sample: 1 − |the mean of the unit normals of its 16 nearest
// samples|, 0 where it is flat (a point-set stand-in for the mesh saliency of Lee et al. 2005: faces, hands
// and paws score high, a smooth back low).
std::vector<float> sampleDetail(const ViewSamples& samples);
// One view direction (unit, from the model towards the eye; samples in the y-up frame): its viewpoint entropy
// in bits, the fraction of the samples facing the eye that something nearer hides, the sum of `detail`
// (one value a sample, or none) over the visible samples, and the share of the covered 3×3-pixel blocks whose
// nearest sample faces the eye (near 1 on a closed surface, short of it at the outline; small where an open
// surface, a one-sided scan, shows its back).
struct ViewScore {
    float entropy = 0, hidden = 0, detail = 0, facing = 0;
};
ViewScore scoreView(const ViewSamples& samples, const glm::vec3& towardsEye,
                    const std::vector<float>* detail = nullptr);

// Sets camera.distance and camera.target so that the projected extent of `samples` (not a bounding sphere)
// fills `fill` of the frame's width or height, whichever it reaches first, centred. The camera's angles, up
// axis and field of view are kept.
void frameSamples(Camera& camera, const ViewSamples& samples, float aspect, float fill = 0.85f);

}  // namespace ink
