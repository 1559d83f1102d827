#include "ssvgi_shaders.h"
#include "voxel_passes.h"

namespace ssvgi::gi {

BrickAllocate::BrickAllocate(gpu::Device& device) : pipeline_(device, shaders::brick_allocate_comp) {}

void BrickAllocate::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
                           glm::uvec2 depthSize, uint32_t pixelStride) {
  auto scope = commands.scope("ssvgi: BrickAllocate");
  const glm::uvec2 threads = (depthSize + pixelStride - 1u) / pixelStride;
  commands.dispatch(pipeline_,
                    scene.bindings()
                        .buffer(shader::kBindGiFrame, inputs.frame)
                        .externalSampled(shader::kBindAllocationDepth, inputs.depth, inputs.pointSampler)
                        .externalSampled(shader::kBindAllocationNormal, inputs.normal, inputs.pointSampler),
                    {threads.x, threads.y, 1});
}

}  // namespace ssvgi::gi
