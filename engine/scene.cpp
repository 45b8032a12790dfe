// Scene (scene.h): the model's point sets, made and replaced as one.
#include "scene.h"

#include <chrono>

namespace ink {

const char* drawStyleName(DrawStyle s) {
    return s == DrawStyle::Stipple ? "stipple" : s == DrawStyle::Direction ? "direction" : "both";
}

Scene::Scene(Context& c, Model m, DrawStyle style, const RefineOptions& options) : ctx(c), model(std::move(m)) {
    refine(style, options);
}

void Scene::refine(DrawStyle style, const RefineOptions& options) {
    vkDeviceWaitIdle(ctx.device);
    sets.clear();
    std::vector<SampleStyle> styles;
    if (style != DrawStyle::Direction) styles.push_back(SampleStyle::Stipple);
    if (style != DrawStyle::Stipple) styles.push_back(SampleStyle::Direction);
    auto start = std::chrono::steady_clock::now();
    for (SampleStyle sampling : styles) {
        RefineOptions r = options;
        r.style = sampling;
        sets.push_back(std::make_unique<Refinement>(ctx, model.hrbf, r));
        runRefinement(ctx, sets.back()->gpu());
    }
    refineSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<const GpuRefinement*> Scene::pointers() const {
    std::vector<const GpuRefinement*> p;
    for (const auto& s : sets) p.push_back(&s->gpu());
    return p;
}

uint64_t Scene::points() {
    uint64_t total = 0;
    for (auto& s : sets)
        for (const LevelStats& l : readLevelStats(ctx, s->gpu())) total += l.kept;
    return total;
}

}  // namespace ink
