#include "gather_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

FinalGather::FinalGather(gpu::Device& device) : pipeline_(device, shaders::final_gather_comp) {}

void FinalGather::record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets,
                         const ProbeVolume& probes) {
  auto scope = commands.scope("ssvgi: FinalGather");
  const gpu::Bindings bindings = inputs.bindings(targets)
                                     .buffer(shader::kBindGatherProbes, probes.probes())
                                     .buffer(shader::kBindGatherProbeVisibility, probes.visibility())
                                     .image(shader::kBindGatherTileIrradiance, targets.tileIrradiance());
  commands.dispatch(pipeline_, bindings, glm::uvec3(targets.tiles(), 1));  // one thread per tile
}

}  // namespace ssvgi::gi
