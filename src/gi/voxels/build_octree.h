#pragma once
// BuildOctree (SPEC §4.4; the talk's "Voxel-Build Octree"): brings the toroidal grid levels of the occupancy hierarchy
// (brick, 2×2×2 bricks, 4×4×4 bricks) up to date for the brick cells whose occupancy changed this frame, then makes the
// local levels (8×8×8 and 16×16×16 bricks, counted from the volume's corner) of the occupancy grid and of the observed
// space again from level 4 (build_octree_local_levels.comp).
#include "gpu/command_list.h"
#include "voxel_scene.h"

namespace ssvgi::gi {

class BuildOctree {
 public:
  explicit BuildOctree(gpu::Device& device);
  // Works through scene.changedCells(): one indirect dispatch per toroidal grid level, finest first, each reading the
  // level the previous one wrote (the barrier between them comes from the tracker: each writes the grid); then one
  // dispatch per local level. Records after every pass this frame that writes level 4 of either bit volume.
  void record(gpu::CommandList& commands, const VoxelScene& scene);

 private:
  gpu::ComputePipeline pipeline_;
  gpu::ComputePipeline localLevels_;
};

}  // namespace ssvgi::gi
