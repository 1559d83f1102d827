#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

VolumeScroll::VolumeScroll(gpu::Device& device) : pipeline_(device, shaders::volume_scroll_comp) {}

void VolumeScroll::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs) {
  auto scope = commands.scope("ssvgi: VolumeScroll");
  commands.dispatch(pipeline_, scene.bindings().buffer(shader::kBindGiFrame, inputs.frame), {scene.cellCount(), 1, 1});
}

}  // namespace ssvgi::gi
