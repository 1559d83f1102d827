#include "fly_camera.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>

namespace ssvgi::cli {

namespace {

constexpr float kRadiansPerPixel = 0.004f;
// The view stays short of straight up or down, where yaw has no meaning.
constexpr float kMaxPitch = 0.49f * glm::pi<float>();

}  // namespace

FlyCamera::FlyCamera(const renderer::Camera& camera)
    : camera_(camera),
      // In proportion to the first view's distance to its target: a Cornell box and a courtyard both cross in seconds.
      speed_(std::clamp(glm::length(camera.target - camera.position), 0.5f, 20.0f)) {}

void FlyCamera::place(const renderer::Camera& camera) { camera_ = camera; }

void FlyCamera::update(const Input& input, float seconds) {
  speed_ *= std::pow(1.25f, input.speedSteps);
  glm::vec3 forward = glm::normalize(camera_.target - camera_.position);
  if (input.turn != glm::vec2(0.0f)) {
    const float yaw = std::atan2(forward.x, forward.z) - input.turn.x * kRadiansPerPixel;
    const float pitch = std::clamp(std::asin(std::clamp(forward.y, -1.0f, 1.0f)) - input.turn.y * kRadiansPerPixel,
                                   -kMaxPitch, kMaxPitch);
    forward = {std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)};
    camera_.target = camera_.position + forward;
  }
  if (input.move != glm::vec3(0.0f)) {
    const glm::vec3 right = glm::normalize(glm::cross(forward, camera_.up));
    const glm::vec3 step = (right * input.move.x + camera_.up * input.move.y + forward * input.move.z) *
                           (speed_ * seconds);
    camera_.position += step;
    camera_.target += step;
  }
}

}  // namespace ssvgi::cli
