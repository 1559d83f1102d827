#include "probe_passes.h"
#include "shared/gi_frame.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbePlacement::ProbePlacement(gpu::Device& device) : pipeline_(device, shaders::probe_placement_comp) {}

void ProbePlacement::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes,
                            const gpu::Buffer& frame, uint32_t blocksInView) {
  auto scope = commands.scope("ssvgi: ProbePlacement");
  const gpu::Bindings bindings = scene.bindings()
                                     .buffer(shader::kBindGiFrame, frame)
                                     .buffer(shader::kBindProbeUpdate, probes.update())
                                     .buffer(shader::kBindProbeBlocks, probes.blocksInView())
                                     .buffer(shader::kBindProbeList, probes.list());
  const uint32_t probesPerBlock = shader::kProbeBlockSize * shader::kProbeBlockSize * shader::kProbeBlockSize;
  commands.dispatch(pipeline_, bindings, {blocksInView * probesPerBlock, 1, 1});
}

}  // namespace ssvgi::gi
