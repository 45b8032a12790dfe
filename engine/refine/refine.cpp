#include "refine/refine.h"

#include "base/common.h"
#include "base/parallel.h"
#include "base/random.h"
#include "select/select.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "compact.comp.h"
#include "refine.comp.h"
#include "refine_global.comp.h"
#include "refine_large.comp.h"
#include "scan.comp.h"

namespace ink {

// hrbf.glsl's uniform blocks (std140, doubles): the header, then the centres, HRBF_BLOCK_SIZE to a 64 KiB
// block, HRBF_BLOCKS blocks (spirv_shaders/shared/refine.h).
constexpr uint32_t kHrbfBlockSize = gpu::HRBF_BLOCK_SIZE, kHrbfBlocks = gpu::HRBF_BLOCKS;
constexpr VkDeviceSize kHrbfBlockBytes = kHrbfBlockSize * sizeof(gpu::HrbfCenter);
static_assert(kHrbfBlockBytes == 65536);
static_assert(kHrbfBlockSize * kHrbfBlocks >= kMaxControlPoints, "room for the largest model (hrbf.h)");

static gpu::HrbfHeader packHrbfHeader(const Hrbf& h) {  // the global fit
    gpu::HrbfHeader header{};
    header.linear = gpu::dvec4(h.a.x(), h.a.y(), h.a.z(), h.b);
    header.count = gpu::uvec4(uint32_t(h.size()), 0, 0, 0);
    return header;
}

static std::vector<gpu::HrbfCenter> packHrbfCenters(const Hrbf& h) {
    size_t blocks = std::max<size_t>(1, (h.size() + kHrbfBlockSize - 1) / kHrbfBlockSize);
    std::vector<gpu::HrbfCenter> data(blocks * kHrbfBlockSize, gpu::HrbfCenter{gpu::dvec4(0.0), gpu::dvec4(0.0)});
    for (size_t j = 0; j < h.size(); ++j) {
        data[j].pAlpha = gpu::dvec4(h.centers[j].x(), h.centers[j].y(), h.centers[j].z(), h.alpha[j]);
        data[j].beta = gpu::dvec4(h.beta[j].x(), h.beta[j].y(), h.beta[j].z(), 0.0);
    }
    return data;
}

// pu_hrbf.glsl's buffers (std140 header, std430 arrays), in float: the header and the patches are
// spirv_shaders/shared/refine.h's structs; the nodes and the far field's centres are vec4 pairs (p, α), (β, 0).
struct PuBuffers {
    gpu::PuHeader header;
    std::vector<gpu::PuPatch> patches;
    std::vector<float> nodes, coarse;
    std::vector<uint32_t> cells;
};

static PuBuffers packPu(const PuHrbf& pu) {
    PuBuffers b;
    const PuGrid& grid = pu.grid;
    uint32_t coarse = uint32_t(pu.coarse.size());
    b.header.origin =
        gpu::vec4(float(grid.origin.x()), float(grid.origin.y()), float(grid.origin.z()), float(1.0 / grid.cell));
    b.header.dims = gpu::uvec4(uint32_t(grid.dims.x()), uint32_t(grid.dims.y()), uint32_t(grid.dims.z()), coarse);
    b.header.coarseLinear =
        gpu::vec4(float(pu.coarse.a.x()), float(pu.coarse.a.y()), float(pu.coarse.a.z()), float(pu.coarse.b));
    b.header.params = gpu::vec4(float(pu.tau), 0.0f, 0.0f, 0.0f);
    b.header.nodes = gpu::uvec4(0u);  // the nodes' address, where they are read by it (createRefinement)
    // Each patch and node into its own slot, on all threads (a scan of 10⁶ points has 7 million nodes).
    b.patches.resize(pu.patches.size());
    parallelChunks(pu.patches.size(), 1 << 14, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
            const PuPatch& p = pu.patches[i];
            b.patches[i] = {gpu::vec4(float(p.center.x()), float(p.center.y()), float(p.center.z()), float(p.radius)),
                            gpu::vec4(float(p.a.x()), float(p.a.y()), float(p.a.z()), float(p.b)),
                            gpu::uvec4(p.first, p.count, 0, 0)};
        }
    });
    b.nodes.resize(8 * pu.nodes.size());
    parallelChunks(pu.nodes.size(), 1 << 15, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
            const PuNode& n = pu.nodes[i];
            const float packed[8] = {float(n.p.x()),    float(n.p.y()),    float(n.p.z()),    float(n.alpha),
                                     float(n.beta.x()), float(n.beta.y()), float(n.beta.z()), 0.0f};
            std::copy(packed, packed + 8, b.nodes.begin() + 8 * i);
        }
    });
    for (size_t j = 0; j < coarse; ++j) {
        const Hrbf& c = pu.coarse;
        b.coarse.insert(b.coarse.end(),
                        {float(c.centers[j].x()), float(c.centers[j].y()), float(c.centers[j].z()), float(c.alpha[j]),
                         float(c.beta[j].x()), float(c.beta[j].y()), float(c.beta[j].z()), 0.0f});
    }
    b.cells = grid.cellStart;
    b.cells.insert(b.cells.end(), grid.cellPatches.begin(), grid.cellPatches.end());
    return b;
}

// A device buffer to hold `data` (at least 16 bytes: empty arrays still need a buffer to bind), its upload added
// to `uploads`.
template <class T>
static Buffer deviceArray(Context& ctx, UploadBatch& uploads, const std::vector<T>& data, VkBufferUsageFlags usage,
                          const char* what) {
    VkDeviceSize bytes = std::max<VkDeviceSize>(16, data.size() * sizeof(T));
    if (bytes > ctx.properties.limits.maxStorageBufferRange)
        throw Error(std::string("the model's ") + what + " take " + std::to_string(bytes >> 20) + " MiB, more than " +
                    ctx.properties.deviceName + " allows in one buffer (" +
                    std::to_string(ctx.properties.limits.maxStorageBufferRange >> 20) + " MiB): fit fewer points");
    Buffer b = createBuffer(ctx, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Device);
    if (!data.empty()) uploads.add(b, data.data(), data.size() * sizeof(T));
    return b;
}

std::vector<DescriptorBinding> puSurfaceBindings(const GpuRefinement& r) {
    const VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    std::vector<DescriptorBinding> bindings = {
        {gpu::REFINE_SURFACE_HEADER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, r.hrbfHeader.buffer},
        {gpu::REFINE_PU_PATCHES, sb, r.puPatches.buffer},
        {gpu::REFINE_PU_CELLS, sb, r.puCells.buffer},
        {gpu::REFINE_PU_COARSE, sb, r.puCoarse.buffer}};
    if (!r.nodesByAddress) bindings.push_back({gpu::REFINE_PU_NODES, sb, r.puNodes.buffer});
    return bindings;
}

void createRefinement(Context& ctx, GpuRefinement& r, const Surface& hrbf, const RefineOptions& options) {
    const uint64_t range = ctx.properties.limits.maxStorageBufferRange;
    const uint64_t groups = ctx.properties.limits.maxComputeWorkGroupCount[0];
    uint64_t maxPoints = std::min(range / sizeof(PointRecord), groups * kGroupSize);
    r.options = options;
    Stopwatch clock;
    r.plan = planRefinement(hrbf, options, maxPoints);
    r.hostMs.plan += clock.lap();
    const RefinePlan& plan = r.plan;
    uint64_t maxCandidates = *std::max_element(plan.maxCandidates.begin(), plan.maxCandidates.end());

    const VkBufferUsageFlags storage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    const bool global = hrbf.method == FitMethod::Global;
    uint32_t realBlocks = 0;
    UploadBatch uploads(ctx);  // submitted below, before what it copies from goes
    gpu::HrbfHeader header{};
    std::vector<gpu::HrbfCenter> centers;
    PuBuffers b;
    std::vector<gpu::PuHeader> puHeader;
    if (global) {
        if (!ctx.float64)
            throw Error(std::string(ctx.properties.deviceName) +
                        " lacks shaderFloat64 (or it is not enabled), which the global fit's evaluation needs; the "
                        "default --fit pu evaluates in float");
        const Hrbf& h = hrbf.global;
        if (h.size() > kHrbfBlockSize * kHrbfBlocks)
            throw Error("the refinement holds at most " + std::to_string(kHrbfBlockSize * kHrbfBlocks) + " centres");
        if (ctx.properties.limits.maxUniformBufferRange < kHrbfBlockBytes)
            throw Error(std::string(ctx.properties.deviceName) +
                        " has uniform buffers under 64 KiB, which the global HRBF needs");
        const VkBufferUsageFlags uniform = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        header = packHrbfHeader(h);
        centers = packHrbfCenters(h);
        r.hrbfHeader = createBuffer(ctx, sizeof(header), uniform, MemoryUse::Device);
        uploads.add(r.hrbfHeader, &header, sizeof(header));
        r.hrbf = createBuffer(ctx, centers.size() * sizeof(gpu::HrbfCenter), uniform, MemoryUse::Device);
        uploads.add(r.hrbf, centers.data(), centers.size() * sizeof(gpu::HrbfCenter));
        // Blocks past the last real one point at block 0: they are declared by the shader but never read.
        realBlocks = uint32_t(centers.size() / kHrbfBlockSize);
    } else {
        b = packPu(hrbf.pu);
        puHeader = {b.header};
        // The memory the model and the points take, against the device's largest heap, before any is allocated:
        // the model's arrays, the refinement's points (32 bytes), candidates (32) and their flags (4), and the
        // selection's per-point arrays (two of 32 bytes, four of 4; its buckets, a few per stage, are left out).
        const uint64_t modelBytes =
            b.patches.size() * sizeof(gpu::PuPatch) + (b.nodes.size() + b.coarse.size() + b.cells.size()) * 4;
        const uint64_t need = modelBytes + plan.maxPoints * sizeof(PointRecord) +
                              maxCandidates * (sizeof(PointRecord) + 4) +
                              (options.selects() ? plan.maxPoints * (2 * sizeof(PointRecord) + 16) : 0);
        VkDeviceSize heap = 0;
        for (uint32_t i = 0; i < ctx.memoryProperties.memoryHeapCount; ++i)
            if (ctx.memoryProperties.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
                heap = std::max(heap, ctx.memoryProperties.memoryHeaps[i].size);
        if (heap && need > heap)
            throw Error("the model and its points need " + std::to_string(need >> 20) +
                        " MiB of device memory, more than " + ctx.properties.deviceName + " has (" +
                        std::to_string(heap >> 20) + " MiB): fit fewer points");
        const VkBufferUsageFlags sbo = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        r.puPatches = deviceArray(ctx, uploads, b.patches, sbo, "patches");
        // The nodes, by far the largest array (a scan of 10⁶ points: 222 MiB), by device address when they outgrow
        // a storage buffer's range: then only the device's largest buffer (and allocation) limits them.
        const VkDeviceSize nodeBytes = std::max<VkDeviceSize>(16, b.nodes.size() * sizeof(float));
        r.nodesByAddress = options.nodesByAddress || nodeBytes > ctx.properties.limits.maxStorageBufferRange;
        if (!r.nodesByAddress) {
            r.puNodes = deviceArray(ctx, uploads, b.nodes, sbo, "patch nodes");
        } else {
            if (!ctx.bufferDeviceAddress)
                throw Error(
                    "the model's patch nodes take " + std::to_string(nodeBytes >> 20) + " MiB, more than " +
                    ctx.properties.deviceName + " allows in one storage buffer (" +
                    std::to_string(ctx.properties.limits.maxStorageBufferRange >> 20) +
                    " MiB), and bufferDeviceAddress, which reads larger ones, is not enabled: fit fewer points");
            if (nodeBytes > ctx.maxBufferSize)
                throw Error("the model's patch nodes take " + std::to_string(nodeBytes >> 20) + " MiB, more than " +
                            ctx.properties.deviceName + " allows in one buffer (" +
                            std::to_string(ctx.maxBufferSize >> 20) + " MiB): fit fewer points");
            r.puNodes = createBuffer(ctx, nodeBytes,
                                     VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     MemoryUse::Device);
            uploads.add(r.puNodes, b.nodes.data(), b.nodes.size() * sizeof(float));
            const VkDeviceAddress address = bufferAddress(ctx, r.puNodes);
            puHeader[0].nodes = gpu::uvec4(uint32_t(address), uint32_t(address >> 32), 0, 0);
        }
        r.hrbfHeader = deviceArray(ctx, uploads, puHeader, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "header");
        r.puCells = deviceArray(ctx, uploads, b.cells, sbo, "patch grid");
        r.puCoarse = deviceArray(ctx, uploads, b.coarse, sbo, "far field");
    }
    r.points = createBuffer(ctx, plan.maxPoints * sizeof(PointRecord),
                            storage | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, MemoryUse::Device);
    r.candidates = createBuffer(ctx, maxCandidates * sizeof(PointRecord), storage, MemoryUse::Device);
    r.flags = createBuffer(ctx, maxCandidates * 4, storage, MemoryUse::Device);
    r.blocks = createBuffer(ctx, (maxCandidates + kGroupSize - 1) / kGroupSize * 4, storage, MemoryUse::Device);
    r.levels = createBuffer(ctx, kMaxLevels * sizeof(gpu::LevelInfo), storage, MemoryUse::Device);
    r.indirect =
        createBuffer(ctx, sizeof(gpu::IndirectArgs), storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, MemoryUse::Device);
    std::vector<Eigen::Vector4f> seeds(plan.seeds.size());
    for (size_t i = 0; i < seeds.size(); ++i) seeds[i] << plan.seeds[i], float(i);
    r.seeds = createBuffer(ctx, seeds.size() * 16, storage, MemoryUse::Device);
    uploads.add(r.seeds, seeds.data(), seeds.size() * 16);

    const VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, ub = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    std::vector<DescriptorBinding> bindings = {{gpu::REFINE_SURFACE_HEADER, ub, r.hrbfHeader.buffer},
                                               {gpu::REFINE_POINTS, sb, r.points.buffer},
                                               {gpu::REFINE_CANDIDATES, sb, r.candidates.buffer},
                                               {gpu::REFINE_FLAGS, sb, r.flags.buffer},
                                               {gpu::REFINE_BLOCKS, sb, r.blocks.buffer},
                                               {gpu::REFINE_LEVELS, sb, r.levels.buffer},
                                               {gpu::REFINE_INDIRECT, sb, r.indirect.buffer},
                                               {gpu::REFINE_SEEDS, sb, r.seeds.buffer}};
    if (global)
        bindings.push_back({gpu::REFINE_HRBF_CENTERS, ub, r.hrbf.buffer, kHrbfBlocks, kHrbfBlockBytes, realBlocks});
    else
        bindings.insert(bindings.end(), {{gpu::REFINE_PU_PATCHES, sb, r.puPatches.buffer},
                                         {gpu::REFINE_PU_CELLS, sb, r.puCells.buffer},
                                         {gpu::REFINE_PU_COARSE, sb, r.puCoarse.buffer}});
    if (!global && !r.nodesByAddress) bindings.push_back({gpu::REFINE_PU_NODES, sb, r.puNodes.buffer});
    r.descriptors = createDescriptorSet(ctx, bindings, VK_SHADER_STAGE_COMPUTE_BIT);
    r.hostMs.buffers += clock.lap();
    r.layout = createPipelineLayout(ctx, r.descriptors.layout, sizeof(LevelParams), VK_SHADER_STAGE_COMPUTE_BIT);
    r.refine = global             ? createComputePipeline(ctx, r.layout, spv_refine_global_comp)
               : r.nodesByAddress ? createComputePipeline(ctx, r.layout, spv_refine_large_comp)
                                  : createComputePipeline(ctx, r.layout, spv_refine_comp);
    r.scan = createComputePipeline(ctx, r.layout, spv_scan_comp);
    r.compact = createComputePipeline(ctx, r.layout, spv_compact_comp);

    VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    query.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query.queryCount = plan.levelCount + 2;  // the start, each level's end, the selection's end
    VK_CHECK(vkCreateQueryPool(ctx.device, &query, nullptr, &r.timestamps));
    r.hostMs.pipelines += clock.lap();

    if (options.selects()) {
        r.selection = new GpuSelection;
        createSelection(ctx, *r.selection, hrbf, plan, selectOptions(options), r.points, r.indirect, uploads, r.hostMs);
        clock.lap();  // counted there
    }
    uploads.submit();  // every upload of the refinement and its selection: one submission
    r.hostMs.buffers += clock.lap();
}

Refinement::Refinement(Context& ctx, const Surface& hrbf, const RefineOptions& options) : ctx_(ctx) {
    try {
        createRefinement(ctx, r_, hrbf, options);
    } catch (...) {
        destroyRefinement(ctx, r_);
        throw;
    }
}

const Buffer& GpuRefinement::drawnPoints() const { return selection ? selection->stipples : points; }

void destroyRefinement(Context& ctx, GpuRefinement& r) {
    if (!ctx.device) return;
    if (r.selection) {
        destroySelection(ctx, *r.selection);
        delete r.selection;
        r.selection = nullptr;
    }
    vkDestroyQueryPool(ctx.device, r.timestamps, nullptr);
    for (VkPipeline p : {r.refine, r.scan, r.compact}) vkDestroyPipeline(ctx.device, p, nullptr);
    vkDestroyPipelineLayout(ctx.device, r.layout, nullptr);
    if (r.descriptors.pool) destroyDescriptorSet(ctx, r.descriptors);
    for (Buffer* b : {&r.hrbfHeader, &r.hrbf, &r.points, &r.candidates, &r.flags, &r.blocks, &r.levels, &r.indirect,
                      &r.seeds, &r.puPatches, &r.puNodes, &r.puCells, &r.puCoarse})
        if (b->buffer) destroyBuffer(ctx, *b);
    r.refine = r.scan = r.compact = VK_NULL_HANDLE;
    r.layout = VK_NULL_HANDLE;
    r.timestamps = VK_NULL_HANDLE;
}

void recordRefinement(Context&, VkCommandBuffer cmd, GpuRefinement& r) {
    const RefinePlan& plan = r.plan;
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const auto rw = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    const auto indirectStage = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;

    // Level 0's counts and dispatch come from the host; later levels' are written by the scan pass.
    gpu::LevelInfo levels[kMaxLevels] = {};
    gpu::IndirectArgs indirect{};
    levels[0].candidates = uint32_t(plan.seeds.size());
    indirect.dispatches[0] = gpu::uvec4((levels[0].candidates + kGroupSize - 1) / kGroupSize, 1, 1, 0);
    vkCmdUpdateBuffer(cmd, r.levels.buffer, 0, sizeof(levels), levels);
    // The dispatches and the refinement's draw; the selection writes its own.
    vkCmdUpdateBuffer(cmd, r.indirect.buffer, 0, GpuRefinement::kSelectedDrawOffset, &indirect);
    stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute | indirectStage,
                 rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);

    vkCmdResetQueryPool(cmd, r.timestamps, 0, plan.levelCount + 2);
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, r.timestamps, 0);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r.layout, 0, 1, &r.descriptors.set, 0, nullptr);
    for (uint32_t level = 0; level < plan.levelCount; ++level) {
        LevelParams params = levelParams(plan, r.options, level);
        vkCmdPushConstants(cmd, r.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params), &params);
        VkDeviceSize dispatch = offsetof(gpu::IndirectArgs, dispatches) + sizeof(gpu::uvec4) * level;

        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r.refine);
        vkCmdDispatchIndirect(cmd, r.indirect.buffer, dispatch);
        stageBarrier(cmd, compute, rw, compute, rw);

        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r.scan);
        vkCmdDispatch(cmd, 1, 1, 1);
        stageBarrier(cmd, compute, rw, compute | indirectStage, rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);

        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r.compact);
        vkCmdDispatchIndirect(cmd, r.indirect.buffer, dispatch);
        stageBarrier(cmd, compute, rw, compute, rw);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, r.timestamps, level + 1);
    }
    if (r.selection) recordSelection(cmd, *r.selection);
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, r.timestamps, plan.levelCount + 1);
    // Who reads the results: the renderer's compute passes (the points as uniform texels, the counts as
    // storage), indirect commands, and copies (readback, the renderer's setup). A caller recording more work into
    // the same command buffer, with no fence wait between, relies on this barrier.
    stageBarrier(cmd, compute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 compute | indirectStage | VK_PIPELINE_STAGE_2_COPY_BIT,
                 VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
                     VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
}

// One submission for all levels. While it runs, the CPU only polls the per-level timestamps (never waits
// between levels) to show progress on a terminal.
void runRefinement(Context& ctx, GpuRefinement& r) {
    Stopwatch clock;
    VkCommandBuffer cmd = beginOneTime(ctx);
    recordRefinement(ctx, cmd, r);
    Progress progress("refine", r.plan.levelCount + 1);  // the levels, then the selection
    const uint32_t queries = r.plan.levelCount + 2;
    std::vector<uint64_t> available(2 * queries);
    endOneTime(ctx, cmd, [&] {
        if (vkGetQueryPoolResults(ctx.device, r.timestamps, 0, queries, available.size() * 8, available.data(), 16,
                                  VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT) < 0)
            return;
        uint32_t done = 0;
        while (done + 1 < queries && available[2 * (done + 1) + 1]) ++done;
        progress.update(done);
    });
    progress.update(r.plan.levelCount + 1);
    r.hostMs.run = clock.lap();
}

double selectionMs(Context& ctx, GpuRefinement& r) {
    uint64_t ticks[2] = {};
    if (!r.selection ||
        vkGetQueryPoolResults(ctx.device, r.timestamps, r.plan.levelCount, 2, sizeof(ticks), ticks, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) != VK_SUCCESS)
        return 0;
    return double(ticks[1] - ticks[0]) * ctx.properties.limits.timestampPeriod * 1e-6;
}

std::vector<LevelStats> readLevelStats(Context& ctx, GpuRefinement& r) {
    std::vector<gpu::LevelInfo> info(kMaxLevels);
    downloadBuffer(ctx, r.levels, 0, info.data(), kMaxLevels * sizeof(gpu::LevelInfo));
    std::vector<uint64_t> ticks(r.plan.levelCount + 1, 0);
    VkResult q =
        vkGetQueryPoolResults(ctx.device, r.timestamps, 0, uint32_t(ticks.size()), ticks.size() * sizeof(uint64_t),
                              ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
    std::vector<LevelStats> stats(r.plan.levelCount);
    for (uint32_t level = 0; level < r.plan.levelCount; ++level) {
        stats[level].level = level;
        stats[level].candidates = info[level].candidates;
        stats[level].kept = info[level].kept;
        for (uint32_t k = 0; k < DropReasonCount; ++k) stats[level].dropped[k] = info[level].dropped[k];
        if (q == VK_SUCCESS)
            stats[level].gpuMs = double(ticks[level + 1] - ticks[level]) * ctx.properties.limits.timestampPeriod * 1e-6;
    }
    return stats;
}

std::vector<PointRecord> readDrawnPoints(Context& ctx, GpuRefinement& r) {
    if (!r.selection) return readPoints(ctx, r);
    uint32_t draw[4];
    downloadBuffer(ctx, r.indirect, GpuRefinement::kSelectedDrawOffset, draw, sizeof(draw));
    std::vector<PointRecord> points(draw[0]);
    downloadBuffer(ctx, r.selection->stipples, 0, points.data(), points.size() * sizeof(PointRecord));
    return points;
}

uint32_t readPointCount(Context& ctx, GpuRefinement& r) {
    uint32_t count = 0;
    downloadBuffer(ctx, r.indirect, GpuRefinement::kDrawOffset, &count, sizeof(count));
    return count;
}

std::vector<PointRecord> readPoints(Context& ctx, GpuRefinement& r) {
    uint32_t draw[4];
    downloadBuffer(ctx, r.indirect, GpuRefinement::kDrawOffset, draw, sizeof(draw));
    std::vector<PointRecord> points(draw[0]);
    downloadBuffer(ctx, r.points, VkDeviceSize(draw[2]) * sizeof(PointRecord), points.data(),
                   points.size() * sizeof(PointRecord));
    return points;
}

}  // namespace ink
