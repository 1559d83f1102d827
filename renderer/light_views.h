#pragma once
// The views of the local lights that the renderer gives ssvgi beyond its camera (SPEC §6.3): what each light sees is
// what it lights, and surfaces the camera never sees (the top of a tall box, the floor behind it) get voxels and light.
// A light's views are a reflective shadow map rendered with the host's own passes: G-buffer, direct light and a
// composite without GI, at a small size; ssvgi adds the probes' light (ssvgi::ExtraView::albedo).
#include "gbuffer_pass.h"
#include "gpu_scene.h"
#include "screen_passes.h"
#include "shadow_pass.h"

#include "ssvgi/ssvgi.h"

#include <vector>

namespace ssvgi::renderer {

class LightViews {
 public:
  // `size`: pixels per side of each view. A point light has six (a cube), a spot light one (its cone).
  LightViews(gpu::Device& device, const Scene& scene, uint32_t size);

  uint32_t viewCount() const { return uint32_t(cameras_.size()); }

  // Renders this frame's views, up to ssvgi::kMaxExtraViews of them (a scene with more takes turns), with the frame's
  // lights and shadows (`frame`: the camera's constants, whose view fields each light view replaces), and returns
  // them ready for ssvgi (their images shader-readable).
  std::vector<ssvgi::ExtraView> record(gpu::CommandList& commands, uint32_t frameIndex,
                                       const shader::FrameConstants& frame, const GpuScene& scene,
                                       const gpu::Buffer& lights, const ShadowPass& shadows, VkSampler pointSampler);

 private:
  struct Slot {
    Slot(gpu::Device& device, uint32_t size);
    gpu::Buffer frameConstants;
    GBuffer gbuffer;
    gpu::Image radiance;  // emission + albedo/π · E_direct
  };

  uint32_t size_;
  std::vector<Camera> cameras_;
  std::vector<Slot> slots_;
  GBufferPass gbufferPass_;
  DirectLighting directLighting_;
  Composite composite_;
  gpu::Image directIrradiance_;  // scratch, shared by the slots
  gpu::Image viewDistance_;
  gpu::Image noIndirect_;        // black: the composite adds no indirect light
  gpu::Image indirectUsed_;
};

}  // namespace ssvgi::renderer
