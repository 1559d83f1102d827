#include "voxel_debug_view.h"

#include "shared/voxel_debug_view.h"
#include "ssvgi_shaders.h"

#include <glm/gtc/type_ptr.hpp>

namespace ssvgi::gi {

VoxelDebugView::VoxelDebugView(gpu::Device& device) : pipeline_(device, shaders::voxel_debug_view_comp) {}

void VoxelDebugView::record(gpu::CommandList& commands, const VoxelScene& scene, DebugView view, const View& camera,
                            VkImage target, VkImageView targetView) {
  auto scope = commands.scope("ssvgi: VoxelDebugView");
  commands.useExternalImage(target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  shader::VoxelDebugViewPush push{};
  push.inverseViewProjection = glm::inverse(glm::make_mat4(camera.viewProjection.data()));
  push.cameraPosition = glm::vec4(camera.position[0], camera.position[1], camera.position[2], 0.0f);
  push.sizeAndMode = glm::uvec4(camera.width, camera.height, view == DebugView::Bricks ? 1u : 0u, 0u);
  commands.dispatch(pipeline_, scene.bindings().externalStorage(shader::kBindFirstPassSlot, targetView),
                    {camera.width, camera.height, 1}, push);
}

}  // namespace ssvgi::gi
