// SPEC §7 lag: a local light is switched on in a converged scene, and the indirect irradiance climbs to its new steady
// state through the loop of SPEC §3 (the lit frame carries the new direct light into the voxels, the probes trace them,
// the gather and its temporal filter pass it on). The renderer uploads Scene::lights every frame, so the switch is the
// light's intensity going from zero to its value between two frames. The scene's emissive surfaces and its other
// lights stay on: the old steady state is not zero, and the lag is counted on the way from the old state to the new.
#include "scenario_rendering.h"

#include <numeric>
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

LagResult measureLag(gpu::Device& device, const ScenarioRendering& rendering, const ScenarioView& view,
                     const LagOptions& options) {
  if (options.light >= view.scene.lights.size())
    throw std::runtime_error("scenario lag: the scene " + view.scene.name + " has no local light " +
                             std::to_string(options.light) + " to switch (it has " +
                             std::to_string(view.scene.lights.size()) + ")");
  if (options.steadyFrames == 0 || options.steadyFrames > options.framesAfterSwitch)
    throw std::runtime_error("scenario lag: the steady frames must be 1 to the frames after the switch");

  renderer::Scene scene = view.scene;  // the renderer reads its lights every frame: the switch below reaches it
  renderer::LocalLight& light = scene.lights[options.light];
  const glm::vec3 intensityOn = light.intensity;
  light.intensity = glm::vec3(0.0f);

  ScenarioRenderer renderer(device, scene, rendering);
  renderer::Renderer& frame = renderer.renderer();
  renderer.render(view.camera, options.convergenceFrames);
  const std::vector<bool> surface = surfacePoints(view.camera, frame.viewDistance()).isSurface;
  const double before = meanWhere(luminance(frame.indirectIrradiance()), surface);

  light.intensity = intensityOn;
  std::vector<double> irradiance;
  renderer.render(view.camera, options.framesAfterSwitch,
                  [&] { irradiance.push_back(meanWhere(luminance(frame.indirectIrradiance()), surface)); });
  const double after = std::accumulate(irradiance.end() - options.steadyFrames, irradiance.end(), 0.0) /
                       double(options.steadyFrames);
  if (!(after > before))
    throw std::runtime_error("scenario lag: switching the light on did not raise the indirect irradiance");

  LagResult result;
  result.irradianceBefore = before;
  result.irradianceAfter = after;
  result.targetFrames = kTargetProbeUpdates * kFramesPerProbeUpdate;
  for (size_t index = 0; index < irradiance.size(); ++index) {
    result.progress.push_back((irradiance[index] - before) / (after - before));
    if (!result.framesToNinetyPercent && result.progress.back() >= kLagFraction)
      result.framesToNinetyPercent = uint32_t(index + 1);
  }
  return result;
}

nlohmann::json toJson(const LagResult& result) {
  return {{"framesToNinetyPercent",
           result.framesToNinetyPercent ? nlohmann::json(*result.framesToNinetyPercent) : nlohmann::json(nullptr)},
          {"targetFrames", result.targetFrames},
          {"irradianceBefore", result.irradianceBefore},
          {"irradianceAfter", result.irradianceAfter},
          {"progress", result.progress}};
}

}  // namespace ssvgi::bench
