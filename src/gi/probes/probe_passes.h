#pragma once
// The passes that update the probe radiance cache each frame (SPEC §4 steps 7–9; the talk's "Part2 Indirect Light"),
// in frame order. Each is one compute shader in shaders/gi/probes/ and one small class that binds and dispatches it.
#include "gi/voxels/voxel_scene.h"
#include "gpu/command_list.h"
#include "probe_volume.h"

namespace ssvgi::gi {

// ProbePlacement: the probes of this frame's level that are in view and near voxels, listed up to the budget; then
// those of the blocks beyond the view whose turn it is, for what the budget leaves.
class ProbePlacement {
 public:
  explicit ProbePlacement(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes, const gpu::Buffer& frame,
              OfferedProbeBlocks blocks);

 private:
  gpu::ComputePipeline pipeline_;
};

// ProbeTrace: rays from each listed probe through the voxels, projected onto SH2 and blended into its history; on level
// 0 with Settings::probeReservoirs it also does UpdateReservoirs (SPEC §4 step 8): the rays go through the probe's
// reservoirs, which it updates.
class ProbeTrace {
 public:
  explicit ProbeTrace(gpu::Device& device);
  // `skyMap`: the host's sky map (FrameDesc::skyRadianceMap) and its sampler; without one any shader-readable image,
  // bound but not read (ProbeUpdate::hasSkyMap).
  void record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes, VkImageView skyMap,
              VkSampler skyMapSampler);

 private:
  gpu::ComputePipeline pipeline_;
  gpu::ComputePipeline keepingReservoirs_;  // for a level that keeps reservoirs (ProbeUpdate::keepsReservoirs)
};

// ProbeRelocate: the virtual offset — listed probes that see back faces move out of the geometry or become invalid.
class ProbeRelocate {
 public:
  explicit ProbeRelocate(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes);

 private:
  gpu::ComputePipeline pipeline_;
};

// ProbeDilate: listed invalid probes take the mean radiance of their usable neighbours.
class ProbeDilate {
 public:
  explicit ProbeDilate(gpu::Device& device);
  void record(gpu::CommandList& commands, const ProbeVolume& probes);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
