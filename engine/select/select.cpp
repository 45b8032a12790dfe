// The stipple selection on the device (select.h): the pool sort, then per stage the buckets (count, scan,
// scatter), the covered points ruled out with their orders u, the open points sorted, and eight phases, then
// the ranked output. Every count lives on the device; passes over a pool run as indirect dispatches, so
// nothing returns to the CPU between stages.
#include "select/select.h"

#include "base/common.h"
#include "shared/select.h"

#include <algorithm>
#include <cstddef>

#include "select_bucket.comp.h"
#include "select_cover.comp.h"
#include "select_output.comp.h"
#include "select_phase.comp.h"
#include "select_pool.comp.h"
#include "select_scan.comp.h"
#include "select_setup.comp.h"
#include "select_sort.comp.h"

namespace ink {

namespace {

// The interface with select_*.comp: spirv_shaders/shared/select.h.
using Push = gpu::SelectParams;
using Counts = gpu::SelectCounts;

constexpr uint32_t kPhaseGroup = gpu::PHASE_GROUP_SIZE;  // select_phase.comp's workgroup
constexpr VkDeviceSize kCandidateDispatch = offsetof(Counts, candidateDispatch);
constexpr VkDeviceSize poolDispatch(uint32_t s) {
    return offsetof(Counts, poolDispatch) + sizeof(gpu::uvec4) * VkDeviceSize(s);
}

uint32_t groups(uint64_t n, uint32_t size) { return uint32_t((n + size - 1) / size); }

}  // namespace

void createSelection(Context& ctx, GpuSelection& s, const Surface& hrbf, const RefinePlan& refine,
                     const SelectOptions& options, const Buffer& points, const Buffer& indirect, UploadBatch& uploads,
                     HostMs& host) {
    Stopwatch clock;
    s.plan = planSelection(hrbf, refine, options);
    host.plan += clock.lap();
    const uint64_t candidates = std::max<uint64_t>(1, refine.maxPoints);
    uint64_t buckets = 0;
    for (const SelectStage& st : s.plan.stages) buckets = std::max<uint64_t>(buckets, 8ull * st.bucketsPerPhase);
    const uint64_t scanned = std::max(candidates, buckets) + 1;  // the scan's length, and its total

    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    s.stages = createBuffer(ctx, s.plan.stages.size() * sizeof(SelectStage), storage, MemoryUse::Device);
    uploads.add(s.stages, s.plan.stages.data(), s.plan.stages.size() * sizeof(SelectStage));
    for (Buffer* b : {&s.stageOf, &s.order, &s.pool, &s.entryStage})
        *b = createBuffer(ctx, candidates * 4, storage, MemoryUse::Device);
    s.entryPoints = createBuffer(ctx, candidates * sizeof(PointRecord), storage, MemoryUse::Device);
    s.bucketCount = createBuffer(ctx, scanned * 4, storage, MemoryUse::Device);
    s.bucketStart = createBuffer(ctx, scanned * 4, storage, MemoryUse::Device);
    s.backFill = createBuffer(ctx, buckets * 4, storage, MemoryUse::Device);
    s.blockSums = createBuffer(ctx, (groups(scanned, gpu::GROUP_SIZE) + 1) * 4, storage, MemoryUse::Device);
    s.counts = createBuffer(ctx, sizeof(Counts),
                            storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                            MemoryUse::Device);
    s.stipples = createBuffer(ctx, candidates * sizeof(PointRecord),
                              storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                              MemoryUse::Device);

    const VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    s.descriptors = createDescriptorSet(ctx,
                                        {{gpu::SELECT_STAGES, sb, s.stages.buffer},
                                         {gpu::SELECT_CANDIDATES, sb, points.buffer},
                                         {gpu::SELECT_INDIRECT, sb, indirect.buffer},
                                         {gpu::SELECT_STAGE_OF, sb, s.stageOf.buffer},
                                         {gpu::SELECT_ENTRY_POINTS, sb, s.entryPoints.buffer},
                                         {gpu::SELECT_ORDER, sb, s.order.buffer},
                                         {gpu::SELECT_POOL, sb, s.pool.buffer},
                                         {gpu::SELECT_ENTRY_STAGE, sb, s.entryStage.buffer},
                                         {gpu::SELECT_BUCKET_COUNT, sb, s.bucketCount.buffer},
                                         {gpu::SELECT_BUCKET_START, sb, s.bucketStart.buffer},
                                         {gpu::SELECT_BLOCKS, sb, s.blockSums.buffer},
                                         {gpu::SELECT_COUNTS, sb, s.counts.buffer},
                                         {gpu::SELECT_STIPPLES, sb, s.stipples.buffer},
                                         {gpu::SELECT_BACK_FILL, sb, s.backFill.buffer}},
                                        VK_SHADER_STAGE_COMPUTE_BIT);
    host.buffers += clock.lap();
    s.layout = createPipelineLayout(ctx, s.descriptors.layout, sizeof(Push), VK_SHADER_STAGE_COMPUTE_BIT);
    s.setup = createComputePipeline(ctx, s.layout, spv_select_setup_comp);
    s.poolSort = createComputePipeline(ctx, s.layout, spv_select_pool_comp);
    s.bucket = createComputePipeline(ctx, s.layout, spv_select_bucket_comp);
    s.scan = createComputePipeline(ctx, s.layout, spv_select_scan_comp);
    s.sort = createComputePipeline(ctx, s.layout, spv_select_sort_comp);
    s.cover = createComputePipeline(ctx, s.layout, spv_select_cover_comp);
    s.phase = createComputePipeline(ctx, s.layout, spv_select_phase_comp);
    s.output = createComputePipeline(ctx, s.layout, spv_select_output_comp);
    host.pipelines += clock.lap();
}

void destroySelection(Context& ctx, GpuSelection& s) {
    if (!ctx.device) return;
    for (VkPipeline p : {s.setup, s.poolSort, s.bucket, s.scan, s.sort, s.cover, s.phase, s.output})
        vkDestroyPipeline(ctx.device, p, nullptr);
    vkDestroyPipelineLayout(ctx.device, s.layout, nullptr);
    if (s.descriptors.pool) destroyDescriptorSet(ctx, s.descriptors);
    for (Buffer* b : {&s.stages, &s.stageOf, &s.order, &s.pool, &s.entryPoints, &s.entryStage, &s.bucketCount,
                      &s.bucketStart, &s.backFill, &s.blockSums, &s.counts, &s.stipples})
        if (b->buffer) destroyBuffer(ctx, *b);
    s = GpuSelection{};
}

void recordSelection(VkCommandBuffer cmd, const GpuSelection& s) {
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const auto indirectStage = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
    const auto transfer = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
    const auto rw = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    const auto indirectRead = VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
    const uint32_t stageCount = uint32_t(s.plan.stages.size());
    // Between two passes: the next reads what the last wrote, as storage or as dispatch arguments.
    auto passBarrier = [&] { stageBarrier(cmd, compute, rw, compute | indirectStage, rw | indirectRead); };
    auto dispatch = [&](VkPipeline pipeline, Push push, uint32_t x) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        vkCmdPushConstants(cmd, s.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(cmd, x, 1, 1);
    };
    auto dispatchIndirect = [&](VkPipeline pipeline, Push push, VkDeviceSize offset) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        vkCmdPushConstants(cmd, s.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatchIndirect(cmd, s.counts.buffer, offset);
    };
    // The exclusive scan of bucketCount[0 .. n) into bucketStart (n = 0xFFFFFFFF: the candidates).
    auto scan = [&](uint32_t n, uint32_t stage) {
        Push p{stage, 0, n, stageCount, s.plan.poolSeed};
        if (n == UINT32_MAX)
            dispatchIndirect(s.scan, p, kCandidateDispatch);
        else
            dispatch(s.scan, p, groups(n, gpu::GROUP_SIZE));
        passBarrier();
        p.phase = 1;
        dispatch(s.scan, p, 1);
        passBarrier();
        p.phase = 2;
        if (n == UINT32_MAX)
            dispatchIndirect(s.scan, p, kCandidateDispatch);
        else
            dispatch(s.scan, p, groups(n, gpu::GROUP_SIZE));
        passBarrier();
    };
    auto clear = [&](std::initializer_list<const Buffer*> buffers, VkDeviceSize bytes) {
        stageBarrier(cmd, compute, rw, transfer, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        for (const Buffer* b : buffers) vkCmdFillBuffer(cmd, b->buffer, 0, bytes, 0);
        stageBarrier(cmd, transfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute | indirectStage, rw | indirectRead);
    };

    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s.layout, 0, 1, &s.descriptors.set, 0, nullptr);
    stageBarrier(cmd, compute, rw, transfer, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, s.counts.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, s.stageOf.buffer, 0, VK_WHOLE_SIZE, 0);
    stageBarrier(cmd, transfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute | indirectStage, rw | indirectRead);

    Push push{0, 0, 0, stageCount, s.plan.poolSeed};
    dispatch(s.setup, push, 1);  // the candidates from the refinement's draw
    passBarrier();
    dispatchIndirect(s.poolSort, push, kCandidateDispatch);  // count
    passBarrier();
    push.phase = 1;
    dispatch(s.setup, push, 1);  // pools and their dispatches
    passBarrier();
    dispatchIndirect(s.poolSort, push, kCandidateDispatch);  // scatter
    passBarrier();

    for (uint32_t k = 0; k < stageCount; ++k) {
        const SelectStage& st = s.plan.stages[k];
        const uint32_t buckets = 8 * st.bucketsPerPhase;
        push = {k, 0, 0, stageCount, s.plan.poolSeed};
        clear({&s.bucketCount}, VkDeviceSize(buckets) * 4);
        dispatchIndirect(s.bucket, push, poolDispatch(k));  // count
        passBarrier();
        scan(buckets, k);
        clear({&s.bucketCount, &s.backFill}, VkDeviceSize(buckets) * 4);
        push.phase = 1;
        dispatchIndirect(s.bucket, push, poolDispatch(k));  // scatter
        passBarrier();
        dispatchIndirect(s.cover, push, poolDispatch(k));
        passBarrier();
        dispatch(s.sort, push, groups(buckets, gpu::GROUP_SIZE));
        passBarrier();
        for (uint32_t phase = 0; phase < 8; ++phase) {
            push.phase = phase;
            dispatch(s.phase, push, groups(st.bucketsPerPhase, kPhaseGroup));
            passBarrier();
        }
    }

    push = {0, 2, 0, stageCount, s.plan.poolSeed};
    dispatch(s.setup, push, 1);  // rank offsets, the draw
    passBarrier();
    push.phase = 0;
    dispatchIndirect(s.output, push, kCandidateDispatch);  // flags
    passBarrier();
    scan(UINT32_MAX, 0);
    push.phase = 1;
    dispatchIndirect(s.output, push, kCandidateDispatch);  // the ranked points
}

std::vector<uint32_t> readStageCounts(Context& ctx, const GpuSelection& s) {
    std::vector<uint32_t> added(s.plan.stages.size());
    downloadBuffer(ctx, s.counts, offsetof(Counts, added), added.data(), added.size() * 4);
    return added;
}

}  // namespace ink
