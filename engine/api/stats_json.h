// The figures the command line's --stats and bench write, as JSON (docs/usage.md, "Stats JSON"): one function an
// engine object, so that the library writes what it measured and the apps only place it.
#pragma once

#include "draw/renderer.h"
#include "draw/scene.h"
#include "gpu/context.h"
#include "refine/point_record.h"
#include "refine/refine.h"
#include "surface/model.h"
#include "vector/vector.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace inkwell::api {

using nlohmann::json;

json fitJson(const ink::Model& m);
// The refinements' host milliseconds (bench's refine_host_ms, render's refine.host_ms).
json hostMsJson(const ink::HostMs& h);
json levelsJson(const std::vector<ink::LevelStats>& levels);
json deviceJson(const ink::Context& ctx);
// A plot's layers: pen, name, paths and vertices before and after simplifying and merging, pen-up travel
// before and after ordering, pen-down length in mm, lifts and the estimated plot time; the pens and the time
// model.
json plotJson(const ink::Plot& plot);
// The pen lines traced: strokes, vertices, lengths and times.
json linesJson(const ink::Scene& scene);
// The last frame's stipples on the page, one object a point set (docs/usage.md, Stats JSON: `stipples`): the
// front dots drawn, how many larger, the outline's dots, and ink::measurePage's windows of 128 output pixels.
json pageJson(const ink::OffscreenRenderer& renderer, size_t sets, const ink::RenderStyle& style, uint32_t width,
              uint32_t height);
// Spacing of a ranked point set: the whole set and its prefixes 1/2, 1/4, 1/8, the area estimated from it.
json spacingJson(const std::vector<ink::PointRecord>& points);

}  // namespace inkwell::api
