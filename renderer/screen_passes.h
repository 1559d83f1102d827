#pragma once
// The renderer's full-screen compute passes, in frame order after the G-buffer. Each is one shader and one record().
#include "gbuffer_pass.h"
#include "shadow_pass.h"

namespace ssvgi::renderer {

// DirectLighting: E_direct from the sun and local lights with shadows, and the view distance of each pixel, for each
// pixel of the G-buffer (the output images may be larger: scratch shared by views of several sizes).
class DirectLighting {
 public:
  explicit DirectLighting(gpu::Device& device);
  void record(gpu::CommandList& commands, const gpu::Buffer& frameConstants, const gpu::Buffer& lights,
              const ShadowPass& shadows, const GBuffer& gbuffer, VkSampler pointSampler, const gpu::Image& irradiance,
              const gpu::Image& viewDistance);

 private:
  gpu::ComputePipeline pipeline_;
};

// Composite: final = emission + albedo/π · (E_direct + E_indirect), the sky behind (SPEC §3). `indirectIrradiance` and
// `indirectConfidence` are half-resolution images (ssvgi's output and confidence) that the caller has made ready for
// compute reads: they are bound untracked. `indirectUsed` receives the E_indirect each pixel was shaded with and, in
// alpha, its confidence.
class Composite {
 public:
  explicit Composite(gpu::Device& device);
  void record(gpu::CommandList& commands, const gpu::Buffer& frameConstants, const gpu::Buffer& fallback,
              const GBuffer& gbuffer, VkSampler pointSampler, const gpu::Image& directIrradiance,
              VkImageView indirectIrradiance, VkImageView indirectConfidence, const gpu::Image& finalRadiance,
              const gpu::Image& indirectUsed, const gpu::Image& directRadiance);

 private:
  gpu::ComputePipeline pipeline_;
};

// Tonemap: exposure, ACES fitted curve, sRGB encoding into an 8-bit image for PNG.
class Tonemap {
 public:
  explicit Tonemap(gpu::Device& device);
  void record(gpu::CommandList& commands, const gpu::Buffer& frameConstants, const gpu::Image& hdr,
              const gpu::Image& ldr);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::renderer
