// Look away (SPEC §6.1): a local light lights the scenario's view; the camera turns to look the other way from the
// same place and the light is switched off as it turns; then it turns back. Two runs side by side, frame for frame:
// this one, and one in which the light was never on. What the light lit kept its light in the voxels while the camera
// looked away; it must be gone by the time the camera is back, or soon after.
#include "scenario_rendering.h"

namespace ssvgi::bench {

LookAwayResult measureLookAway(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                               const LookAwayOptions& options) {
  requireLocalLight(view.scene, options.light, "look-away");
  renderer::Scene switchedScene = view.scene;  // the renderer reads its lights every frame: the switch reaches it
  renderer::Scene neverOnScene = view.scene;
  neverOnScene.lights[options.light].intensity = glm::vec3(0.0f);
  ScenarioRenderer switched(device, switchedScene, rendering);
  ScenarioRenderer neverOn(device, neverOnScene, rendering);
  LookAwayResult result;
  switched.render(view.camera, options.framesBefore);
  neverOn.render(view.camera, options.framesBefore);
  const std::vector<bool> surface = surfacePoints(view.camera, neverOn.renderer().viewDistance()).isSurface;
  result.differenceWithTheLightOn = relativeMeanAbsoluteDifference(
      switched.renderer().indirectIrradiance(), neverOn.renderer().indirectIrradiance(), surface);

  renderer::Camera away = view.camera;
  away.target = view.camera.position - (view.camera.target - view.camera.position);
  switchedScene.lights[options.light].intensity = glm::vec3(0.0f);
  switched.render(away, options.framesAway);
  neverOn.render(away, options.framesAway);

  for (uint32_t frame = 0; frame < options.framesAfter; ++frame) {
    switched.render(view.camera, 1);
    neverOn.render(view.camera, 1);
    result.differenceFromNeverOn.push_back(relativeMeanAbsoluteDifference(
        switched.renderer().indirectIrradiance(), neverOn.renderer().indirectIrradiance(), surface));
    if (result.differenceFromNeverOn.back() >= options.tolerance) result.framesToMatch.reset();
    else if (!result.framesToMatch) result.framesToMatch = frame + 1;
  }
  return result;
}

nlohmann::json toJson(const LookAwayResult& result) {
  return {{"framesToMatch", result.framesToMatch ? nlohmann::json(*result.framesToMatch) : nlohmann::json(nullptr)},
          {"differenceWithTheLightOn", result.differenceWithTheLightOn},
          {"differenceFromNeverOn", result.differenceFromNeverOn}};
}

}  // namespace ssvgi::bench
