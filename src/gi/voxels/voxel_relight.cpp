#include "shared/gather_interface.h"
#include "shared/voxel_interface.h"
#include "ssvgi_shaders.h"
#include "voxel_passes.h"

#include <algorithm>

namespace ssvgi::gi {

VoxelRelight::VoxelRelight(gpu::Device& device) : pipeline_(device, shaders::voxel_relight_comp) {}

void VoxelRelight::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeLight& probeLight,
                          uint32_t frameIndex, uint32_t period) {
  auto scope = commands.scope("ssvgi: VoxelRelight");
  // The bricks in `period` phases, one a frame: every live voxel is relit once every `period` frames.
  const struct {
    uint32_t phase;
    uint32_t period;
  } phase{frameIndex % period, period};
  // Enough workgroups to fill a GPU; each loops over the used bricks, relighting those of the frame's phase.
  constexpr uint32_t kWorkgroups = 256;
  const uint32_t capacity = scene.settings().brickPoolCapacity;
  const uint32_t workgroups =
      std::min(kWorkgroups, (capacity + shader::kRelightBricksAtOnce - 1) / shader::kRelightBricksAtOnce);
  commands.dispatch(pipeline_,
                    scene.bindings()
                        .buffer(shader::kBindGatherConstants, probeLight.gatherConstants)
                        .buffer(shader::kBindGatherProbes, probeLight.probes),
                    {workgroups * shader::kRelightBricksAtOnce * shader::kRelightVoxelsAtOnce, 1, 1}, phase);
}

}  // namespace ssvgi::gi
