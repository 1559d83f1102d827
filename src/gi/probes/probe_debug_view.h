#pragma once
#include "gi/voxels/voxel_scene.h"
#include "gpu/command_list.h"
#include "probe_volume.h"
#include "ssvgi/ssvgi.h"

namespace ssvgi::gi {

// ProbeDebugView: the finest probe level as small spheres showing their SH irradiance and state, in front of the
// voxel scene (DebugView::Probes).
class ProbeDebugView {
 public:
  explicit ProbeDebugView(gpu::Device& device);
  // `probeCamera`: where the last dispatch centred the probe levels.
  void record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes, glm::vec3 probeCamera,
              const View& camera, VkImage target, VkImageView targetView);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
