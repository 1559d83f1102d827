#pragma once
// SkyMap: the frame's sky as an equirectangular radiance map (shaders/renderer/sky_map.comp), which the renderer gives
// ssvgi as FrameDesc::skyRadianceMap beside its SH2.
#include "gpu/command_list.h"
#include "gpu/pipelines.h"

namespace ssvgi::renderer {

class SkyMap {
 public:
  // 2.8° a texel: the clear sky's circumsolar glow (shared/sky.h) falls by e over 19°.
  static constexpr uint32_t kWidth = 128, kHeight = 64;

  explicit SkyMap(gpu::Device& device);
  // Writes the map of the sky `frameConstants` holds and leaves it ready for compute reads.
  void record(gpu::CommandList& commands, const gpu::Buffer& frameConstants);
  const gpu::Image& image() const { return image_; }

 private:
  gpu::ComputePipeline pipeline_;
  gpu::Image image_;
};

}  // namespace ssvgi::renderer
