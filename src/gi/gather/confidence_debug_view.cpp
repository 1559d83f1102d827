#include "confidence_debug_view.h"

#include "gi/voxels/voxel_debug_view.h"
#include "shared/debug_view.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ConfidenceDebugView::ConfidenceDebugView(gpu::Device& device)
    : pipeline_(device, shaders::confidence_debug_view_comp) {}

void ConfidenceDebugView::record(gpu::CommandList& commands, const VoxelScene& scene, const GatherTargets& targets,
                                 const gpu::Buffer& probes, const View& camera, VkImage target,
                                 VkImageView targetView) {
  auto scope = commands.scope("ssvgi: ConfidenceDebugView");
  commands.useExternalImage(target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  const shader::ConfidenceDebugViewPush push{debugViewCamera(camera, 0u)};
  const gpu::Bindings bindings = scene.bindings()
                                     .buffer(shader::kBindGatherConstants, targets.constants())
                                     .buffer(shader::kBindGatherProbes, probes)
                                     .externalStorage(shader::kBindGatherDebugTarget, targetView);
  commands.dispatch(pipeline_, bindings, {camera.width, camera.height, 1}, push);
}

}  // namespace ssvgi::gi
