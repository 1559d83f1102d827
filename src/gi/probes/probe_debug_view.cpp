#include "probe_debug_view.h"

#include "gi/voxels/voxel_debug_view.h"
#include "shared/debug_view.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeDebugView::ProbeDebugView(gpu::Device& device) : pipeline_(device, shaders::probe_debug_view_comp) {}

void ProbeDebugView::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes,
                            glm::vec3 probeCamera, const View& camera, VkImage target, VkImageView targetView) {
  auto scope = commands.scope("ssvgi: ProbeDebugView");
  commands.useExternalImage(target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  const glm::ivec3 dimensions = probes.current().probesPerAxis;
  const shader::ProbeDebugViewPush push{
      debugViewCamera(camera, 0u),
      probes.levelOrigin(0, probeCamera), probes.levelSpacing(0), dimensions, int(probes.probesPerLevel())};
  const gpu::Bindings bindings = scene.bindings()
                                     .externalStorage(shader::kBindFirstPassSlot, targetView)
                                     .buffer(shader::kBindProbes, probes.probes());
  commands.dispatch(pipeline_, bindings, {camera.width, camera.height, 1}, push);
}

}  // namespace ssvgi::gi
