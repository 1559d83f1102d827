#include "build_octree.h"

#include "ssvgi_shaders.h"

namespace ssvgi::gi {

BuildOctree::BuildOctree(gpu::Device& device)
    : pipeline_(device, shaders::build_octree_comp), localLevels_(device, shaders::build_octree_local_levels_comp) {}

void BuildOctree::record(gpu::CommandList& commands, const VoxelScene& scene) {
  auto scope = commands.scope("ssvgi: BuildOctree");
  const gpu::Bindings bindings = scene.bindings();
  for (uint32_t level = shader::kFirstGridLevel; level < shader::kFirstLocalGridLevel; ++level)
    commands.dispatchIndirect(pipeline_, bindings, scene.changedCells(), 0, &level, sizeof(level));
  for (uint32_t level = shader::kFirstLocalGridLevel; level < shader::kOccupancyLevels; ++level)
    commands.dispatch(localLevels_, bindings, {scene.gridLevelWords(level), 1, 1}, &level, sizeof(level));
}

}  // namespace ssvgi::gi
