#include "scene.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ssvgi::renderer {

Bounds worldBounds(const Scene& scene) {
  glm::vec3 low(std::numeric_limits<float>::max());
  glm::vec3 high(std::numeric_limits<float>::lowest());
  for (const Instance& instance : scene.instances) {
    for (const Vertex& vertex : scene.meshes[instance.mesh].vertices) {
      const glm::vec3 world(instance.transform * glm::vec4(vertex.position, 1.0f));
      low = glm::min(low, world);
      high = glm::max(high, world);
    }
  }
  if (low.x > high.x) return {};
  return {low, high};
}

float giDetailScaleFor(const Bounds& bounds, const glm::vec3& viewpoint) {
  constexpr float kTierProbeSpacing = 1.0f;  // metres, every tier's (ssvgi::settingsForTier)
  constexpr float kFinestScale = 1.0f / 16.0f;
  const glm::vec3 extent = bounds.max - bounds.min;
  const float middleExtent =
      std::max(std::min(extent.x, extent.y), std::min(std::max(extent.x, extent.y), extent.z));
  const float viewDistance = glm::distance(viewpoint, 0.5f * (bounds.min + bounds.max));
  float scale = 1.0f;
  while (scale > kFinestScale && middleExtent < kGiProbeSpacingsAcrossScene * kTierProbeSpacing * scale &&
         viewDistance <= kGiProbeSpacingsToViewpoint * kTierProbeSpacing * 0.5f * scale)
    scale *= 0.5f;
  return scale;
}

glm::vec3 sunDirection(float azimuthDegrees, float elevationDegrees) {
  const float azimuth = glm::radians(azimuthDegrees);
  const float elevation = glm::radians(elevationDegrees);
  return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
}

namespace {

// The camera on a looping path of keys sorted by time; before the first key's time it waits at the first key.
Camera cameraOnPath(const std::vector<CameraKey>& path, const Camera& baseCamera, float seconds) {
  Camera camera = baseCamera;
  const float loopLength = path.back().time;
  const float t = loopLength > 0.0f ? seconds - loopLength * std::floor(seconds / loopLength) : 0.0f;
  // The first key later than t; the pose lies between it and the key before.
  const auto next =
      std::upper_bound(path.begin(), path.end(), t, [](float time, const CameraKey& key) { return time < key.time; });
  if (next == path.begin() || next == path.end()) {
    const CameraKey& key = next == path.begin() ? path.front() : path.back();
    camera.position = key.position;
    camera.target = key.target;
    return camera;
  }
  const CameraKey& previous = *(next - 1);
  const float blend = (t - previous.time) / (next->time - previous.time);
  camera.position = glm::mix(previous.position, next->position, blend);
  camera.target = glm::mix(previous.target, next->target, blend);
  return camera;
}

}  // namespace

AnimatedState evaluateAnimation(const Scene& scene, const Camera& baseCamera, float seconds) {
  AnimatedState state;
  state.camera = scene.cameraPath.empty() ? baseCamera : cameraOnPath(scene.cameraPath, baseCamera, seconds);

  if (scene.movingObject) {
    const MovingObject& moving = *scene.movingObject;
    // A cosine ease: at rest at both ends of the segment, so the motion has no jolt where it turns.
    const float phase = moving.period > 0.0f ? glm::two_pi<float>() * seconds / moving.period : 0.0f;
    const float travelled = 0.5f - 0.5f * std::cos(phase);
    state.movingObjectTransform =
        glm::translate(glm::mat4(1.0f), moving.offset * travelled) * scene.instances[moving.instance].transform;
  }

  state.sun = scene.sun;
  if (scene.sunCycle) {
    const SunCycle& cycle = *scene.sunCycle;
    state.sun.direction = sunDirection(cycle.azimuthDegrees + cycle.azimuthDegreesPerSecond * seconds,
                                       cycle.elevationDegrees + cycle.elevationDegreesPerSecond * seconds);
  }
  return state;
}

}  // namespace ssvgi::renderer
