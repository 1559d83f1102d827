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

glm::mat4 reversedZOrthographicProjection(float left, float right, float bottom, float top, float nearPlane,
                                          float farPlane) {
  glm::mat4 projection(1.0f);
  projection[0][0] = 2.0f / (right - left);
  projection[1][1] = 2.0f / (top - bottom);
  projection[3][0] = -(right + left) / (right - left);
  projection[3][1] = -(top + bottom) / (top - bottom);
  // NDC depth = (far − distance) / (far − near), with distance = −z.
  projection[2][2] = 1.0f / (farPlane - nearPlane);
  projection[3][2] = farPlane / (farPlane - nearPlane);
  return projection;
}

glm::mat4 jitteredProjection(const glm::mat4& projection, glm::vec2 pixels, uint32_t width, uint32_t height) {
  // NDC +y is up, pixel rows run down.
  const glm::vec2 ndcOffset(2.0f * pixels.x / float(width), -2.0f * pixels.y / float(height));
  return glm::translate(glm::mat4(1.0f), glm::vec3(ndcOffset, 0.0f)) * projection;
}

void setFrameView(shader::FrameConstants& frame, const glm::mat4& view, const glm::mat4& projection, uint32_t width,
                  uint32_t height) {
  frame.viewProjection = projection * view;
  frame.inverseViewProjection = glm::inverse(frame.viewProjection);
  frame.previousViewProjection = frame.viewProjection;
  const glm::mat4 cameraToWorld = glm::inverse(view);
  frame.cameraPosition = cameraToWorld[3];
  frame.cameraForward = -glm::normalize(cameraToWorld[2]);
  frame.viewportSize = glm::vec4(width, height, 1.0f / float(width), 1.0f / float(height));
}

void setFrameView(shader::FrameConstants& frame, const Camera& camera, uint32_t width, uint32_t height) {
  const float aspect = float(width) / float(height);
  setFrameView(frame, viewMatrix(camera), reversedZInfiniteProjection(camera.verticalFov, aspect, camera.nearPlane),
               width, height);
}

}  // namespace ssvgi::renderer
