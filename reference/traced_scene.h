#pragma once
// The reference's GPU copy of a scene as it is at one moment: the world-space triangles in a BVH, their shading, the
// materials and textures, the delta lights, the table of emissive triangles and the frame constants (sun, sky, camera). Every pass of the reference
// (PrimaryHits, PathTrace, PointRadiance) traces it through shaders/reference/scene_tracing.glsl.
#include "gpu/command_list.h"
#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "gpu_host/owned_device.h"
#include "scene.h"
#include "shared/path_tracer_interface.h"

#include <cstdint>

namespace ssvgi::reference {

// How much work the next dispatch of a progressive pass takes. A dispatch holds the GPU (or lavapipe's threads) until
// it is done, so the work is split into dispatches of about `secondsPerDispatch` each, sized from the last one's time.
// The results never depend on the split.
class DispatchPacer {
 public:
  explicit DispatchPacer(double secondsPerDispatch) : secondsPerDispatch_(secondsPerDispatch) {}
  // Units of work (samples, rounds) for the next dispatch, of `remaining`.
  uint32_t nextUnits(uint32_t remaining) const;
  // A dispatch of `units` took `seconds`.
  void measured(uint32_t units, double seconds);

 private:
  double secondsPerDispatch_;
  uint32_t unitsPerDispatch_ = 1;
};

// The specialization constants of a pass that traces `scene` (scene_tracing.glsl's kSceneCutsOut): a scene none of whose
// materials cuts its surfaces out traces without looking.
gpu::SpecializationConstants sceneTracingConstants(const renderer::Scene& scene);

class TracedScene {
 public:
  // The scene at `state` (the moving object's transform, the sun, the camera), seen in a view of width × height
  // pixels. Throws gpu::GpuError for a scene without triangles or materials, or a mesh with a missing material.
  TracedScene(gpu::OwnedDevice& device, const renderer::Scene& scene, const renderer::AnimatedState& state,
              uint32_t width, uint32_t height, float exposure);

  // The scene's slots, kBindTrace* of shared/path_tracer_interface.h.
  gpu::Bindings bindings() const;
  const gpu::Buffer& frameConstants() const { return frameConstants_; }

  uint32_t triangleCount() const { return triangleCount_; }
  uint32_t bvhNodeCount() const { return bvhNodeCount_; }
  uint32_t bvhDepth() const { return bvhDepth_; }
  // Entries of the emissive-triangle table (shader::EmissiveTriangle): triangles of positive area whose material emits.
  uint32_t emitterCount() const { return emitterCount_; }
  // Σ area × shader::emissionLuminance over that table: the push constants' emittedPower.
  float emittedPower() const { return emittedPower_; }

 private:
  gpu::Buffer frameConstants_;
  gpu::Buffer nodes_;
  gpu::Buffer triangles_;
  gpu::Buffer shading_;
  gpu::Buffer materials_;
  gpu::Buffer textures_;
  gpu::Buffer texels_;
  gpu::Buffer lights_;
  gpu::Buffer emitters_;
  uint32_t triangleCount_ = 0;
  uint32_t bvhNodeCount_ = 0;
  uint32_t bvhDepth_ = 0;
  uint32_t emitterCount_ = 0;
  float emittedPower_ = 0.0f;
};

}  // namespace ssvgi::reference
