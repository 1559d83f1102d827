#include "voxel_debug_view.h"

#include "shared/debug_view.h"
#include "ssvgi_shaders.h"

#include <glm/gtc/type_ptr.hpp>

namespace ssvgi::gi {

shader::DebugViewCamera debugViewCamera(const View& camera, uint32_t mode) {
  return {glm::inverse(glm::make_mat4(camera.viewProjection.data())),
          glm::vec3(camera.position[0], camera.position[1], camera.position[2]), mode,
          glm::uvec2(camera.width, camera.height), glm::uvec2(0u)};
}

VoxelDebugView::VoxelDebugView(gpu::Device& device) : pipeline_(device, shaders::voxel_debug_view_comp) {}

void VoxelDebugView::record(gpu::CommandList& commands, const VoxelScene& scene, DebugView view, const View& camera,
                            VkImage target, VkImageView targetView) {
  auto scope = commands.scope("ssvgi: VoxelDebugView");
  commands.useExternalImage(target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  const shader::VoxelDebugViewPush push{debugViewCamera(camera, view == DebugView::Bricks ? 1u : (view == DebugView::ObservedSpace ? 2u : 0u))};
  commands.dispatch(pipeline_, scene.bindings().externalStorage(shader::kBindFirstPassSlot, targetView),
                    {camera.width, camera.height, 1}, push);
}

}  // namespace ssvgi::gi
