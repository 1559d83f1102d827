#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

SceneVoxelization::SceneVoxelization(gpu::Device& device)
    : pipeline_(device, shaders::scene_voxelization_comp, {VK_FALSE}),
      reflectiveShadowMap_(device, shaders::scene_voxelization_comp, {VK_TRUE}) {}

void SceneVoxelization::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
                               const LitFrameImages& lit, uint32_t viewKind) {
  auto scope = commands.scope("ssvgi: SceneVoxelization");
  const bool reflectiveShadowMap = (viewKind & shader::kViewIsReflectiveShadowMap) != 0u;
  commands.dispatchIndirect(reflectiveShadowMap ? reflectiveShadowMap_ : pipeline_,
                            scene.bindings()
                                .buffer(shader::kBindGiFrame, inputs.frame)
                                .externalSampled(shader::kBindInjectionColor, lit.color, inputs.pointSampler)
                                .externalSampled(shader::kBindInjectionDepth, lit.depth, inputs.pointSampler)
                                .externalSampled(shader::kBindInjectionNormal, lit.normal, inputs.pointSampler)
                                .externalSampled(shader::kBindInjectionAlbedo, lit.albedo, inputs.pointSampler)
                                .sampled(shader::kBindInjectionIrradiance, *lit.lastOutput, inputs.pointSampler)
                                .buffer(shader::kBindInjectionBricks, inputs.visibleBricks)
                                .buffer(shader::kBindHiZ, inputs.hiz),
                            inputs.visibleBricks, 0);
}

}  // namespace ssvgi::gi
