// A camera cut: the camera jumps in one frame — a teleport, a 180° turn. Everything ssvgi kept of the old view is then
// misplaced or out of view: the temporal filter's history reprojects to nothing, the clipmaps scroll by whole slabs,
// probes and voxels of the new view are new. The images must stay finite through it, and the GI must return to what a
// run that sat at the new view from its first frame shows. The two runs are rendered side by side, frame for frame,
// so that both are at the same frame index (the gather's jitter, the probes' level and ray set) when compared.
#include "scenario_rendering.h"

namespace ssvgi::bench {

CameraCutResult measureCameraCut(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                                 const CameraCutOptions& options) {
  ScenarioRenderer cut(device, view.scene, rendering);
  ScenarioRenderer settled(device, view.scene, rendering);
  cut.render(view.camera, options.framesBefore);
  settled.render(options.to, options.framesBefore);

  const std::vector<bool> surface = surfacePoints(options.to, settled.renderer().viewDistance()).isSurface;

  CameraCutResult result;
  for (uint32_t frame = 0; frame < options.framesAfter; ++frame) {
    cut.render(options.to, 1);
    settled.render(options.to, 1);
    const renderer::FloatImage indirect = cut.renderer().indirectIrradiance();
    result.allFinite = result.allFinite && allFinite(indirect) && allFinite(cut.renderer().finalRadiance());
    result.differenceFromSettled.push_back(
        relativeMeanAbsoluteDifference(indirect, settled.renderer().indirectIrradiance(), surface));
    if (result.differenceFromSettled.back() >= options.recoveryTolerance) result.framesToRecover.reset();
    else if (!result.framesToRecover) result.framesToRecover = frame + 1;
  }
  return result;
}

nlohmann::json toJson(const CameraCutResult& result) {
  return {{"allFinite", result.allFinite},
          {"framesToRecover", result.framesToRecover ? nlohmann::json(*result.framesToRecover) : nlohmann::json(nullptr)},
          {"differenceFromSettled", result.differenceFromSettled}};
}

}  // namespace ssvgi::bench
