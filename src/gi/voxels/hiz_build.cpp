#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

HiZBuild::HiZBuild(gpu::Device& device)
    : fromDepth_(device, shaders::hiz_build_comp, {VK_TRUE}), fromLevelBefore_(device, shaders::hiz_build_comp, {VK_FALSE}) {}

void HiZBuild::record(gpu::CommandList& commands, const VoxelFrameInputs& inputs, const shader::GiFrame& frame,
                      uint32_t levels) {
  auto scope = commands.scope("ssvgi: HiZBuild");
  const gpu::Bindings bindings = gpu::Bindings()
                                     .buffer(shader::kBindGiFrame, inputs.frame)
                                     .externalSampled(shader::kBindHiZDepth, inputs.depth, inputs.pointSampler)
                                     .buffer(shader::kBindHiZPyramid, inputs.hiz);
  for (uint32_t level = 0; level < levels; ++level) {
    const glm::uvec3 texels(frame.hizLevels[level].size, 1);
    commands.dispatch(level == 0 ? fromDepth_ : fromLevelBefore_, bindings, texels, level);
  }
}

}  // namespace ssvgi::gi
