#pragma once
// Ground truth for the GI's probes (SPEC §4.5, §7): the radiance arriving at free points of the scene from every
// direction, path-traced over the same scene as the reference images (shaders/reference/point_radiance.comp) and
// projected onto SH2 with SPEC §2's convention, so that it compares coefficient for coefficient with a probe's.
#include "path_tracer.h"
#include "shared/sh.h"
#include "traced_scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace ssvgi::reference {

struct PointRadianceSettings {
  uint32_t maxBounces = kDefaultMaxBounces;  // reflections of light from its source to the point
  uint32_t seed = 0;  // the result is a function of (scene, points, settings, seed, directions) only
  bool sampleEmitters = true;  // as PathTracerSettings::sampleEmitters, from each path's first vertex on
  double secondsPerDispatch = 0.25;  // as PathTracerSettings::secondsPerDispatch
};

class PointRadianceTracer {
 public:
  // The scene as it is at `state`, and the points (world, m) whose incoming radiance is wanted. A point should lie in
  // free space: on a surface, half its directions would start inside the surface's thickness or on its plane.
  PointRadianceTracer(gpu::OwnedDevice& device, const renderer::Scene& scene, const renderer::AnimatedState& state,
                      std::span<const glm::vec3> points, const PointRadianceSettings& settings = {});

  // Adds at least `directions` uniformly distributed directions to every point (rounded up to a whole number of
  // rounds, shader::kPointRadianceDirectionsPerRound), in dispatches of adaptive size, waiting for each.
  void trace(uint32_t directions);
  uint32_t directionsPerPoint() const { return rounds_ * shader::kPointRadianceDirectionsPerRound; }

  // Per point, over the N directions traced so far, each sum scaled by 4π/N (shared/path_tracer_interface.h): its
  // incoming radiance as SH2 of each colour channel, L_lm = (4π/N) Σ L(ω_i) Y_lm(ω_i) (SPEC §2), and the irradiance
  // E(n) = (4π/N) Σ L(ω_i)·max(0, ω_i·n) on the six axis-facing surfaces through it, which SH2 holds only in part.
  std::vector<shader::PointRadianceSums> measurements();
  // Their radiance SH2 alone.
  std::vector<shader::Sh2Rgb> radiance();

 private:
  gpu::OwnedDevice& device_;
  PointRadianceSettings settings_;
  gpu::DescriptorArena descriptors_;
  gpu::ComputePipeline pipeline_;
  TracedScene scene_;
  DispatchPacer pacer_;
  gpu::Buffer points_;
  gpu::Buffer sums_;
  uint32_t pointCount_ = 0;
  uint32_t rounds_ = 0;
};

}  // namespace ssvgi::reference
