// A camera cut: the camera jumps in one frame — a teleport, a 180° turn. Everything ssvgi kept of the old view is then
// misplaced or out of view: the temporal filter's history reprojects to nothing, the clipmaps scroll by whole slabs,
// probes and voxels of the new view are new. The images must stay finite through it, and the GI must return to what a
// run that sat at the new view from its first frame shows. The two runs are rendered side by side, frame for frame,
// so that both are at the same frame index (the gather's jitter, the probes' level and ray set) when compared.
// What is kept of the old view may still be right at the new one: the voxels of walls seen before, the space the views
// observed (SPEC §6.4). The run after the cut then knows more than the one that sat at the new view, and differs from
// it for good; the path-traced reference of the new view tells which of the two is further from the truth.
#include "image_compare.h"
#include "path_tracer.h"
#include "scenario_rendering.h"

#include <algorithm>
#include <functional>

namespace ssvgi::bench {

namespace {

// Adds `image` into `sum` (both of one size and channel count; `sum` empty: becomes a copy).
void accumulate(renderer::FloatImage& sum, const renderer::FloatImage& image) {
  if (sum.pixels.empty()) {
    sum = image;
    return;
  }
  std::transform(sum.pixels.begin(), sum.pixels.end(), image.pixels.begin(), sum.pixels.begin(), std::plus<float>());
}

renderer::FloatImage referenceIndirect(gpu::OwnedDevice& device, const ScenarioRendering& rendering,
                                       const ScenarioView& view, const renderer::Camera& camera, uint32_t samples) {
  renderer::AnimatedState state = renderer::evaluateAnimation(view.scene, camera, 0.0f);
  state.camera = camera;
  reference::PathTracerSettings settings;
  settings.width = rendering.width;
  settings.height = rendering.height;
  reference::PathTracer tracer(device, view.scene, state, settings);
  tracer.trace(samples);
  return tracer.indirectIrradiance();
}

}  // namespace

CameraCutResult measureCameraCut(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                                 const CameraCutOptions& options) {
  ScenarioRenderer cut(device, view.scene, rendering);
  ScenarioRenderer settled(device, view.scene, rendering);
  cut.render(view.camera, options.framesBefore);
  settled.render(options.to, options.framesBefore);

  const std::vector<bool> surface = surfacePoints(options.to, settled.renderer().viewDistance()).isSurface;

  CameraCutResult result;
  renderer::FloatImage cutSum, settledSum;  // E_indirect over the last kCutFramesAgainstReference frames
  for (uint32_t frame = 0; frame < options.framesAfter; ++frame) {
    cut.render(options.to, 1);
    settled.render(options.to, 1);
    const renderer::FloatImage indirect = cut.renderer().indirectIrradiance();
    const renderer::FloatImage settledIndirect = settled.renderer().indirectIrradiance();
    result.allFinite = result.allFinite && allFinite(indirect) && allFinite(cut.renderer().finalRadiance());
    result.differenceFromSettled.push_back(relativeMeanAbsoluteDifference(indirect, settledIndirect, surface));
    if (result.differenceFromSettled.back() >= options.recoveryTolerance) result.framesToRecover.reset();
    else if (!result.framesToRecover) result.framesToRecover = frame + 1;
    if (frame + kCutFramesAgainstReference >= options.framesAfter) {
      accumulate(cutSum, indirect);
      accumulate(settledSum, settledIndirect);
    }
  }
  if (options.referenceSamples > 0) {
    const renderer::FloatImage reference =
        referenceIndirect(device, rendering, view, options.to, options.referenceSamples);
    const reference::PixelMask mask = reference::maskFromDepth(settled.renderer().viewDistance());
    const auto errorOf = [&](const renderer::FloatImage& sum) {
      renderer::FloatImage mean = sum;
      const float frames = float(std::min(kCutFramesAgainstReference, options.framesAfter));
      for (float& value : mean.pixels) value /= frames;
      return reference::compareImages(mean, reference, &mask, 4).relativeMeanAbsoluteError;
    };
    result.errorAfterCut = errorOf(cutSum);
    result.errorSettled = errorOf(settledSum);
  }
  return result;
}

nlohmann::json toJson(const CameraCutResult& result) {
  return {{"allFinite", result.allFinite},
          {"framesToRecover", result.framesToRecover ? nlohmann::json(*result.framesToRecover) : nlohmann::json(nullptr)},
          {"differenceFromSettled", result.differenceFromSettled},
          {"errorAfterCut", result.errorAfterCut ? nlohmann::json(*result.errorAfterCut) : nlohmann::json(nullptr)},
          {"errorSettled", result.errorSettled ? nlohmann::json(*result.errorSettled) : nlohmann::json(nullptr)}};
}

}  // namespace ssvgi::bench
