// The occluding contour traced on the device, for every view (docs/lines.md): the drawn points nearest the contour
// seed it, one a cell (the least |n·v|), all projected onto it at once into nodes; then every node marches along
// the curve at once (predictor–corrector steps on the partition of unity, in float) until it meets the next node.
// The host reads the marches back (one copy of what they wrote), follows the links into curves (chainMarches),
// and splits them at their cusps as the CPU tracer does (splitAtCusps). The CPU tracer (lines.h) is its twin in
// tests: both find the same curve.
#pragma once

#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "lines/lines.h"

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ink {

struct GpuRefinement;

// One march as read back: from node `from`'s forward or backward port (fromForward) to a port of node `to` (kNoNode
// when it met none and ends in the open); its vertices are [first, first + count) of the arrays chainMarches takes,
// the starting node's own position first, the met node's not included.
struct ContourMarch {
    static constexpr uint32_t kNoNode = 0xFFFFFFFFu;
    uint32_t from = 0;
    bool fromForward = true;
    uint32_t to = kNoNode;
    bool toForward = false;
    uint32_t first = 0, count = 0;
    // A seed's backward march, or a march on from where such a march stopped: it runs against the curve's
    // orientation, over stretches a forward march may trace too. Ports go to forward marches first.
    bool backward = false;
};

struct ContourNodeInfo {
    Eigen::Vector3d position, normal, tangent;
    // A node a march left where it stopped (too long): that march arrived at its backward port, and its own march
    // from its forward port is the rest of it.
    bool continuation = false;
};

struct ChainedCurve {
    std::vector<Eigen::Vector3d> points, normals;
    bool closed = false;
};

// Joins the marches into curves. Each node has two ports, and each port takes one march: the shortest of those
// that start or end there (two marches between the same ports are one stretch of curve traced from both ends; a
// march that passed a node without meeting it is longer than the one from that node), the forward ones first (a
// backward march that a forward one's would take over piece by piece must not leave the pieces after the first
// without the march that led to them: ends in the middle of a curve). The march on from a continuation node goes
// when the march that stopped there lost its ports (a second copy of a stretch another march traces). Then the
// curves are followed from port to port: open ones from each free port (or a march that ended in the open), closed
// ones round the rest.
// First, nodes within `merge` of each other on one line (seeds projected to nearly one point: float leaves the
// contour's position uncertain along g's small gradient) are one node, so that marches meeting either meet the
// same ports.
std::vector<ChainedCurve> chainMarches(const std::vector<ContourMarch>& marches,
                                       const std::vector<ContourNodeInfo>& nodes,
                                       const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<Eigen::Vector3d>& normals, double merge);

class DeviceContours {
public:
    // Whether the device traces this refinement's surface: the partition of unity (a global fit, evaluated in
    // double, is traced on the CPU).
    static bool supports(const GpuRefinement& refinement);

    // Buffers and pipelines for seeds from the first `samples` drawn points of `refinement`, which must outlive it.
    DeviceContours(Context& ctx, const GpuRefinement& refinement, uint32_t samples, const ContourOptions& options);
    ~DeviceContours();
    DeviceContours(const DeviceContours&) = delete;
    DeviceContours& operator=(const DeviceContours&) = delete;

    // The contour seen from `eye` (normalized coordinates), in pieces between cusps as traceContours gives them.
    // Throws ink::Error past options.maxTotalVertices. Submits and waits.
    // `surface` is the refinement's: the open ends are traced on from on the CPU (extendContour).
    std::vector<PenStroke> trace(const Surface& surface, const Eigen::Vector3d& eye, ContourStats* stats = nullptr);

    const GpuRefinement& refinement() const { return refinement_; }
    uint32_t samples() const { return samples_; }

private:
    void release();

    Context& ctx_;
    const GpuRefinement& refinement_;
    const uint32_t samples_;
    const ContourOptions options_;
    uint32_t seedSlots_ = 0, gridSlots_ = 0, nodeCapacity_ = 0, vertexCapacity_ = 0;
    uint32_t groupItems_ = 1;  // seeds or marches a workgroup traces (ContourParams::shape.x)
    Buffer seedTable_, nodes_, grid_, vertices_, counters_, list_, readback_;
    DescriptorSet descriptors_;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline seeds_ = VK_NULL_HANDLE, trace_ = VK_NULL_HANDLE;
    VkQueryPool timestamps_ = VK_NULL_HANDLE;
};

}  // namespace ink
