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
  // The pool in `period` slices, one a frame: every live voxel is relit once every `period` frames.
  const uint32_t capacity = scene.settings().brickPoolCapacity;
  const uint32_t bricksPerSlice = (capacity + period - 1) / period;
  const struct {
    uint32_t firstBrick;
    uint32_t endBrick;
  } slice{frameIndex % period * bricksPerSlice, std::min(capacity, (frameIndex % period + 1) * bricksPerSlice)};
  // Enough workgroups to fill a GPU; each loops over the slice's used bricks.
  constexpr uint32_t kWorkgroups = 256;
  const uint32_t workgroups =
      std::min(kWorkgroups, (bricksPerSlice + shader::kRelightBricksAtOnce - 1) / shader::kRelightBricksAtOnce);
  commands.dispatch(pipeline_,
                    scene.bindings()
                        .buffer(shader::kBindGatherConstants, probeLight.gatherConstants)
                        .buffer(shader::kBindGatherProbes, probeLight.probes),
                    {workgroups * shader::kRelightBricksAtOnce * shader::kRelightVoxelsAtOnce, 1, 1}, slice);
}

}  // namespace ssvgi::gi
