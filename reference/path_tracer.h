#pragma once
// The reference: a progressive GPU path tracer over exactly the scene the host renderer draws (same triangles,
// materials, textures, delta lights, sky and emissive surfaces, same camera matrices and pixel centres), producing the
// same images as the renderer, so that every quality test can compare against it (SPEC §1, §7).
#include "gpu/command_list.h"
#include "gpu/profiler.h"
#include "image_io.h"
#include "scene.h"
#include "screen_passes.h"
#include "traced_scene.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace ssvgi::reference {

// Reflections of light counted from its source to the primary hit. With a cap of B a closed room of albedo a loses
// a^(B+2) of its light: 0.05 % for B = 32 and a = 0.8. Russian roulette ends most paths long before, so the cap costs
// nothing where light dies out quickly.
inline constexpr uint32_t kDefaultMaxBounces = 32;

struct PathTracerSettings {
  uint32_t width = 256;   // pixels
  uint32_t height = 256;
  uint32_t maxBounces = kDefaultMaxBounces;  // 0: only the sky and emitters seen directly from the primary hit
  uint32_t seed = 0;      // the images are a function of (scene, view, settings, seed, samples per pixel) only
  // Next-event estimation of the emissive triangles: every path vertex (and the primary hit) samples a point on them
  // with a shadow ray, combined with the emission the paths hit by multiple importance sampling (power heuristic).
  // Much less noise from small bright emitters, and none of the emitter sample's 1/d² fireflies where an emitter
  // touches a surface; off, paths find emitters only by hitting them (the estimator without it, e.g. noise-free in a
  // furnace).
  bool sampleEmitters = true;
  float exposure = 1.0f;  // multiplies radiance before the tonemap (PNG only)
  // Wall time to aim at per dispatch: a dispatch holds the GPU (or lavapipe's threads) until it is done. The number
  // of samples per dispatch adapts to reach it; the images do not depend on it.
  double secondsPerDispatch = 0.25;
};

// The images have the meaning of the renderer's (renderer::Renderer), at every pixel centre:
//   directIrradiance   E_direct: sun and local lights with exact hard shadows (shadow rays), not noisy;
//   indirectIrradiance E_indirect: the mean of the samples so far (see shaders/reference/path_trace.comp);
//   finalRadiance      emission + albedo/π · (E_direct + E_indirect), the sky where nothing was hit;
//   albedo, normal, viewDistance: of the surface the pixel sees (0 where none).
class PathTracer {
 public:
  // Builds the BVH over the scene as it is at `state` (the moving object's transform, the sun) and traces the
  // primary hits. Throws gpu::GpuError for a scene without triangles or materials.
  PathTracer(gpu::OwnedDevice& device, const renderer::Scene& scene, const renderer::AnimatedState& state,
             const PathTracerSettings& settings);

  // Adds `samples` samples per pixel (at least 1), in dispatches of adaptive size, waiting for each; `progress`
  // is called after each with the samples per pixel reached so far.
  void trace(uint32_t samples, const std::function<void(uint32_t samplesPerPixel)>& progress = {});

  uint32_t samplesPerPixel() const { return samplesPerPixel_; }
  uint32_t triangleCount() const { return scene_.triangleCount(); }
  uint32_t bvhNodeCount() const { return scene_.bvhNodeCount(); }
  uint32_t bvhDepth() const { return scene_.bvhDepth(); }
  uint32_t emissiveTriangleCount() const { return scene_.emitterCount(); }
  // GPU time per pass, summed over every dispatch so far.
  const std::vector<gpu::PassTiming>& passTimings() const { return timings_; }

  renderer::FloatImage finalRadiance();
  renderer::FloatImage directIrradiance();
  renderer::FloatImage indirectIrradiance();
  renderer::FloatImage albedo();
  renderer::FloatImage normal();
  renderer::FloatImage viewDistance();
  std::vector<uint8_t> tonemapped();  // RGBA8, sRGB, through the renderer's Tonemap

 private:
  void submit(const std::function<void(gpu::CommandList&)>& record);
  gpu::Bindings primaryHitBindings() const;  // the scene and the primary hits' images, written by PrimaryHits

  gpu::OwnedDevice& device_;
  PathTracerSettings settings_;
  gpu::DescriptorArena descriptors_;
  gpu::Profiler profiler_;
  gpu::ComputePipeline primaryHitsPipeline_;
  gpu::ComputePipeline pathTracePipeline_;
  renderer::Tonemap tonemap_;
  TracedScene scene_;
  DispatchPacer pacer_;
  gpu::Image rayOrigins_;
  gpu::Image normals_;
  gpu::Image albedos_;
  gpu::Image primaryRadiance_;
  gpu::Image directIrradiance_;
  gpu::Image viewDistances_;
  gpu::Image indirectSums_;
  gpu::Image indirectIrradiance_;
  gpu::Image finalRadiance_;
  gpu::Image tonemapped_;
  uint32_t samplesPerPixel_ = 0;
  std::vector<gpu::PassTiming> timings_;
};

}  // namespace ssvgi::reference
