#pragma once
#include "gpu_host/host_command_list.h"
#include "gpu_scene.h"

namespace ssvgi::renderer {

// The G-buffer of one view: reversed-Z depth, linear albedo, emission, world normal and screen-space motion.
struct GBuffer {
  GBuffer(gpu::Device& device, uint32_t width, uint32_t height);
  gpu::Image depth;     // D32, reversed-Z (1 at the near plane, 0 at infinity)
  gpu::Image albedo;    // rgba16f, linear base colour
  gpu::Image emission;  // rgba16f, emitted radiance
  gpu::Image normal;    // rgba16f, unit world normal facing the camera
  gpu::Image motion;    // rg16f, UV(current) - UV(previous)
};

// GBuffer: rasterises the scene into a GBuffer with dynamic rendering.
class GBufferPass {
 public:
  explicit GBufferPass(gpu::Device& device);
  void record(gpu::HostCommandList& commands, const GpuScene& scene, const gpu::Buffer& frameConstants,
              const GBuffer& target);

 private:
  gpu::GraphicsPipeline pipeline_;
};

}  // namespace ssvgi::renderer
