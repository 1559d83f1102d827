#include "gather_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

TemporalFilter::TemporalFilter(gpu::Device& device) : pipeline_(device, shaders::temporal_filter_comp) {}

void TemporalFilter::record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets) {
  auto scope = commands.scope("ssvgi: TemporalFilter");
  const gpu::Bindings bindings = inputs.bindings(targets)
                                     .image(shader::kBindGatherTileIrradiance, targets.tileIrradiance())
                                     .image(shader::kBindGatherTileProbeBlend, targets.tileProbeBlend())
                                     .image(shader::kBindGatherHistory, targets.history())
                                     .image(shader::kBindGatherOutput, targets.output());
  commands.dispatch(pipeline_, bindings, glm::uvec3(targets.halfSize(), 1));  // one thread per half-resolution pixel
}

}  // namespace ssvgi::gi
