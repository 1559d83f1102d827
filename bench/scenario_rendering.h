#pragma once
// What the scenarios of scenarios.h share: a renderer with ssvgi on a still view, and the figures taken of its images.
#include "image_io.h"
#include "renderer.h"
#include "scenarios.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ssvgi::bench {

// The host renderer with ssvgi compositing its indirect light, rendering a still scene (animation time 0) from a
// camera the scenario chooses per frame.
class ScenarioRenderer {
 public:
  ScenarioRenderer(gpu::OwnedDevice& device, const renderer::Scene& scene, const ScenarioRendering& rendering);

  // Renders `frames` frames from `camera`; `afterEachFrame` (if given) sees each of them.
  void render(const renderer::Camera& camera, uint32_t frames, const std::function<void()>& afterEachFrame = {});

  renderer::Renderer& renderer() { return renderer_; }

 private:
  const renderer::Scene& scene_;
  renderer::Renderer renderer_;
};

// Throws std::runtime_error (one line naming the scenario and the scene) unless the scene has local light `light`,
// which the scenario switches.
void requireLocalLight(const renderer::Scene& scene, uint32_t light, const std::string& scenario);

// Where each pixel's surface is in the world, from the camera and the view distance (Renderer::viewDistance); nothing
// for a pixel without a surface.
struct SurfacePoints {
  std::vector<glm::vec3> positions;  // per pixel, row by row from the top
  std::vector<bool> isSurface;       // per pixel
};
SurfacePoints surfacePoints(const renderer::Camera& camera, const renderer::FloatImage& viewDistance);

// Rec. 709 luminance 0.2126 R + 0.7152 G + 0.0722 B of each pixel of an RGB image (as `ssvgi compare`'s SSIM).
std::vector<double> luminance(const renderer::FloatImage& rgb);

// The mean of `values` over the pixels where `selected` holds; 0 when none does.
double meanWhere(const std::vector<double>& values, const std::vector<bool>& selected);

// Σ|a − b| / Σ|b| over the pixels where `selected` holds and the colour channels (RGB images of the same size).
double relativeMeanAbsoluteDifference(const renderer::FloatImage& a, const renderer::FloatImage& b,
                                      const std::vector<bool>& selected);

// True when no channel of any pixel is NaN or infinite.
bool allFinite(const renderer::FloatImage& image);

}  // namespace ssvgi::bench
