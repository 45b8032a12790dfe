// The CPU reference of the stipple selection (select_*.comp): the same pools, cells, phases, priorities and
// float arithmetic, so that it selects exactly the device's points. Within a phase the cells are independent,
// so the device's one-thread-per-bucket order and this file's one global priority order decide the same.
//
// Built with -ffp-contract=off (CMakeLists.txt): the shaders mark these expressions `precise`, so neither side
// fuses a multiply and an add, and every comparison sees the same bits.
#include "base/random.h"
#include "select/select_math.h"
#include "select/select_plan.h"

#include <algorithm>
#include <unordered_map>

namespace ink {

namespace {

struct CellHash {
    size_t operator()(const CellKey& c) const { return cellHash(c); }
};

}  // namespace

std::vector<PointRecord> selectOnCpu(const std::vector<PointRecord>& candidates, const SelectPlan& plan,
                                     std::vector<uint32_t>* addedOut) {
    const uint32_t n = uint32_t(candidates.size());
    const uint32_t stages = uint32_t(plan.stages.size());
    std::vector<uint32_t> stageOf(n, 0);  // 1 + the stage that selected the point; 0: not selected
    std::vector<float> order(n, 0.0f);    // u(p)
    std::vector<uint32_t> keys(n), added(stages, 0);
    for (uint32_t p = 0; p < n; ++p) keys[p] = poolKey(plan.poolSeed, p);

    for (uint32_t k = 0; k < stages; ++k) {
        const SelectStage& s = plan.stages[k];
        std::vector<uint32_t> pool;
        for (uint32_t p = 0; p < n; ++p)
            if (inPool(keys[p], s)) pool.push_back(p);
        std::unordered_map<CellKey, std::vector<uint32_t>, CellHash> cells;
        std::vector<CellKey> cellOf(n);
        for (uint32_t p : pool) {
            cellOf[p] = cellOfPoint(candidates[p].position, s);
            cells[cellOf[p]].push_back(p);
        }
        // Calls visit(q) for every pool point q ≠ p in the 27 cells around p's.
        auto forNeighbours = [&](uint32_t p, auto&& visit) {
            const CellKey& c = cellOf[p];
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        auto it = cells.find({c.x + dx, c.y + dy, c.z + dz});
                        if (it == cells.end()) continue;
                        for (uint32_t q : it->second)
                            if (q != p) visit(q);
                    }
        };
        std::vector<uint32_t> phase[8];
        for (uint32_t p : pool)
            if (!stageOf[p]) phase[cellPhase(cellOf[p])].push_back(p);
        for (auto& list : phase) {
            std::sort(list.begin(), list.end(), [&](uint32_t a, uint32_t b) {
                return priorityBefore(stagePriority(s, a), a, stagePriority(s, b), b);
            });
            for (uint32_t p : list) {
                bool free = true;
                forNeighbours(p, [&](uint32_t q) {
                    if (stageOf[q] && sameSideDistance2(candidates[p], candidates[q]) < s.radius2) free = false;
                });
                if (free) stageOf[p] = k + 1, ++added[k];
            }
        }
        // Order the points this stage added: farthest from the earlier stages' first.
        for (uint32_t p : pool) {
            if (stageOf[p] != k + 1) continue;
            if (k == 0) {
                order[p] = firstStageOrder(s, p);
                continue;
            }
            float best = INFINITY;
            forNeighbours(p, [&](uint32_t q) {
                if (stageOf[q] && stageOf[q] <= k)
                    best = std::min(best, sameSideDistance2(candidates[p], candidates[q]));
            });
            order[p] = additionOrder(s, best);
        }
    }

    std::vector<uint32_t> before(stages + 1, 0);
    for (uint32_t k = 0; k < stages; ++k) before[k + 1] = before[k] + added[k];
    const uint32_t total = before[stages];
    std::vector<PointRecord> out;
    out.reserve(total);
    for (uint32_t p = 0; p < n; ++p) {
        if (!stageOf[p]) continue;
        PointRecord r = candidates[p];
        uint32_t k = stageOf[p] - 1;
        r.tone = stippleRank(before[k], added[k], total, order[p]);
        out.push_back(r);
    }
    if (addedOut) *addedOut = added;
    return out;
}

}  // namespace ink
