#include "gather_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

Upsample::Upsample(gpu::Device& device) : pipeline_(device, shaders::upsample_comp) {}

void Upsample::record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets) {
  auto scope = commands.scope("ssvgi: Upsample");
  const gpu::Bindings bindings = inputs.bindings(targets)
                                     .image(shader::kBindGatherTileIrradiance, targets.tileIrradiance())
                                     .image(shader::kBindGatherTileProbeBlend, targets.tileProbeBlend())
                                     .image(shader::kBindGatherOutput, targets.output())
                                     .image(shader::kBindGatherConfidence, targets.confidence());
  commands.dispatch(pipeline_, bindings, glm::uvec3(targets.halfSize(), 1));  // one thread per half-resolution pixel
}

}  // namespace ssvgi::gi
