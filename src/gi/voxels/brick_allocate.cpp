#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

BrickAllocate::BrickAllocate(gpu::Device& device)
    : allocating_(device, shaders::brick_allocate_comp, {VK_FALSE}),
      allocatingAndCountingHeights_(device, shaders::brick_allocate_comp, {VK_TRUE}) {}

void BrickAllocate::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
                           glm::uvec2 depthSize, uint32_t pixelStride, bool countsHeights) {
  auto scope = commands.scope("ssvgi: BrickAllocate");
  const glm::uvec2 samples = (depthSize + pixelStride - 1u) / pixelStride;
  const glm::uvec2 threads = (samples + 1u) / 2u;  // 2×2 sample pixels an invocation
  commands.dispatch(countsHeights ? allocatingAndCountingHeights_ : allocating_,
                    scene.bindings()
                        .buffer(shader::kBindGiFrame, inputs.frame)
                        .externalSampled(shader::kBindAllocationDepth, inputs.depth, inputs.pointSampler)
                        .externalSampled(shader::kBindAllocationNormal, inputs.normal, inputs.pointSampler),
                    {threads.x, threads.y, 1});
}

}  // namespace ssvgi::gi
