#include "gather_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

Upsample::Upsample(gpu::Device& device) : pipeline_(device, shaders::upsample_comp) {}

void Upsample::record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets) {
  auto scope = commands.scope("ssvgi: Upsample");
  const gpu::Bindings bindings = gpu::Bindings()
                                     .buffer(shader::kBindGiFrame, inputs.frame)
                                     .buffer(shader::kBindGatherConstants, targets.constants())
                                     .externalSampled(shader::kBindGatherDepth, inputs.depth, inputs.pointSampler)
                                     .externalSampled(shader::kBindGatherNormal, inputs.normal, inputs.pointSampler)
                                     .image(shader::kBindGatherTileIrradiance, targets.tileIrradiance())
                                     .image(shader::kBindGatherTileGeometry, targets.tileGeometry())
                                     .image(shader::kBindGatherUpsampled, targets.upsampled());
  commands.dispatch(pipeline_, bindings, glm::uvec3(targets.halfSize(), 1));  // one thread per half-resolution pixel
}

}  // namespace ssvgi::gi
