#pragma once
// BuildOctree (SPEC §4.4; the talk's "Voxel-Build Octree"): brings the grid levels of the occupancy hierarchy (brick,
// 2×2×2 bricks, 4×4×4 bricks) up to date for the brick cells whose occupancy changed this frame.
#include "gpu/command_list.h"
#include "voxel_scene.h"

namespace ssvgi::gi {

class BuildOctree {
 public:
  explicit BuildOctree(gpu::Device& device);
  // Works through scene.changedCells(): one indirect dispatch per grid level, finest first, each reading the level
  // the previous one wrote (the barrier between them comes from the tracker: each writes the grid).
  void record(gpu::CommandList& commands, const VoxelScene& scene);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
