// SPEC §7 lag: a local light is switched on (or off) in a converged scene, and the indirect irradiance moves to its new
// steady state through the voxel → probe loop (the lit frame and the views carry the new direct light into the
// voxels, the probes trace them, the relight and the gather pass it on). The renderer uploads Scene::lights every
// frame, so the switch is the light's intensity going from zero to its value, or back, between two frames. The
// scene's emissive surfaces and its other lights stay on: the old steady state is not zero, and the lag is counted on
// the way from the old state to the new.
#include "scenario_rendering.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>

namespace ssvgi::bench {

namespace {

// SPEC §4.5: one of the three probe levels is updated per frame.
constexpr uint32_t kFramesPerProbeUpdate = 3;
// SPEC §6.2: 90 % of the new steady state within 8 updates of each probe.
constexpr uint32_t kTargetProbeUpdates = 8;
constexpr double kLagFraction = 0.9;

}  // namespace

LagResult measureLag(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                     const LagOptions& options) {
  requireLocalLight(view.scene, options.light, "lag");
  if (options.steadyFrames == 0 || options.steadyFrames > options.convergenceFrames)
    throw std::runtime_error("scenario lag: the steady frames must be 1 to the frames before the switch");
  const uint32_t frames = options.convergenceFrames + options.framesAfterSwitch;
  if (options.settledMeanFrames == 0 || options.settledMeanFrames > std::max(frames, options.settledRunFrames))
    throw std::runtime_error("scenario lag: the settled run's averaged frames must be 1 to the frames it renders");

  // Two runs side by side, frame for frame: the switched one, and the settled one with the light as the switch leaves
  // it all along, which then goes on alone until it has converged: its last frames are the new steady state (the
  // loop converges over many frames, so the switched run's own last frames would still be on their way). Where that
  // state is known, the switched run alone.
  renderer::Scene switchedScene = view.scene;  // the renderer reads its lights every frame: the switch reaches it
  renderer::Scene settledScene = view.scene;
  const glm::vec3 intensityOn = view.scene.lights[options.light].intensity;
  const glm::vec3 intensityBefore = options.switchOff ? intensityOn : glm::vec3(0.0f);
  const glm::vec3 intensityAfter = options.switchOff ? glm::vec3(0.0f) : intensityOn;
  renderer::LocalLight& light = switchedScene.lights[options.light];
  light.intensity = intensityBefore;
  settledScene.lights[options.light].intensity = intensityAfter;
  ScenarioRenderer switched(device, switchedScene, rendering);
  std::optional<ScenarioRenderer> settled;
  if (!options.knownIrradianceAfter) settled.emplace(device, settledScene, rendering);

  std::vector<bool> surface;
  std::vector<double> switchedIrradiance, settledIrradiance;
  for (uint32_t frame = 0; frame < frames; ++frame) {
    if (frame == options.convergenceFrames) light.intensity = intensityAfter;
    switched.render(view.camera, 1);
    if (surface.empty()) surface = surfacePoints(view.camera, switched.renderer().viewDistance()).isSurface;
    switchedIrradiance.push_back(meanWhere(luminance(switched.renderer().indirectIrradiance()), surface));
    if (!settled) continue;
    settled->render(view.camera, 1);
    settledIrradiance.push_back(meanWhere(luminance(settled->renderer().indirectIrradiance()), surface));
  }
  // The mean of `count` frames of a run, the last of them `end` − 1.
  const auto meanOfFrames = [](const std::vector<double>& irradiance, size_t end, size_t count) {
    return std::accumulate(irradiance.begin() + ptrdiff_t(end - count), irradiance.begin() + ptrdiff_t(end), 0.0) /
           double(count);
  };
  while (settled && settledIrradiance.size() < options.settledRunFrames) {
    settled->render(view.camera, 1);
    settledIrradiance.push_back(meanWhere(luminance(settled->renderer().indirectIrradiance()), surface));
  }
  const size_t settledFrames = settledIrradiance.size();
  const double before = meanOfFrames(switchedIrradiance, options.convergenceFrames, options.steadyFrames);
  const double after = options.knownIrradianceAfter
                           ? *options.knownIrradianceAfter
                           : meanOfFrames(settledIrradiance, settledFrames, options.settledMeanFrames);
  if (options.switchOff ? !(after < before) : !(after > before))
    throw std::runtime_error(options.switchOff
                                 ? "scenario lag: switching the light off did not lower the indirect irradiance"
                                 : "scenario lag: switching the light on did not raise the indirect irradiance");

  LagResult result;
  result.irradianceBefore = before;
  result.irradianceAfter = after;
  result.settledRunFrames = uint32_t(settledFrames);
  result.targetFrames = kTargetProbeUpdates * kFramesPerProbeUpdate;
  for (size_t frame = options.convergenceFrames; frame < frames; ++frame) {
    result.progress.push_back((switchedIrradiance[frame] - before) / (after - before));
    if (!result.framesToNinetyPercent && result.progress.back() >= kLagFraction)
      result.framesToNinetyPercent = uint32_t(result.progress.size());
  }
  for (size_t frame = 0; frame < settledFrames && !result.settledRunFramesToNinetyPercent; ++frame)
    if (std::abs(settledIrradiance[frame] - after) <= (1.0 - kLagFraction) * after)
      result.settledRunFramesToNinetyPercent = uint32_t(frame + 1);
  if (settledFrames >= 2 * options.settledMeanFrames)
    result.steadyDrift =
        after / meanOfFrames(settledIrradiance, settledFrames - options.settledMeanFrames, options.settledMeanFrames) -
        1.0;
  return result;
}

nlohmann::json toJson(const LagResult& result) {
  return {{"framesToNinetyPercent",
           result.framesToNinetyPercent ? nlohmann::json(*result.framesToNinetyPercent) : nlohmann::json(nullptr)},
          {"targetFrames", result.targetFrames},
          {"settledRunFramesToNinetyPercent", result.settledRunFramesToNinetyPercent
                                                  ? nlohmann::json(*result.settledRunFramesToNinetyPercent)
                                                  : nlohmann::json(nullptr)},
          {"steadyDrift", result.steadyDrift},
          {"settledRunFrames", result.settledRunFrames},
          {"irradianceBefore", result.irradianceBefore},
          {"irradianceAfter", result.irradianceAfter},
          {"progress", result.progress}};
}

}  // namespace ssvgi::bench
