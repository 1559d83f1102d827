#include "gather_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

FinalGather::FinalGather(gpu::Device& device) : pipeline_(device, shaders::final_gather_comp) {}

void FinalGather::record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets,
                         const VoxelScene& scene, const gpu::Buffer& probes) {
  auto scope = commands.scope("ssvgi: FinalGather");
  const gpu::Bindings bindings = inputs.bindings(targets, scene.bindings())
                                     .buffer(shader::kBindGatherProbes, probes)
                                     .image(shader::kBindGatherTileIrradiance, targets.tileIrradiance())
                                     .image(shader::kBindGatherTileProbeBlend, targets.tileProbeBlend());
  // One thread per tile the frame gathers: half of each row (shader::gatherTileOfThread).
  const glm::uvec2 tiles = targets.tiles();
  commands.dispatch(pipeline_, bindings, {(tiles.x + 1) / 2, tiles.y, 1});
}

}  // namespace ssvgi::gi
