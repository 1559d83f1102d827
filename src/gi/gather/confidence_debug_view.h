#pragma once
#include "gather_targets.h"
#include "gi/voxels/voxel_scene.h"
#include "gpu/command_list.h"
#include "ssvgi/ssvgi.h"

namespace ssvgi::gi {

// ConfidenceDebugView: the confidence the gather gives the surfaces a camera sees in the voxels, in grey
// (DebugView::Confidence).
class ConfidenceDebugView {
 public:
  explicit ConfidenceDebugView(gpu::Device& device);
  // `targets`: the last dispatch's, whose GatherConstants place the probe levels; `probes`: Probe[] (ProbeVolume).
  void record(gpu::CommandList& commands, const VoxelScene& scene, const GatherTargets& targets,
              const gpu::Buffer& probes, const View& camera, VkImage target, VkImageView targetView);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
