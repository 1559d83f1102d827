#include "camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ssvgi::renderer {

glm::mat4 viewMatrix(const Camera& camera) { return glm::lookAtRH(camera.position, camera.target, camera.up); }

glm::mat4 reversedZInfiniteProjection(float verticalFov, float aspect, float nearPlane) {
  const float focal = 1.0f / std::tan(verticalFov * 0.5f);
  glm::mat4 projection(0.0f);
  projection[0][0] = focal / aspect;
  projection[1][1] = focal;
  projection[2][3] = -1.0f;      // clip w = view distance along -Z
  projection[3][2] = nearPlane;  // clip z = near, so NDC z = near / distance
  return projection;
}

void setFrameView(shader::FrameConstants& frame, const Camera& camera, uint32_t width, uint32_t height) {
  const float aspect = float(width) / float(height);
  frame.viewProjection = reversedZInfiniteProjection(camera.verticalFov, aspect, camera.nearPlane) * viewMatrix(camera);
  frame.inverseViewProjection = glm::inverse(frame.viewProjection);
  frame.previousViewProjection = frame.viewProjection;
  frame.cameraPositionAndNear = glm::vec4(camera.position, camera.nearPlane);
  frame.cameraForward = glm::vec4(glm::normalize(camera.target - camera.position), 0.0f);
  frame.viewportSize = glm::vec4(width, height, 1.0f / float(width), 1.0f / float(height));
}

}  // namespace ssvgi::renderer
