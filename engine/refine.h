// Point sets on the HRBF surface (report §4, §6.2): seeds, then refinement levels of stippling or direction
// sampling, each child projected onto f = 0. The GPU path records every level into one command buffer with
// barriers between passes (no CPU round trip); the CPU reference (refine_cpu.cpp) follows the same rules
// and the same random numbers.
#pragma once

#include "hrbf.h"
#include "pipelines.h"
#include "point_record.h"
#include "resources.h"

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace ink {

enum class SampleStyle { Stipple, Direction };
enum class DirectionField { Axis, CurvatureMin, CurvatureMax };
enum class SeedMode { ControlPoints, Grid };
// What a stippling refinement draws: the stipples selected from its points with blue-noise spacing and
// progressive ranks (select.h), or all its points with the report's random tone values.
enum class Distribution { BlueNoise, Refinement };

struct RefineOptions {
    SampleStyle style = SampleStyle::Stipple;
    DirectionField direction = DirectionField::Axis;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitY();  // for DirectionField::Axis, in model coordinates
    uint32_t levels = 4;                              // refinement levels after the seed level (level 0)
    // Independent sets of level-1 children of the seeds (the seeds are not repeated); 0: the default, 1 for the
    // blue-noise selection's candidates, the report's 2 otherwise.
    uint32_t passes = 0;
    uint32_t seed = 1;
    double rho0 = 0;  // ρ₀ in normalized units (diagonal 1); 0 = half the mean seed spacing
    // ρ of each level over the next's: the report's 3, or 0 for the default: 3 for the report's look, 2 for the
    // blue-noise selection's candidates (four children at half the spacing keep an even density; a third leaves
    // gaps that no later level fills, see docs/algorithm.md).
    double rhoDivisor = 0;
    SeedMode seeds = SeedMode::ControlPoints;
    uint32_t grid = 32;  // cells along the longest box side for SeedMode::Grid
    double eps1 = 1e-5;  // ε₁, as a fraction of the diagonal
    double eps2 = 1e-6;  // ε₂
    double delta = 0.5;  // δ
    double phi = 0.25;   // φ
    uint32_t maxIterations = 32;
    double jumpFactor = 3.0;  // drop a child that ends farther than jumpFactor·ρ from its parent
    bool keepAllLevels = true;
    Distribution distribution = Distribution::BlueNoise;  // stippling only; direction sampling draws its points
    float candidatesPerStipple = 4.0f;  // for BlueNoise: the selection keeps about one candidate in this many
    bool selects() const { return style == SampleStyle::Stipple && distribution == Distribution::BlueNoise; }
};

constexpr uint32_t kMaxLevels = 16;  // MAX_LEVELS in common.glsl: seeds + 15 refinement levels
constexpr uint32_t kGroupSize = 256;

enum DropReason : uint32_t { DropGradient, DropArmijo, DropIterations, DropJump, DropReasonCount };
const char* dropReasonName(uint32_t reason);

struct LevelStats {
    uint32_t level = 0;
    uint32_t candidates = 0;
    uint32_t kept = 0;
    std::array<uint32_t, DropReasonCount> dropped{};
    double gpuMs = 0;  // from timestamp queries; 0 on the CPU backend
};

// Seed positions (normalized) and the per-level plan derived from the options.
struct RefinePlan {
    std::vector<Eigen::Vector3f> seeds;
    float seedJumpLimit = 0;              // level 0: how far a seed may move while projected
    double gridCell = 0;                  // the seed grid's cell side for SeedMode::Grid, else 0
    double rho0 = 0;                      // resolved ρ₀
    double rhoDivisor = 3;                // ρ of level k+1 is ρ of level k over this
    uint32_t passes = 1;                  // resolved RefineOptions::passes
    uint32_t levelCount = 0;              // seed level + refinement levels
    std::vector<uint32_t> childCount;     // per level: 1 for seeds, 4 stippling, 2 direction
    std::vector<uint64_t> maxCandidates;  // per level, worst case
    uint64_t maxPoints = 0;               // all levels, worst case
};

// The squared distance from points[i] to the nearest other point (a brute-force scan: for the few thousand
// control points).
double nearestSquaredDistance(const std::vector<Eigen::Vector3d>& points, size_t i);

// Throws ink::Error when the request is out of bounds (levels, a point count that cannot fit `maxPoints`).
RefinePlan planRefinement(const Hrbf& hrbf, const RefineOptions& options, uint64_t maxPoints);

// The push constants of the refinement passes (Params in refine_bindings.glsl), shared with the CPU reference.
struct LevelParams {
    float axis[4];
    float rho, jumpLimit, eps1, eps2, delta, phi;
    uint32_t maxIterations, mode, direction, level, seed, childCount, nextChildCount, keepAll;
    float toneOffset, toneScale;  // this level's share of [0,1) for the tone value, coarse levels first
    uint32_t passChildren;        // children of one pass: childCount / passChildren passes at level 1
};
static_assert(sizeof(LevelParams) == 84);
LevelParams levelParams(const RefinePlan& plan, const RefineOptions& options, uint32_t level);
double levelRho(const RefinePlan& plan, uint32_t level);  // ρ of a level: 0 for the seeds, ρ₀ for level 1

struct GpuSelection;  // select.h

// Device resources of one refinement, and of the stipple selection that follows it when the options select
// (RefineOptions::selects). drawnPoints() and drawOffset() are what the renderer reads.
struct GpuRefinement {
    RefinePlan plan;
    RefineOptions options;
    Buffer hrbfHeader, hrbf, points, candidates, flags, blocks, levels, indirect, seeds;
    DescriptorSet descriptors;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline refine = VK_NULL_HANDLE, scan = VK_NULL_HANDLE, compact = VK_NULL_HANDLE;
    VkQueryPool timestamps = VK_NULL_HANDLE;
    GpuSelection* selection = nullptr;                            // owned; null when every refined point is drawn
    static constexpr VkDeviceSize kDrawOffset = 16 * kMaxLevels;  // the refinement's VkDrawIndirectCommand
    static constexpr VkDeviceSize kSelectedDrawOffset = kDrawOffset + 16;  // the selection's

    // The points drawn: the selected stipples (rank in `tone`), or the refined points.
    const Buffer& drawnPoints() const;
    VkDeviceSize drawOffset() const { return selection ? kSelectedDrawOffset : kDrawOffset; }
};

void createRefinement(Context& ctx, GpuRefinement& r, const Hrbf& hrbf, const RefineOptions& options);
void destroyRefinement(Context& ctx, GpuRefinement& r);

// Owns one GpuRefinement: created in the constructor (what was made is released when that throws), destroyed
// with the owner.
class Refinement {
public:
    Refinement(Context& ctx, const Hrbf& hrbf, const RefineOptions& options);
    ~Refinement() { destroyRefinement(ctx_, r_); }
    Refinement(const Refinement&) = delete;
    Refinement& operator=(const Refinement&) = delete;

    GpuRefinement& gpu() { return r_; }
    const GpuRefinement& gpu() const { return r_; }

private:
    Context& ctx_;
    GpuRefinement r_;
};
// Records every level: refine → scan → compact per level, synchronization2 barriers between them, then the
// selection; ends with a barrier that makes the points and draw arguments visible to compute shaders (as
// storage and as uniform texels), indirect commands and copies.
void recordRefinement(Context& ctx, VkCommandBuffer cmd, GpuRefinement& r);
// Records, submits and waits: the whole refinement in one submission.
void runRefinement(Context& ctx, GpuRefinement& r);
std::vector<LevelStats> readLevelStats(Context& ctx, GpuRefinement& r);
// Milliseconds the stipple selection took on the device (timestamps); 0 without one.
double selectionMs(Context& ctx, GpuRefinement& r);
// The refined points (all levels, or the last), in point-buffer order: the selection's candidates.
std::vector<PointRecord> readPoints(Context& ctx, GpuRefinement& r);
uint32_t readPointCount(Context& ctx, GpuRefinement& r);  // how many, without reading them
// The points the renderer draws: the selected stipples in candidate order, or the refined points.
std::vector<PointRecord> readDrawnPoints(Context& ctx, GpuRefinement& r);

// The CPU reference backend: the same plan, rules and random numbers, on all hardware threads.
std::vector<PointRecord> refineOnCpu(const Hrbf& hrbf, const RefineOptions& options, const RefinePlan& plan,
                                     std::vector<LevelStats>* stats = nullptr, unsigned threads = 0);

}  // namespace ink
