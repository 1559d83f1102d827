#include "probe_passes.h"
#include "shared/gi_frame.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbePlacement::ProbePlacement(gpu::Device& device) : pipeline_(device, shaders::probe_placement_comp) {}

void ProbePlacement::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes,
                            const gpu::Buffer& frame, OfferedProbeBlocks blocks) {
  auto scope = commands.scope("ssvgi: ProbePlacement");
  const gpu::Bindings bindings = scene.bindings()
                                     .buffer(shader::kBindGiFrame, frame)
                                     .buffer(shader::kBindProbeUpdate, probes.update())
                                     .buffer(shader::kBindProbeBlocks, probes.offeredBlocks())
                                     .buffer(shader::kBindProbes, probes.probes())
                                     .buffer(shader::kBindProbeChanges, probes.changes())
                                     .buffer(shader::kBindProbeList, probes.list());
  const uint32_t probesPerBlock = shader::kProbeBlockSize * shader::kProbeBlockSize * shader::kProbeBlockSize;
  // The blocks in view first, so that theirs are listed first and keep the budget; those beyond the view take what is
  // left (the second dispatch waits for the first: both write the list).
  if (blocks.inView > 0)
    commands.dispatch(pipeline_, bindings, {blocks.inView * probesPerBlock, 1, 1},
                      shader::ProbePlacementPush{.firstBlock = 0, .inView = 1});
  if (blocks.beyondView > 0)
    commands.dispatch(pipeline_, bindings, {blocks.beyondView * probesPerBlock, 1, 1},
                      shader::ProbePlacementPush{.firstBlock = blocks.inView, .inView = 0});
}

}  // namespace ssvgi::gi
