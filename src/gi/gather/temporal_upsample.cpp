#include "gather_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

TemporalUpsample::TemporalUpsample(gpu::Device& device) : pipeline_(device, shaders::temporal_upsample_comp) {}

void TemporalUpsample::record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets) {
  auto scope = commands.scope("ssvgi: TemporalUpsample");
  const gpu::Bindings bindings = inputs.bindings(targets)
                                     .image(shader::kBindGatherTileIrradiance, targets.tileIrradiance())
                                     .image(shader::kBindGatherTileProbeBlend, targets.tileProbeBlend())
                                     .image(shader::kBindGatherHistory, targets.history())
                                     .image(shader::kBindGatherOutput, targets.output())
                                     .image(shader::kBindGatherConfidence, targets.confidence());
  // One thread per 2×2 half-resolution pixels.
  commands.dispatch(pipeline_, bindings, glm::uvec3((targets.halfSize() + 1u) / 2u, 1));
}

}  // namespace ssvgi::gi
