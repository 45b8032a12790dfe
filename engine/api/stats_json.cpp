#include "api/stats_json.h"

#include "draw/page_metrics.h"
#include "refine/spacing.h"

#include <algorithm>

namespace inkwell::api {

json hostMsJson(const ink::HostMs& h) {
    return {{"plan", h.plan}, {"buffers", h.buffers}, {"pipelines", h.pipelines}, {"run", h.run}};
}

json fitJson(const ink::Model& m) {
    json j = {{"method", m.surface.method == ink::FitMethod::Global ? "global" : "pu"},
              {"seconds", m.fit.seconds},
              {"relative_residual", m.fit.relativeResidual},
              {"max_distance", m.fit.maxDistance},
              {"max_normal_angle_deg", m.fit.maxNormalAngleDeg},
              {"input_max_distance", m.inputMaxDistance},
              {"input_mean_distance", m.inputMeanDistance},
              {"input_max_normal_angle_deg", m.inputMaxAngleDeg},
              {"two_sided", m.twoSided},
              {"turned_outward", m.turnedOutward},
              {"outliers", m.outliers},
              {"noise", m.noise},
              {"smoothed_by", m.smoothedBy},
              {"estimated_normals", m.estimatedNormals}};
    if (!m.fit.phases.ms.empty()) {  // a fitted model: where its fit's time went
        json phases = json::object();
        for (const auto& [step, ms] : m.fit.phases.ms) phases[step] = ms;
        j["phases_ms"] = phases;
    }
    if (m.surface.method == ink::FitMethod::PartitionOfUnity)
        j["patches"] = {{"count", m.patches.patches},
                        {"min_points", m.patches.minPatch},
                        {"max_points", m.patches.maxPatch},
                        {"mean_points", m.patches.meanPatch},
                        {"far_field_points", m.patches.coarsePoints},
                        {"grid_cells", m.patches.gridCells},
                        {"grid_entries", m.patches.gridEntries},
                        {"seams",
                         {{"samples", m.patches.seams.samples},
                          {"normal_deg_median", m.patches.seams.normalDegMedian},
                          {"normal_deg_p95", m.patches.seams.normalDegP95},
                          {"curvature_ratio_median", m.patches.seams.curvatureRatioMedian},
                          {"curvature_ratio_p95", m.patches.seams.curvatureRatioP95},
                          {"roughness_median", m.patches.seams.roughnessMedian},
                          {"roughness_p95", m.patches.seams.roughnessP95}}}};
    return j;
}

json levelsJson(const std::vector<ink::LevelStats>& levels) {
    json list = json::array();
    for (const auto& s : levels) {
        json dropped;
        for (uint32_t k = 0; k < ink::DropReasonCount; ++k) dropped[ink::dropReasonName(k)] = s.dropped[k];
        list.push_back({{"level", s.level},
                        {"candidates", s.candidates},
                        {"kept", s.kept},
                        {"dropped", dropped},
                        {"gpu_ms", s.gpuMs}});
    }
    return list;
}

json plotJson(const ink::Plot& plot) {
    json layers = json::array();
    double seconds = 0;
    std::vector<glm::vec3> inks;
    for (const ink::PlotLayer& l : plot.layers) {
        layers.push_back({{"pen", l.pen},
                          {"name", l.name},
                          {"paths", l.paths.size()},
                          {"paths_before", l.pathsBefore},
                          {"vertices", l.vertices},
                          {"vertices_before", l.verticesBefore},
                          {"merged", l.merged},
                          {"retraced_mm", l.retraced},
                          {"travel_before_mm", l.travelBefore},
                          {"travel_after_mm", l.travelAfter},
                          {"pen_down_mm", l.penDown},
                          {"lifts", l.lifts},
                          {"fill_circles", l.fillCircles},
                          {"plot_seconds", l.plotSeconds}});
        seconds += l.plotSeconds;
        if (std::find(inks.begin(), inks.end(), l.color) == inks.end()) inks.push_back(l.color);
    }
    return {{"page_mm", {plot.width, plot.height}},
            {"pen_width_mm", plot.penWidth},
            {"pens", plot.layers.size()},
            {"inks", inks.size()},
            {"plot_seconds", seconds},
            {"time_model",
             {{"pen_down_mm_per_s", plot.drawSpeed},
              {"pen_up_mm_per_s", plot.travelSpeed},
              {"seconds_per_lift", plot.liftSeconds}}},
            {"layers", layers}};
}

// A model's feature lines: whether they were drawn and, if so, how many and how long (normalized units). Not
// drawn, they may not have been looked for (modelOptions).
static json featureJson(const std::vector<ink::PenStroke>& strokes, bool drawn) {
    if (!drawn) return {{"drawn", false}};
    double length = 0;
    for (const ink::PenStroke& s : strokes) length += s.length();
    return {{"strokes", strokes.size()}, {"length", length}, {"drawn", true}};
}

json pageJson(const ink::OffscreenRenderer& renderer, size_t sets, const ink::RenderStyle& style, uint32_t width,
              uint32_t height) {
    json out = json::array();
    const double factor = renderer.supersample();
    for (size_t k = 0; k < sets; ++k) {
        const ink::PageMetrics m =
            ink::measurePage(renderer.dotList(k), uint32_t(width * factor), uint32_t(height * factor), 128.0 * factor,
                             style.frontSize * factor, 8.0 * factor);
        out.push_back({{"front_dots", m.frontDots},
                       {"larger_dots", m.largerDots},
                       {"outline_dots", m.outlineDots},
                       {"screen_spacing", style.screenSpacing},
                       {"page",
                        {{"windows", m.windows.size()},
                         {"mean_nn_over_r_max", m.meanNearest},
                         {"worst_nn_over_r_max", m.worstNearest},
                         {"worst_clumped", m.worstClumped},
                         {"coverage", {m.leastCoverage, m.mostCoverage}}}}});
    }
    return out;
}

json linesJson(const ink::Scene& scene) {
    const ink::HatchStats& h = scene.hatchStats;
    const ink::ContourStats& c = scene.contourStats;
    return {{"hatching",
             {{"strokes", scene.hatching.size()},
              {"vertices", h.vertices},
              {"length", h.length},
              {"field_seconds", h.fieldSeconds},
              {"field_graph_seconds", h.fieldGraphSeconds},
              {"field_on", h.fieldOnDevice ? "device" : "cpu"},
              {"field_device_ms", h.fieldDeviceMs},
              {"seconds", h.seconds}}},
            {"creases", featureJson(scene.model.features.creases, scene.lines.creases)},
            {"boundaries", featureJson(scene.model.features.boundaries, scene.lines.boundaries)},
            {"contours",
             {{"curves", c.curves},
              {"closed_curves", c.closedCurves},
              {"pieces", scene.contours.size()},
              {"cusps", c.cusps},
              {"small_loops_dropped", c.smallLoops},
              {"swallowtails_merged", c.swallowtails},
              {"occluded_pieces", c.occluded},
              {"seeds_tried", c.seedsTried},
              {"vertices", c.vertices},
              {"traced_on", c.onDevice ? "device" : "cpu"},
              {"device_ms", c.deviceMs},
              {"device_passes_ms",
               {{"seeds", c.devicePassMs[0]},
                {"projection", c.devicePassMs[1]},
                {"first_marches", c.devicePassMs[2]},
                {"later_rounds", c.devicePassMs[3]}}},
              {"open_marches", c.openMarches},
              {"lost", c.lost},
              {"evaluations", c.evaluations},
              {"ends_traced_on_cpu", c.extended},
              {"vertices_traced_on_cpu", c.extendedVertices},
              {"seconds", c.seconds}}}};
}

json deviceJson(const ink::Context& ctx) { return {{"device", ctx.properties.deviceName}, {"driver", ctx.driverInfo}}; }

json spacingJson(const std::vector<ink::PointRecord>& points) {
    double area = ink::estimateSurfaceArea(points);
    json list = json::array();
    for (double fraction : {1.0, 0.5, 0.25, 0.125}) {
        ink::SpacingStats s = ink::measureSpacing(points, fraction, area);
        list.push_back({{"fraction", fraction},
                        {"points", s.points},
                        {"r_max", s.rMax},
                        {"mean_nn_over_r_max", s.meanNearest},
                        {"min_nn_over_r_max", s.minNearest},
                        {"clumped_fraction", s.clumped}});
    }
    return {{"area_estimate", area}, {"prefixes", list}};
}

}  // namespace inkwell::api
