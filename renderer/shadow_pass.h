#pragma once
#include "gpu_host/host_command_list.h"
#include "gpu_scene.h"

#include <vector>

namespace ssvgi::renderer {

struct ShadowSettings {
  uint32_t sunResolution = 2048;   // texels per side of the sun's shadow map, fitted to the scene
  uint32_t localResolution = 512;  // texels per side of a spot light's map or a point light's cube face
};

// Shadow: depth maps for the sun (orthographic, fitted to the scene bounds) and for the shadowed local lights
// (one layer of the local array per spot light, six per point light, kMaxShadowLayers in all).
class ShadowPass {
 public:
  ShadowPass(gpu::Device& device, const ShadowSettings& settings);

  // Works out this frame's shadow views and fills the lights' shadow layers and the frame's sun shadow matrix.
  void prepare(const Scene& scene, const Bounds& sceneBounds, const Sun& sun, shader::FrameConstants& frame,
               std::vector<shader::GpuLight>& lights);
  void record(gpu::HostCommandList& commands, const GpuScene& scene);

  const gpu::Image& sunShadowMap() const { return sunMap_; }
  const gpu::Image& localShadowMaps() const { return localMaps_; }
  const gpu::Buffer& views() const { return views_; }  // [0]: the sun; [1 + layer]: local layers
  VkSampler compareSampler() const { return compareSampler_.handle(); }
  uint32_t unshadowedLightCount() const { return unshadowedLights_; }

 private:
  gpu::Device& device_;
  ShadowSettings settings_;
  gpu::GraphicsPipeline pipeline_;
  gpu::GraphicsPipeline cutOutPipeline_;  // for the draws whose material cuts the surface out (Draw::cutsOut)
  gpu::Sampler compareSampler_;
  gpu::Image sunMap_;
  gpu::Image localMaps_;
  gpu::Buffer views_;
  bool sunEnabled_ = false;
  uint32_t localLayers_ = 0;
  uint32_t unshadowedLights_ = 0;
};

}  // namespace ssvgi::renderer
