#pragma once
#include "gpu/command_list.h"
#include "shared/debug_view.h"
#include "ssvgi/ssvgi.h"
#include "voxel_scene.h"

namespace ssvgi::gi {

// The push-constant camera of the debug views.
shader::DebugViewCamera debugViewCamera(const View& camera, uint32_t mode);

// VoxelDebugView: a picture of the voxel scene from a camera, ray-traced through the occupancy hierarchy: the stored
// radiance of the first voxel hit, or a colour per brick.
class VoxelDebugView {
 public:
  explicit VoxelDebugView(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelScene& scene, DebugView view, const View& camera, VkImage target,
              VkImageView targetView);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
