// SPEC §7 flicker: in a converged still scene nothing changes but the GI's own noise — the gather's jittered sample
// pixel, the probes' rotating ray sets — so the frame-to-frame relative change of the final image measures how much of
// that noise reaches the screen.
#include "scenario_rendering.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ssvgi::bench {

namespace {

// A pixel's relative change is |a − b| over their mean. Below this fraction of the frame's mean luminance a pixel is
// black to the eye whatever its relative change (0.1 % is under one 8-bit step of the tonemapped image at the
// average's brightness), so the denominator is held at least this large: a near-black pixel's tiny absolute noise is
// not read as a large flicker.
constexpr double kDarkFloorOfMean = 1e-3;

// Accumulates the mean relative change between consecutive frames of one image over the selected pixels.
class RelativeChange {
 public:
  void add(const std::vector<double>& previous, const std::vector<double>& current, const std::vector<bool>& selected) {
    const double floor = kDarkFloorOfMean * std::max(meanWhere(current, selected), 1e-30);
    for (size_t pixel = 0; pixel < current.size(); ++pixel) {
      if (!selected[pixel]) continue;
      const double mean = 0.5 * (previous[pixel] + current[pixel]);
      sum_ += std::abs(current[pixel] - previous[pixel]) / std::max(mean, floor);
      ++count_;
    }
  }
  double mean() const { return count_ > 0 ? sum_ / double(count_) : 0.0; }

 private:
  double sum_ = 0.0;
  uint64_t count_ = 0;
};

}  // namespace

FlickerResult measureFlicker(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                             const FlickerOptions& options) {
  ScenarioRenderer renderer(device, view.scene, rendering);
  renderer.render(view.camera, options.convergenceFrames);

  renderer::Renderer& frame = renderer.renderer();
  const std::vector<bool> surface = surfacePoints(view.camera, frame.viewDistance()).isSurface;
  const uint64_t pixels = uint64_t(std::count(surface.begin(), surface.end(), true));
  if (pixels == 0) throw std::runtime_error("scenario flicker: the view shows no surface");

  std::vector<double> finalBefore = luminance(frame.finalRadiance());
  const double firstMean = meanWhere(finalBefore, surface);
  std::vector<double> indirectBefore = luminance(frame.indirectIrradiance());
  RelativeChange finalChange, indirectChange;
  renderer.render(view.camera, options.measuredFrames, [&] {
    std::vector<double> finalNow = luminance(frame.finalRadiance());
    std::vector<double> indirectNow = luminance(frame.indirectIrradiance());
    finalChange.add(finalBefore, finalNow, surface);
    indirectChange.add(indirectBefore, indirectNow, surface);
    finalBefore = std::move(finalNow);
    indirectBefore = std::move(indirectNow);
  });
  const double lastMean = meanWhere(finalBefore, surface);
  const double drift = (lastMean - firstMean) / std::max(0.5 * (firstMean + lastMean), 1e-30) / options.measuredFrames;
  return {finalChange.mean(), indirectChange.mean(), drift, pixels};
}

nlohmann::json toJson(const FlickerResult& result) {
  return {{"flicker", result.finalImageFlicker},
          {"indirectFlicker", result.indirectFlicker},
          {"driftPerFrame", result.driftPerFrame},
          {"pixels", result.pixels}};
}

}  // namespace ssvgi::bench
