// The refinement's options and plan (report §4, §6.2), and each level's rules: what both backends follow, the
// device (refine.h) and the CPU reference (refineOnCpu). No Vulkan here.
#pragma once

#include "refine/point_record.h"
#include "shared/refine.h"  // the refinement device side (spirv_shaders/shared/)
#include "surface/surface.h"

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
    // The device reads the partition of unity's nodes by address (refine_large.comp) when they outgrow a storage
    // buffer's range, or always with this set: tests compare the two paths on small models.
    bool nodesByAddress = false;
    bool selects() const { return style == SampleStyle::Stipple && distribution == Distribution::BlueNoise; }
};

// Host time of making and running a refinement with its selection, in milliseconds (bench's `refine_host_ms`):
// the plans, buffers with their uploads, pipelines (the driver's shader compiles), and the submission of all
// levels and the selection until its fence (the device's own time is in the timestamps).
struct HostMs {
    double plan = 0, buffers = 0, pipelines = 0, run = 0;
    HostMs& operator+=(const HostMs& o) {
        plan += o.plan, buffers += o.buffers, pipelines += o.pipelines, run += o.run;
        return *this;
    }
};

constexpr uint32_t kMaxLevels = gpu::MAX_LEVELS;  // seeds + 15 refinement levels
// ρ₀ is 0 (the default: half the seed spacing) or a fraction of the diagonal in (0, 1]; NaN, negative and
// larger values are refused (above 1 every child would be dropped).
inline bool validRho(double rho0) { return rho0 == 0 || (rho0 > 0 && rho0 <= 1); }
constexpr uint32_t kGroupSize = gpu::GROUP_SIZE;

enum DropReason : uint32_t {
    DropGradient = gpu::DROP_GRADIENT,
    DropArmijo = gpu::DROP_ARMIJO,
    DropIterations = gpu::DROP_ITERATIONS,
    DropJump = gpu::DROP_JUMP,
    DropReasonCount = gpu::DROP_REASONS
};
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
RefinePlan planRefinement(const Surface& hrbf, const RefineOptions& options, uint64_t maxPoints);

// One level's rules, the same numbers for both backends. The device takes them as they are as push constants:
// RefineParams in spirv_shaders/shared/refine.h, whose layout both languages share.
using LevelParams = gpu::RefineParams;
LevelParams levelParams(const RefinePlan& plan, const RefineOptions& options, uint32_t level);
double levelRho(const RefinePlan& plan, uint32_t level);  // ρ of a level: 0 for the seeds, ρ₀ for level 1

// How the CPU reference evaluates f and ∇f: the fastest this CPU has (AVX2 with FMA where there is one), or
// the portable code every target builds (what ARM64 runs; tests run it on x86-64 too).
enum class CpuKernel { Best, Portable };

// The most points the CPU reference refines: the 4,194,304 (2^22) that lavapipe's limits allow the device
// (128 MiB of 32-byte records for the points, with the candidates and work buffers about 0.5 GiB in all).
// Pass it to planRefinement for the CPU backend; refineOnCpu refuses a plan above it.
constexpr uint64_t kMaxCpuPoints = uint64_t(1) << 22;

// The CPU reference backend: the same plan, rules and random numbers, on all hardware threads.
std::vector<PointRecord> refineOnCpu(const Surface& hrbf, const RefineOptions& options, const RefinePlan& plan,
                                     std::vector<LevelStats>* stats = nullptr, unsigned threads = 0,
                                     CpuKernel kernel = CpuKernel::Best);

}  // namespace ink
