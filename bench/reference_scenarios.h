#pragma once
// The GI held to the path-traced reference (SPEC §7): a view rendered with ssvgi until its indirect light has
// converged, then
//   - the error of its indirect irradiance image against the reference's (SPEC §7 "error vs reference");
//   - the irradiance its probes hold against the reference's at the same points (the probe radiance cache, §4.5).
// Both report the reference's own noise, measured from two independent halves of it, as the floor under the figure.
#include "gpu_host/owned_device.h"
#include "image_compare.h"
#include "scenario_rendering.h"
#include "scenarios.h"
#include "shared/path_tracer_interface.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace ssvgi::bench {

// The GI has converged when the mean of its indirect irradiance over the surface pixels changes by less than
// `tolerance` (relative) from the end of one window of frames to the end of the next. A window of 48 frames updates
// every probe level 16 times (one level per frame, SPEC §4.5) and spans three turns of the gather's 16-frame jitter.
// The later bounces of the lit-frame loop settle slowly: at 1 % a window `cornell` at 640×360 stopped at frame 144
// with 5 % less light than at 0.2 % (frame 864), and the figure depended on how fast the first bounces came
// (docs/QUALITY.md, 2026-12-01).
struct ConvergenceOptions {
  uint32_t windowFrames = 48;
  double tolerance = 0.002;
  uint32_t maxFrames = 1536;  // stop here, converged or not (reported)
};

struct Convergence {
  uint32_t frames = 0;      // rendered in all
  double lastChange = 0.0;  // relative change of the mean indirect irradiance over the last window
  bool converged = false;   // lastChange < tolerance
};

// A view rendered with the GI until its indirect light has converged: what the measurements below start from. One
// may serve both, so that a view is converged once (the Cornell tests'). `view` must outlive it.
class ConvergedView {
 public:
  ConvergedView(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                const ConvergenceOptions& options = {});

  ScenarioRenderer& renderer() { return renderer_; }
  const ScenarioRendering& rendering() const { return rendering_; }
  const ScenarioView& view() const { return view_; }
  const Convergence& convergence() const { return convergence_; }

 private:
  ScenarioRendering rendering_;
  const ScenarioView& view_;
  ScenarioRenderer renderer_;
  Convergence convergence_;
};

// ---------------------------------------------------------------------------------------------------------------------
// Error vs reference (SPEC §7): relative mean absolute error of E_indirect against the path-traced reference's, over
// the pixels where the renderer drew a surface, after convergence, both images box-filtered in downsample² blocks.

struct IndirectErrorOptions {
  ConvergenceOptions convergence;
  uint32_t referenceSamples = 1024;  // per pixel, an even number: two halves of independent seeds
  uint32_t downsample = 4;
  uint32_t seed = 0;  // the reference's halves use seed and seed + 1
};

struct IndirectErrorResult {
  reference::ImageComparison comparison;  // E_indirect of the GI against the reference's: SPEC §7's figure
  // The relative mean absolute error a perfect E_indirect would show against this reference, from its noise alone:
  // the error between its two independent halves / 2 (each half has √2 × the whole's noise, their difference √2 ×
  // a half's). The figure above means little unless it is well above this.
  double referenceNoiseFloor = 0.0;
  uint32_t referenceSamples = 0;  // per pixel, both halves together
  Convergence convergence;
};

// Renders the view with the GI until converged, path-traces the same view (animation time 0) and compares.
IndirectErrorResult measureIndirectError(gpu::OwnedDevice& device, const ScenarioRendering& rendering,
                                         const ScenarioView& view, const IndirectErrorOptions& options = {});
// The same of a view already converged (options.convergence is not used).
IndirectErrorResult measureIndirectError(gpu::OwnedDevice& device, ConvergedView& converged,
                                         const IndirectErrorOptions& options = {});

// ---------------------------------------------------------------------------------------------------------------------
// Probe irradiance vs reference (SPEC §4.5): what the level-0 probes hold against the path-traced radiance at the
// same points, as E(n) for the six axis normals.

struct ProbeIrradianceOptions {
  ConvergenceOptions convergence;
  uint32_t referenceDirections = 65536;  // per probe, both halves together (PointRadianceTracer)
  uint32_t seed = 0;                     // the reference's halves use seed and seed + 1
};

// The six axis normals E(n) is compared for: +X, −X, +Y, −Y, +Z, −Z (shader::pointAxisNormal).
inline constexpr uint32_t kAxisNormals = shader::kPointAxisNormals;

struct ProbeIrradiance {
  glm::ivec3 probe{0};        // world probe coordinate on level 0
  glm::vec3 position{0.0f};   // where its rays leave: the grid position plus its virtual offset
  std::array<glm::vec3, kAxisNormals> gi{};         // E(n) of its radiance SH2 (SPEC §2), clamped at 0 as gathers do
  std::array<glm::vec3, kAxisNormals> reference{};  // the same of the path-traced SH2 at its position
  std::array<glm::vec3, kAxisNormals> exact{};      // the path-traced E(n) itself, summed over its directions
};

// Two irradiances over the probes, the six normals and the colour channels.
struct IrradianceAgreement {
  double relativeMeanAbsoluteError = 0.0;  // Σ|E_test − E_against| / Σ E_against
  double meanRatio = 0.0;                  // Σ E_test / Σ E_against
  std::array<double, kAxisNormals> ratioByNormal{};  // the same for each normal alone
};

struct ProbeIrradianceResult {
  std::vector<ProbeIrradiance> probes;  // the probes compared (see measureProbeIrradiance)
  uint32_t usableProbes = 0;            // usable level-0 probes in all, compared or not
  // Σ|E_probe − E_reference| / Σ E_reference over the probes, the six normals and the colour channels.
  double relativeMeanAbsoluteError = 0.0;
  double meanRatio = 0.0;            // Σ E_probe / Σ E_reference
  double referenceNoiseFloor = 0.0;  // as IndirectErrorResult's, between the two halves of the reference
  uint32_t referenceDirections = 0;  // per point, both halves together
  // The probes' E(n), read as the gather reads them, against the reference's exact E(n): what the gather starts from.
  IrradianceAgreement againstExact;
  // The reference's own SH2 read the same way against its exact E(n): what the SH2 reading alone loses, whatever the
  // probes hold.
  IrradianceAgreement readingOfReference;
  Convergence convergence;
};

// Renders the view with the GI until converged, then compares the irradiance held by the level-0 probes the camera
// sees into with the path-traced radiance at their positions. Compared are the usable probes (probeIsUsable) that lie
// inside the scene's bounds, in the view frustum and in front of the surface drawn where they project: ssvgi's probes
// see voxels, and voxels exist only where the camera saw a surface, so only a probe in the space the camera looks into
// has surroundings the GI can know (in `cornell`, the box's interior and its open front). A probe elsewhere — outside
// the box, behind a wall — would measure what the camera never saw rather than the probe cache. And at least one
// voxel (Settings::voxelSize) from every surface: the voxels place a surface only to within a voxel, so nearer than
// that the distance to it — and the solid angle it fills — is not known to the GI at all; on a surface the
// reference's own rays would start on it. Throws std::runtime_error when no probe qualifies.
ProbeIrradianceResult measureProbeIrradiance(gpu::OwnedDevice& device, const ScenarioRendering& rendering,
                                             const ScenarioView& view, const ProbeIrradianceOptions& options = {});
// The same of a view already converged (options.convergence is not used).
ProbeIrradianceResult measureProbeIrradiance(gpu::OwnedDevice& device, ConvergedView& converged,
                                             const ProbeIrradianceOptions& options = {});

nlohmann::json toJson(const IndirectErrorResult& result);
nlohmann::json toJson(const ProbeIrradianceResult& result);

}  // namespace ssvgi::bench
