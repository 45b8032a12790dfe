// The hatching's cross field solved on the device (cross_field_device.h): cross_field.comp.
#include "lines/cross_field_device.h"

#include "base/common.h"
#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "refine/refine.h"
#include "shared/cross_field.h"

#include <algorithm>
#include <cstring>
#include <span>

#include "cross_field.comp.h"
#include "cross_field_large.comp.h"

namespace ink {

using Eigen::Vector3d;

bool solvesCrossFieldOnDevice(const GpuRefinement& r) { return r.partitionOfUnity(); }

namespace {

// The bytes of the two largest buffers: the graph's words, and the state (or the directions, as large).
VkDeviceSize graphBytes(const CrossFieldGraph& g) {
    return 4 * (VkDeviceSize(g.k + 2) * g.points() + 1 + g.children.size());
}
VkDeviceSize stateBytes(const CrossFieldGraph& g) { return VkDeviceSize(2) * g.points() * sizeof(gpu::vec4); }

// What one solve makes, released however it ends.
struct FieldResources {
    Context& ctx;
    Buffer samples, graph, state, directions, readback;
    DescriptorSet descriptors;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkQueryPool timestamps = VK_NULL_HANDLE;

    explicit FieldResources(Context& c) : ctx(c) {}
    FieldResources(const FieldResources&) = delete;
    FieldResources& operator=(const FieldResources&) = delete;
    ~FieldResources() {
        vkDestroyQueryPool(ctx.device, timestamps, nullptr);
        vkDestroyPipeline(ctx.device, pipeline, nullptr);
        vkDestroyPipelineLayout(ctx.device, layout, nullptr);
        if (descriptors.pool) destroyDescriptorSet(ctx, descriptors);
        for (Buffer* b : {&samples, &graph, &state, &directions, &readback})
            if (b->buffer) destroyBuffer(ctx, *b);
    }
};

}  // namespace

bool crossFieldFitsDevice(const Context& ctx, const CrossFieldGraph& graph) {
    return std::max(graphBytes(graph), stateBytes(graph)) <= ctx.properties.limits.maxStorageBufferRange;
}

CrossFieldSolution solveCrossFieldOnDevice(Context& ctx, const GpuRefinement& r,
                                           const std::vector<SurfaceSample>& samples, const CrossFieldGraph& graph,
                                           const CrossFieldOptions& options, double* deviceMs) {
    if (!solvesCrossFieldOnDevice(r)) throw Error("the device solves the cross field of a partition-of-unity fit only");
    const uint32_t m = uint32_t(samples.size()), total = graph.points(), k = graph.k;
    if (graph.levels() == 0 || graph.levelStart[1] != m)
        throw Error("a cross field's graph does not match its samples");
    CrossFieldSolution solution;
    if (m == 0) return solution;

    // The graph as the shader reads it (shared/cross_field.h): neighbours, parents, child starts, children.
    std::vector<uint32_t> words;
    words.reserve(size_t(k + 2) * total + 1 + graph.children.size());
    words.insert(words.end(), graph.neighbours.begin(), graph.neighbours.end());
    words.insert(words.end(), graph.parent.begin(), graph.parent.end());
    words.insert(words.end(), graph.childStart.begin(), graph.childStart.end());
    words.insert(words.end(), graph.children.begin(), graph.children.end());
    std::vector<gpu::vec4> points(2 * size_t(m));
    for (uint32_t i = 0; i < m; ++i) {
        const Vector3d &p = samples[i].position, &n = samples[i].normal;
        points[2 * i] = gpu::vec4(float(p.x()), float(p.y()), float(p.z()), 0.0f);
        points[2 * i + 1] = gpu::vec4(float(n.x()), float(n.y()), float(n.z()), 0.0f);
    }
    if (!crossFieldFitsDevice(ctx, graph))
        throw Error("the cross field's " + std::to_string(m) + " samples need " +
                    std::to_string(std::max(graphBytes(graph), stateBytes(graph)) >> 20) +
                    " MiB in one buffer, more than " + ctx.properties.deviceName + " allows (" +
                    std::to_string(ctx.properties.limits.maxStorageBufferRange >> 20) + " MiB)");
    const VkDeviceSize stateSize = stateBytes(graph), graphSize = VkDeviceSize(words.size()) * 4;

    FieldResources res(ctx);
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, dst = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             src = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    res.samples = createBuffer(ctx, points.size() * sizeof(gpu::vec4), storage | dst, MemoryUse::Device);
    res.graph = createBuffer(ctx, std::max<VkDeviceSize>(graphSize, 16), storage | dst, MemoryUse::Device);
    res.state = createBuffer(ctx, stateSize, storage | src, MemoryUse::Device);
    res.directions = createBuffer(ctx, stateSize, storage | src, MemoryUse::Device);
    // Read back: the samples' (normal, confidence), seeds and directions.
    const VkDeviceSize sampleBytes = VkDeviceSize(m) * sizeof(gpu::vec4);
    res.readback = createBuffer(ctx, 3 * sampleBytes, dst, MemoryUse::Readback);
    UploadBatch upload(ctx);
    upload.add(res.samples, points.data(), points.size() * sizeof(gpu::vec4));
    upload.add(res.graph, words.data(), graphSize);
    upload.submit();

    const VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    std::vector<DescriptorBinding> bindings = puSurfaceBindings(r);
    bindings.insert(bindings.end(), {{gpu::FIELD_SAMPLES, sb, res.samples.buffer},
                                     {gpu::FIELD_GRAPH, sb, res.graph.buffer},
                                     {gpu::FIELD_STATE, sb, res.state.buffer},
                                     {gpu::FIELD_DIRECTIONS, sb, res.directions.buffer}});
    res.descriptors = createDescriptorSet(ctx, bindings, VK_SHADER_STAGE_COMPUTE_BIT);
    res.layout =
        createPipelineLayout(ctx, res.descriptors.layout, sizeof(gpu::FieldParams), VK_SHADER_STAGE_COMPUTE_BIT);
    res.pipeline = createComputePipeline(ctx, res.layout,
                                         r.nodesByAddress ? std::span<const uint32_t>(spv_cross_field_large_comp)
                                                          : std::span<const uint32_t>(spv_cross_field_comp));
    VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    query.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query.queryCount = 2;
    VK_CHECK(vkCreateQueryPool(ctx.device, &query, nullptr, &res.timestamps));

    gpu::FieldParams params{};
    params.counts = gpu::uvec4(total, k, m, 0);
    params.options = gpu::vec4(float(options.fidelity), float(options.featureSize), 0.0f, 0.0f);
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const auto rw = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    uint32_t half = 0;  // the half of the directions that holds the current ones
    submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        vkCmdResetQueryPool(cmd, res.timestamps, 0, 2);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, res.timestamps, 0);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, res.pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, res.layout, 0, 1, &res.descriptors.set, 0,
                                nullptr);
        // One pass over level l's points, then a barrier before the next reads what it wrote.
        auto pass = [&](size_t l, uint32_t which) {
            const uint32_t begin = graph.levelStart[l], end = graph.levelStart[l + 1];
            params.range = gpu::uvec4(begin, end, which, half);
            vkCmdPushConstants(cmd, res.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params), &params);
            vkCmdDispatch(cmd, (end - begin + gpu::FIELD_GROUP_SIZE - 1) / gpu::FIELD_GROUP_SIZE, 1, 1);
            stageBarrier(cmd, compute, rw, compute, rw);
        };
        const size_t levels = graph.levels(), coarsest = levels - 1;
        pass(0, gpu::FIELD_PASS_SEED);
        for (size_t l = 1; l < levels; ++l) pass(l, gpu::FIELD_PASS_RESTRICT);
        pass(coarsest, gpu::FIELD_PASS_START);
        auto smooth = [&](size_t l, uint32_t sweeps) {
            for (uint32_t s = 0; s < sweeps; ++s) {
                pass(l, gpu::FIELD_PASS_SMOOTH);
                half = 1 - half;
            }
        };
        smooth(coarsest, options.coarseSweeps);
        for (size_t l = coarsest; l-- > 0;) {
            pass(l, gpu::FIELD_PASS_PROLONG);
            smooth(l, options.fineSweeps);
        }
        vkCmdWriteTimestamp2(cmd, compute, res.timestamps, 1);
        stageBarrier(cmd, compute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT);
        const VkBufferCopy state[2] = {{0, 0, sampleBytes},
                                       {VkDeviceSize(total) * sizeof(gpu::vec4), sampleBytes, sampleBytes}};
        vkCmdCopyBuffer(cmd, res.state.buffer, res.readback.buffer, 2, state);
        const VkBufferCopy directions{VkDeviceSize(half) * total * sizeof(gpu::vec4), 2 * sampleBytes, sampleBytes};
        vkCmdCopyBuffer(cmd, res.directions.buffer, res.readback.buffer, 1, &directions);
    });
    uint64_t ticks[2] = {};
    if (deviceMs && vkGetQueryPoolResults(ctx.device, res.timestamps, 0, 2, sizeof(ticks), ticks, sizeof(uint64_t),
                                          VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS)
        *deviceMs = double(ticks[1] - ticks[0]) * ctx.properties.limits.timestampPeriod * 1e-6;

    const auto* out = static_cast<const gpu::vec4*>(res.readback.mapped);
    auto vector = [](const gpu::vec4& v) { return Vector3d(v.x, v.y, v.z); };
    solution.normals.resize(m);
    solution.principal.resize(m);
    solution.directions.resize(m);
    solution.confidence.resize(m);
    for (uint32_t i = 0; i < m; ++i) {
        solution.normals[i] = vector(out[i]).normalized();
        solution.confidence[i] = out[i].w;
        solution.principal[i] = vector(out[m + i]);
        solution.directions[i] = vector(out[2 * m + i]);
    }
    return solution;
}

}  // namespace ink
