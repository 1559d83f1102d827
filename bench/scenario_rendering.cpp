#include "scenario_rendering.h"

#include "ssvgi/pixel_coordinates.h"

#include "camera.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ssvgi::bench {

namespace {

renderer::RendererSettings rendererSettings(const ScenarioRendering& rendering) {
  renderer::RendererSettings settings;
  settings.width = rendering.width;
  settings.height = rendering.height;
  settings.gi = rendering.gi;
  settings.extraViews = rendering.extraViews;
  settings.litFrameDirectOnly = rendering.litFrameDirectOnly;
  settings.giMemoryBudgetBytes = rendering.giMemoryBudgetBytes;
  return settings;
}

}  // namespace

ScenarioRenderer::ScenarioRenderer(gpu::OwnedDevice& device, const renderer::Scene& scene,
                                   const ScenarioRendering& rendering)
    : scene_(scene), renderer_(device, scene, rendererSettings(rendering)) {}

void ScenarioRenderer::render(const renderer::Camera& camera, uint32_t frames,
                              const std::function<void()>& afterEachFrame) {
  // The scene stands still at time 0 (no camera path, moving object or sun cycle): the scenarios measure the GI of a
  // still view, or of one change they make themselves.
  renderer::AnimatedState state = renderer::evaluateAnimation(scene_, camera, 0.0f);
  state.camera = camera;
  for (uint32_t frame = 0; frame < frames; ++frame) {
    renderer_.render(state);
    if (afterEachFrame) afterEachFrame();
  }
}

SurfacePoints surfacePoints(const renderer::Camera& camera, const renderer::FloatImage& viewDistance) {
  const uint32_t width = viewDistance.width, height = viewDistance.height;
  const glm::mat4 inverseViewProjection = glm::inverse(
      renderer::reversedZInfiniteProjection(camera.verticalFov, float(width) / float(height), camera.nearPlane) *
      renderer::viewMatrix(camera));
  SurfacePoints points;
  points.positions.resize(size_t(width) * height);
  points.isSurface.resize(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const size_t pixel = size_t(y) * width + x;
      const float distance = viewDistance.pixels[pixel];
      if (!(distance > 0.0f)) continue;
      const glm::vec2 ndc = shader::ssvgiPixelToNdc(glm::vec2(x, y), glm::vec2(width, height));  // the pixel's centre
      const glm::vec4 onPlane = inverseViewProjection * glm::vec4(ndc, 0.5f, 1.0f);
      const glm::vec3 direction = glm::normalize(glm::vec3(onPlane) / onPlane.w - camera.position);
      points.positions[pixel] = camera.position + direction * distance;
      points.isSurface[pixel] = true;
    }
  return points;
}

std::vector<double> luminance(const renderer::FloatImage& rgb) {
  std::vector<double> values(size_t(rgb.width) * rgb.height);
  for (size_t pixel = 0; pixel < values.size(); ++pixel) {
    const float* p = &rgb.pixels[pixel * rgb.channels];
    values[pixel] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
  }
  return values;
}

double meanWhere(const std::vector<double>& values, const std::vector<bool>& selected) {
  double sum = 0.0;
  uint64_t count = 0;
  for (size_t i = 0; i < values.size(); ++i)
    if (selected[i]) {
      sum += values[i];
      ++count;
    }
  return count > 0 ? sum / double(count) : 0.0;
}

bool allFinite(const renderer::FloatImage& image) {
  for (const float value : image.pixels)
    if (!std::isfinite(value)) return false;
  return true;
}

double relativeMeanAbsoluteDifference(const renderer::FloatImage& a, const renderer::FloatImage& b,
                                      const std::vector<bool>& selected) {
  double difference = 0.0, reference = 0.0;
  for (size_t pixel = 0; pixel < selected.size(); ++pixel) {
    if (!selected[pixel]) continue;
    for (uint32_t channel = 0; channel < 3; ++channel) {
      const size_t at = pixel * a.channels + channel;
      difference += std::abs(double(a.pixels[at]) - double(b.pixels[at]));
      reference += std::abs(double(b.pixels[at]));
    }
  }
  return reference > 0.0 ? difference / reference : 0.0;
}

void requireLocalLight(const renderer::Scene& scene, uint32_t light, const std::string& scenario) {
  if (light >= scene.lights.size())
    throw std::runtime_error("scenario " + scenario + ": the scene " + scene.name + " has no local light " +
                             std::to_string(light) + " to switch (it has " + std::to_string(scene.lights.size()) + ")");
}

}  // namespace ssvgi::bench
