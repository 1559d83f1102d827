#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

SceneVoxelization::SceneVoxelization(gpu::Device& device) : pipeline_(device, shaders::scene_voxelization_comp) {}

void SceneVoxelization::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
                               const LitFrameImages& lit) {
  auto scope = commands.scope("ssvgi: SceneVoxelization");
  commands.dispatchIndirect(pipeline_,
                            scene.bindings().buffer(shader::kBindGiFrame, inputs.frame)
                                .externalSampled(8, lit.color, inputs.pointSampler)
                                .externalSampled(9, lit.depth, inputs.pointSampler)
                                .externalSampled(10, lit.normal, inputs.pointSampler)
                                .buffer(11, inputs.visibleBricks),
                            inputs.visibleBricks, 0);
}

}  // namespace ssvgi::gi
