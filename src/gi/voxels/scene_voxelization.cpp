#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

SceneVoxelization::SceneVoxelization(gpu::Device& device) : pipeline_(device, shaders::scene_voxelization_comp) {}

void SceneVoxelization::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
                               const LitFrameImages& lit) {
  auto scope = commands.scope("ssvgi: SceneVoxelization");
  commands.dispatchIndirect(pipeline_,
                            scene.bindings()
                                .buffer(shader::kBindGiFrame, inputs.frame)
                                .externalSampled(shader::kBindInjectionColor, lit.color, inputs.pointSampler)
                                .externalSampled(shader::kBindInjectionDepth, lit.depth, inputs.pointSampler)
                                .externalSampled(shader::kBindInjectionNormal, lit.normal, inputs.pointSampler)
                                .externalSampled(shader::kBindInjectionAlbedo, lit.albedo, inputs.pointSampler)
                                .sampled(shader::kBindInjectionIrradiance, *lit.lastOutput, inputs.pointSampler)
                                .buffer(shader::kBindInjectionBricks, inputs.visibleBricks),
                            inputs.visibleBricks, 0);
}

}  // namespace ssvgi::gi
