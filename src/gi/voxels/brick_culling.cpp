#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

BrickCulling::BrickCulling(gpu::Device& device) : pipeline_(device, shaders::brick_culling_comp) {}

void BrickCulling::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs) {
  auto scope = commands.scope("ssvgi: BrickCulling");
  commands.dispatch(pipeline_,
                    scene.bindings()
                        .buffer(shader::kBindGiFrame, inputs.frame)
                        .buffer(shader::kBindHiZ, inputs.hiz)
                        .buffer(shader::kBindCullingVisibleBricks, inputs.visibleBricks),
                    {scene.settings().brickPoolCapacity, 1, 1});
}

}  // namespace ssvgi::gi
