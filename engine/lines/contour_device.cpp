// The occluding contour traced on the device (contour_device.h): contour_seeds.comp and contour_trace.comp.
#include "lines/contour_device.h"

#include "base/common.h"
#include "base/point_hash.h"
#include "refine/refine.h"
#include "shared/contour.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>
#include <tuple>

#include "contour_seeds.comp.h"
#include "contour_trace.comp.h"
#include "contour_trace_large.comp.h"

namespace ink {

using Eigen::Vector3d;

std::vector<ChainedCurve> chainMarches(const std::vector<ContourMarch>& input,
                                       const std::vector<ContourNodeInfo>& nodes, const std::vector<Vector3d>& points,
                                       const std::vector<Vector3d>& normals, double merge) {
    constexpr uint32_t kNone = ContourMarch::kNoNode;
    const uint32_t n = uint32_t(nodes.size());
    // Each node stands for the first node within `merge` of it on the same line (flipped when their tangents
    // are opposite); its marches become that node's.
    std::vector<uint32_t> rep(n);
    std::vector<bool> flip(n, false);
    {
        PointHash near(merge);
        for (uint32_t k = 0; k < n; ++k) {
            rep[k] = k;
            uint32_t found = kNone;
            near.forEachNear(nodes[k].position, merge, [&](uint32_t j) {
                if (found == kNone && std::abs(nodes[j].tangent.dot(nodes[k].tangent)) > 0.7) found = j;
            });
            if (found != kNone) {
                rep[k] = rep[found];
                flip[k] = flip[found] != (nodes[found].tangent.dot(nodes[k].tangent) < 0);
            } else {
                near.add(nodes[k].position, nodes[k].normal, k, 0);
            }
        }
    }
    std::vector<ContourMarch> marches;
    for (ContourMarch m : input) {
        if (m.from >= n || (m.to != kNone && m.to >= n)) continue;
        m.fromForward = m.fromForward != flip[m.from];
        m.from = rep[m.from];
        if (m.to != kNone) {
            m.toForward = m.toForward != flip[m.to];
            m.to = rep[m.to];
            if (m.to == m.from && m.count < 4) continue;  // from one of two merged nodes to the other
        }
        marches.push_back(m);
    }
    // Port 2k is node k's forward end, 2k + 1 its backward one.
    auto portOf = [](uint32_t node, bool forward) { return 2 * node + (forward ? 0u : 1u); };
    std::vector<uint32_t> order(marches.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return std::tie(marches[a].backward, marches[a].count) < std::tie(marches[b].backward, marches[b].count);
    });
    std::vector<uint32_t> portMarch(2 * size_t(n), kNone);
    for (uint32_t i : order) {
        const ContourMarch& m = marches[i];
        const uint32_t a = portOf(m.from, m.fromForward);
        if (portMarch[a] != kNone) continue;
        if (m.to != kNone) {
            const uint32_t b = portOf(m.to, m.toForward);
            if (b == a || portMarch[b] != kNone) continue;
            portMarch[b] = i;
        }
        portMarch[a] = i;
    }
    // The rest of a march that lost its ports is a stretch another march traces too: drawn, it would be a second
    // copy, a scrap of its own (whose visibility, decided along that scrap alone, flickers where the first copy is
    // hidden: specks on the armadillo). It goes too, and what went on from its end, in turn.
    std::vector<uint32_t> members(n, 0);
    for (uint32_t k = 0; k < n; ++k) ++members[rep[k]];
    for (bool dropped = true; dropped;) {
        dropped = false;
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t out = portOf(k, true), i = portMarch[out];
            if (!nodes[k].continuation || members[k] != 1 || rep[k] != k || i == kNone) continue;
            if (portMarch[portOf(k, false)] != kNone || marches[i].from != k || !marches[i].fromForward) continue;
            if (marches[i].to != kNone) portMarch[portOf(marches[i].to, marches[i].toForward)] = kNone;
            portMarch[out] = kNone;
            dropped = true;
        }
    }

    // Appends march i's vertices to c, walked from `port` (one of its ends); returns the port at its other end
    // (kNone when it ends in the open).
    auto walk = [&](ChainedCurve& c, uint32_t i, uint32_t port) {
        const ContourMarch& m = marches[i];
        const uint32_t a = portOf(m.from, m.fromForward);
        if (port == a) {
            c.points.insert(c.points.end(), points.begin() + m.first, points.begin() + m.first + m.count);
            c.normals.insert(c.normals.end(), normals.begin() + m.first, normals.begin() + m.first + m.count);
            return m.to == kNone ? kNone : portOf(m.to, m.toForward);
        }
        c.points.push_back(nodes[m.to].position);
        c.normals.push_back(nodes[m.to].normal);
        for (uint32_t v = m.count; v-- > 1;) {
            c.points.push_back(points[m.first + v]);
            c.normals.push_back(normals[m.first + v]);
        }
        return a;
    };
    std::vector<ChainedCurve> curves;
    std::vector<bool> visited(n, false);
    // From node s out of port `leave` (its other port is an end, or the start of a closed curve).
    auto follow = [&](uint32_t s, uint32_t leave, ChainedCurve c) {
        uint32_t port = leave;
        for (;;) {
            const uint32_t node = port / 2;
            visited[node] = true;
            const uint32_t i = portMarch[port];
            if (i == kNone) {  // an end
                c.points.push_back(nodes[node].position);
                c.normals.push_back(nodes[node].normal);
                break;
            }
            const uint32_t other = walk(c, i, port);
            if (other == kNone) break;  // ended in the open
            if (other / 2 == s && other == (leave ^ 1u)) {
                c.closed = true;
                break;
            }
            if (visited[other / 2]) break;  // (cannot happen: every port takes one march)
            port = other ^ 1u;
        }
        if (!c.points.empty()) curves.push_back(std::move(c));
    };
    for (uint32_t s = 0; s < n; ++s) visited[s] = rep[s] != s;
    for (uint32_t s = 0; s < n; ++s)
        for (uint32_t end : {portOf(s, true), portOf(s, false)}) {
            if (visited[s]) break;
            const uint32_t i = portMarch[end];
            ChainedCurve c;
            if (i != kNone) {
                // A march that leaves this port and ends in the open is an end too: its vertices come first,
                // reversed.
                const ContourMarch& m = marches[i];
                if (m.to != kNone || portOf(m.from, m.fromForward) != end) continue;
                for (uint32_t v = m.count; v-- > 1;) {
                    c.points.push_back(points[m.first + v]);
                    c.normals.push_back(normals[m.first + v]);
                }
            }
            follow(s, end ^ 1u, std::move(c));
        }
    for (uint32_t s = 0; s < n; ++s)  // what is left are closed curves
        if (!visited[s]) follow(s, portOf(s, true), {});
    return curves;
}

namespace {

const VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr double kCellSteps = 6;
// The trace's start, then the ends of the seeds, the projection, the first round of marches, the later rounds.
constexpr uint32_t kTimestamps = 5;
constexpr double kProjectSteps = 8;
constexpr double kMergeSteps = 0.05;  // nodes nearer than this are one (chainMarches)  // a seed moves at most this far
                                      // onto the contour (about 20 pixels)
static_assert(kCellSteps >= gpu::CONTOUR_LONGEST_STEP + gpu::CONTOUR_MEET_STEPS,
              "a node a march meets must lie in the cells around its step's end");

}  // namespace

bool DeviceContours::supports(const GpuRefinement& r) { return r.partitionOfUnity(); }

DeviceContours::DeviceContours(Context& ctx, const GpuRefinement& r, uint32_t samples, const ContourOptions& options)
    : ctx_(ctx), refinement_(r), samples_(samples), options_(options) {
    if (!supports(r)) throw Error("the device traces the contour of a partition-of-unity fit only");
    try {
        // Seeds: a slot per drawn point at most (a few in the band, fewer cells); nodes: one per seed cell at most.
        seedSlots_ = std::bit_ceil(std::max(1024u, std::min(samples, 1u << 24)));
        nodeCapacity_ = std::max(256u, std::min(samples, 1u << 20));
        // The march passes take two subgroups a node, groupItems_ a workgroup: their workgroups must stay within
        // the device's dispatch limit (lavapipe's is 65,535).
        groupItems_ = std::max(1u, gpu::CONTOUR_GROUP_SIZE / std::max(1u, ctx.maxSubgroupSize));
        const uint64_t mostGroups = ctx.properties.limits.maxComputeWorkGroupCount[0];
        nodeCapacity_ = uint32_t(std::min<uint64_t>(nodeCapacity_, (mostGroups - 1) * groupItems_ / 2));
        gridSlots_ = std::bit_ceil(2 * nodeCapacity_);
        // Each march takes room for CONTOUR_MARCH_VERTICES and uses a few on average (the bunny: 8); every seed
        // marches both ways in round 0. Room for 1,200,000 vertices (38 MB): the first marches of 12,500 seeds (the
        // bunny's default view has 372, the armadillo's 1,242); assimp's 2CylinderEngine.glb, 322,000 vertices
        // traced, fits. Not the CPU's limit times four (128 MB on the device and as much to read back, for every
        // contour traced).
        vertexCapacity_ = uint32_t(
            std::min<uint64_t>({1200000, 2 * uint64_t(options.maxTotalVertices),
                                uint64_t(ctx.properties.limits.maxStorageBufferRange) / sizeof(gpu::ContourVertex)}));
        const auto dst = VK_BUFFER_USAGE_TRANSFER_DST_BIT, src = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
        seedTable_ =
            createBuffer(ctx, VkDeviceSize(seedSlots_) * gpu::CONTOUR_SEED_SLOT * 4, kStorage | dst, MemoryUse::Device);
        grid_ = createBuffer(ctx, VkDeviceSize(gridSlots_) * (gpu::CONTOUR_GRID_NODES + 1) * 4, kStorage | dst,
                             MemoryUse::Device);
        nodes_ = createBuffer(ctx, VkDeviceSize(nodeCapacity_) * sizeof(gpu::ContourNode), kStorage | src,
                              MemoryUse::Device);
        vertices_ = createBuffer(ctx, VkDeviceSize(vertexCapacity_) * sizeof(gpu::ContourVertex), kStorage | src,
                                 MemoryUse::Device);
        list_ = createBuffer(ctx, VkDeviceSize(seedSlots_) * 16, kStorage, MemoryUse::Device);
        counters_ = createBuffer(ctx, sizeof(gpu::ContourCounters),
                                 kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | dst | src, MemoryUse::Device);
        readback_ =
            createBuffer(ctx, nodes_.size + vertices_.size + sizeof(gpu::ContourCounters), dst, MemoryUse::Readback);

        const VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        std::vector<DescriptorBinding> bindings = puSurfaceBindings(r);
        bindings.insert(bindings.end(), {{gpu::CONTOUR_SAMPLES, sb, r.drawnPoints().buffer},
                                         {gpu::CONTOUR_SEEDS, sb, seedTable_.buffer},
                                         {gpu::CONTOUR_NODES, sb, nodes_.buffer},
                                         {gpu::CONTOUR_GRID, sb, grid_.buffer},
                                         {gpu::CONTOUR_VERTICES, sb, vertices_.buffer},
                                         {gpu::CONTOUR_COUNTERS, sb, counters_.buffer},
                                         {gpu::CONTOUR_LIST, sb, list_.buffer}});
        descriptors_ = createDescriptorSet(ctx, bindings, VK_SHADER_STAGE_COMPUTE_BIT);
        layout_ =
            createPipelineLayout(ctx, descriptors_.layout, sizeof(gpu::ContourParams), VK_SHADER_STAGE_COMPUTE_BIT);
        seeds_ = createComputePipeline(ctx, layout_, spv_contour_seeds_comp);
        trace_ = createComputePipeline(ctx, layout_,
                                       r.nodesByAddress ? std::span<const uint32_t>(spv_contour_trace_large_comp)
                                                        : std::span<const uint32_t>(spv_contour_trace_comp));
        VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        query.queryType = VK_QUERY_TYPE_TIMESTAMP;
        query.queryCount = kTimestamps;
        VK_CHECK(vkCreateQueryPool(ctx.device, &query, nullptr, &timestamps_));
    } catch (...) {
        release();
        throw;
    }
}

DeviceContours::~DeviceContours() { release(); }

void DeviceContours::release() {
    if (!ctx_.device) return;
    vkDestroyQueryPool(ctx_.device, timestamps_, nullptr);
    for (VkPipeline p : {seeds_, trace_}) vkDestroyPipeline(ctx_.device, p, nullptr);
    vkDestroyPipelineLayout(ctx_.device, layout_, nullptr);
    if (descriptors_.pool) destroyDescriptorSet(ctx_, descriptors_);
    for (Buffer* b : {&seedTable_, &nodes_, &grid_, &vertices_, &counters_, &list_, &readback_})
        if (b->buffer) destroyBuffer(ctx_, *b);
    timestamps_ = VK_NULL_HANDLE;
    seeds_ = trace_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
}

std::vector<PenStroke> DeviceContours::trace(const Surface& surface, const Vector3d& eye, ContourStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    ContourStats s;
    s.onDevice = true;
    const double step = options_.step;
    gpu::ContourParams params{};
    params.eye = gpu::vec4(float(eye.x()), float(eye.y()), float(eye.z()), float(step));
    // Cells of six steps: a node every few steps along the curve where the seeds are dense, and every node a
    // march can meet within the 27 cells around its step's end (a step is at most CONTOUR_LONGEST_STEP, and
    // meets a node within CONTOUR_MEET_STEPS of it).
    params.sizes = gpu::vec4(float(kCellSteps * step), float(kProjectSteps * step), 0.0f, 0.0f);
    params.counts = gpu::uvec4(samples_, seedSlots_, gridSlots_, 0);
    params.limits = gpu::uvec4(nodeCapacity_, vertexCapacity_, 0, gpu::CONTOUR_ROUNDS);
    // A subgroup a seed or a march: a workgroup holds at least this many (subgroups of the largest size).
    params.shape.x = groupItems_;
    const uint32_t sampleGroups = (samples_ + gpu::CONTOUR_GROUP_SIZE - 1) / gpu::CONTOUR_GROUP_SIZE;
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const auto rw = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

    submitAndWait(ctx_, [&](VkCommandBuffer cmd) {
        vkCmdResetQueryPool(cmd, timestamps_, 0, kTimestamps);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, timestamps_, 0);
        vkCmdFillBuffer(cmd, seedTable_.buffer, 0, VK_WHOLE_SIZE, gpu::CONTOUR_NONE);
        vkCmdFillBuffer(cmd, grid_.buffer, 0, VK_WHOLE_SIZE, gpu::CONTOUR_NONE);
        gpu::ContourCounters zero{};
        zero.march = zero.project = gpu::uvec4(0, 1, 1, 0);
        vkCmdUpdateBuffer(cmd, counters_.buffer, 0, sizeof(zero), &zero);
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute, rw);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &descriptors_.set, 0, nullptr);
        auto pass = [&](VkPipeline pipeline, uint32_t which) {
            params.counts.w = which;
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
            vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params), &params);
        };
        pass(seeds_, gpu::CONTOUR_PASS_CELLS);
        vkCmdDispatch(cmd, sampleGroups, 1, 1);
        stageBarrier(cmd, compute, rw, compute, rw);
        pass(seeds_, gpu::CONTOUR_PASS_PICK);
        vkCmdDispatch(cmd, sampleGroups, 1, 1);
        stageBarrier(cmd, compute, rw, compute, rw);
        pass(seeds_, gpu::CONTOUR_PASS_PAIR);
        vkCmdDispatch(cmd, (seedSlots_ + gpu::CONTOUR_GROUP_SIZE - 1) / gpu::CONTOUR_GROUP_SIZE, 1, 1);
        stageBarrier(cmd, compute, rw, compute | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                     rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
        vkCmdWriteTimestamp2(cmd, compute, timestamps_, 1);
        pass(trace_, gpu::CONTOUR_PASS_PROJECT);
        vkCmdDispatchIndirect(cmd, counters_.buffer, offsetof(gpu::ContourCounters, project));
        stageBarrier(cmd, compute, rw, compute | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                     rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
        vkCmdWriteTimestamp2(cmd, compute, timestamps_, 2);
        // Round 0: every seed node marches forward and backward; then the nodes each round's marches left where
        // they stopped march on. Before each round, the nodes made since the last enter the grid (each round's
        // marches see the same).
        for (uint32_t round = 0; round < gpu::CONTOUR_ROUNDS; ++round) {
            params.limits.z = round;
            for (uint32_t p : {gpu::CONTOUR_PASS_ENTER, gpu::CONTOUR_PASS_MARCH}) {
                pass(trace_, p);
                vkCmdDispatchIndirect(cmd, counters_.buffer, offsetof(gpu::ContourCounters, march));
                stageBarrier(cmd, compute, rw, compute | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                             rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
            }
            if (round == 0) vkCmdWriteTimestamp2(cmd, compute, timestamps_, 3);
        }
        vkCmdWriteTimestamp2(cmd, compute, timestamps_, 4);
        stageBarrier(cmd, compute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferCopy copy{0, 0, sizeof(gpu::ContourCounters)};
        vkCmdCopyBuffer(cmd, counters_.buffer, readback_.buffer, 1, &copy);
    });
    gpu::ContourCounters counters;
    std::memcpy(&counters, readback_.mapped, sizeof(counters));
    uint64_t ticks[kTimestamps] = {};
    if (vkGetQueryPoolResults(ctx_.device, timestamps_, 0, kTimestamps, sizeof(ticks), ticks, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS) {
        const double ms = ctx_.properties.limits.timestampPeriod * 1e-6;
        s.deviceMs = double(ticks[4] - ticks[0]) * ms;
        for (int k = 0; k < 4; ++k) s.devicePassMs[k] = double(ticks[k + 1] - ticks[k]) * ms;
    }
    auto tooRough = [&](const std::string& what) {
        return Error("the contour of this view passed " + what +
                     ": the surface is too rough to draw lines on (a noisy fit?); draw dots instead, or fit fewer "
                     "points (--control-points)");
    };
    if (counters.vertices > vertexCapacity_)
        throw tooRough("the device's room for " + std::to_string(vertexCapacity_) + " vertices");
    if (counters.nodes > nodeCapacity_) throw tooRough(std::to_string(nodeCapacity_) + " nodes");

    // The marches, read back: the nodes' links and the vertices they wrote.
    const uint32_t nodeCount = counters.nodes, vertexCount = counters.vertices;
    const VkDeviceSize nodeBytes = VkDeviceSize(nodeCount) * sizeof(gpu::ContourNode),
                       vertexBytes = VkDeviceSize(vertexCount) * sizeof(gpu::ContourVertex);
    if (nodeCount > 0)
        submitAndWait(ctx_, [&](VkCommandBuffer cmd) {
            VkBufferCopy n{0, 0, nodeBytes}, v{0, nodeBytes, vertexBytes};
            vkCmdCopyBuffer(cmd, nodes_.buffer, readback_.buffer, 1, &n);
            if (vertexBytes) vkCmdCopyBuffer(cmd, vertices_.buffer, readback_.buffer, 1, &v);
        });
    const auto* node = static_cast<const gpu::ContourNode*>(readback_.mapped);
    const auto* vertex =
        reinterpret_cast<const gpu::ContourVertex*>(static_cast<const char*>(readback_.mapped) + nodeBytes);
    // The nodes in the order of their positions: the device numbers them as its invocations come (atomically),
    // and what is made of them must not depend on that.
    std::vector<uint32_t> order(nodeCount), rank(nodeCount);
    for (uint32_t k = 0; k < nodeCount; ++k) order[k] = k;
    auto key = [&](uint32_t k) {
        const gpu::ContourNode& d = node[k];
        return std::tuple(d.position.x, d.position.y, d.position.z, d.tangent.x, d.tangent.y, d.tangent.z);
    };
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    // (Nodes at one place, which a march may meet either of, are one in chainMarches.)
    for (uint32_t r = 0; r < nodeCount; ++r) rank[order[r]] = r;
    std::vector<ContourMarch> marches;
    std::vector<ContourNodeInfo> nodes(nodeCount);
    for (uint32_t r = 0; r < nodeCount; ++r) {
        const gpu::ContourNode& d = node[order[r]];
        nodes[r] = {Vector3d(d.position.x, d.position.y, d.position.z), Vector3d(d.normal.x, d.normal.y, d.normal.z),
                    Vector3d(d.tangent.x, d.tangent.y, d.tangent.z), d.state.x > 0};
        for (bool forward : {true, false}) {
            const gpu::uvec4& link = forward ? d.forward : d.backward;
            if (link.z == 0) continue;  // no march from this port
            ContourMarch m;
            m.from = r;
            m.fromForward = forward;
            m.to = link.x < nodeCount ? rank[link.x] : ContourMarch::kNoNode;
            m.toForward = (link.w & gpu::CONTOUR_AT_FORWARD) != 0;
            m.first = link.y;
            m.count = link.z;
            m.backward = !forward || d.state.y != 0;
            marches.push_back(m);
            if (!(link.w & gpu::CONTOUR_MET)) ++s.openMarches;
        }
    }
    std::vector<Vector3d> points(vertexCount), normals(vertexCount);
    for (uint32_t v = 0; v < vertexCount; ++v) {
        points[v] = Vector3d(vertex[v].position.x, vertex[v].position.y, vertex[v].position.z);
        normals[v] = Vector3d(vertex[v].normal.x, vertex[v].normal.y, vertex[v].normal.z);
    }
    s.seedsTried = nodeCount;
    s.evaluations = counters.evaluations;
    s.lost = counters.lost;

    std::vector<ChainedCurve> curves = chainMarches(marches, nodes, points, normals, kMergeSteps * step);

    // The ends float left open (a march stuck where ∇g's tangential part nearly vanishes): traced on from there on
    // the CPU, in double, until they run into a traced curve (extendContour).
    PointHash traced(step);
    std::vector<double> lengths(curves.size(), 0.0);
    const bool anyOpen = std::any_of(curves.begin(), curves.end(), [](const ChainedCurve& c) { return !c.closed; });
    auto enter = [&](uint32_t i, const std::vector<Vector3d>& p, size_t from, double arc) {
        for (size_t v = from; v < p.size(); ++v) {
            if (v > 0) arc += (p[v] - p[v - 1]).norm();
            traced.add(p[v], curves[i].normals[v], i, arc);
        }
        return arc;
    };
    for (uint32_t i = 0; anyOpen && i < curves.size(); ++i) lengths[i] = enter(i, curves[i].points, 0, 0.0);
    for (uint32_t i = 0; anyOpen && i < curves.size(); ++i) {
        ChainedCurve& c = curves[i];
        if (c.closed || c.points.size() < 2) continue;
        for (bool tail : {true, false}) {
            const size_t m = c.points.size();
            const Vector3d end = tail ? c.points[m - 1] : c.points[0];
            const Vector3d direction = tail ? c.points[m - 1] - c.points[m - 2] : c.points[0] - c.points[1];
            const std::vector<Vector3d> more = extendContour(surface, eye, end, direction, traced, i,
                                                             tail ? lengths[i] : 0.0, tail ? 1.0 : -1.0, options_);
            if (more.empty()) continue;
            ++s.extended;
            s.extendedVertices += more.size();
            std::vector<Vector3d> moreNormals(more.size());
            for (size_t v = 0; v < more.size(); ++v) {
                Vector3d g;
                surface.eval(more[v], g);
                moreNormals[v] = g.normalized();
            }
            if (tail) {
                c.points.insert(c.points.end(), more.begin(), more.end());
                c.normals.insert(c.normals.end(), moreNormals.begin(), moreNormals.end());
            } else {
                c.points.insert(c.points.begin(), more.rbegin(), more.rend());
                c.normals.insert(c.normals.begin(), moreNormals.rbegin(), moreNormals.rend());
            }
            // (The new points joined the hash, beyond the curve's arc: the end facing this one across the gap stops
            // at them instead of tracing the gap again.)
            if (tail)
                for (size_t v = 0; v < more.size(); ++v) lengths[i] += (more[v] - (v == 0 ? end : more[v - 1])).norm();
        }
        // Closed when the ends now meet.
        if (c.points.size() >= 4 && (c.points.front() - c.points.back()).norm() < 1.5 * step) c.closed = true;
    }

    std::vector<PenStroke> pieces;
    uint32_t curveId = 0;
    for (const ChainedCurve& c : curves) {
        if (droppedLoop(c.points, c.closed, eye, options_)) {
            s.smallLoops += c.points.size() >= 4;
            continue;
        }
        ++s.curves;
        s.closedCurves += c.closed;
        s.vertices += c.points.size();
        splitAtCusps(c.points, c.normals, c.closed, eye, options_, curveId++, pieces, s);
    }
    s.pieces = pieces.size();
    s.occluded = markOccluded(surface, eye, kOccludedSteps * options_.step, pieces);
    s.seconds = secondsSince(start);
    if (stats) *stats = s;
    return pieces;
}

}  // namespace ink
