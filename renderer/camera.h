#pragma once
#include "scene.h"
#include "shared/renderer_interface.h"

#include <glm/glm.hpp>

namespace ssvgi::renderer {

// World -> view (right-handed, looking down -Z).
glm::mat4 viewMatrix(const Camera& camera);

// Reversed-Z perspective with an infinite far plane (SPEC §2): NDC depth = near / view distance along the axis, 1 at the
// near plane, 0 at infinity. NDC +y is up; the renderer flips the viewport.
glm::mat4 reversedZInfiniteProjection(float verticalFov, float aspect, float nearPlane);

// Reversed-Z orthographic projection of the view-space box x ∈ [left, right], y ∈ [bottom, top] between distances
// `nearPlane` and `farPlane` along −Z: NDC depth 1 at the near plane, 0 at the far one.
glm::mat4 reversedZOrthographicProjection(float left, float right, float bottom, float top, float nearPlane,
                                          float farPlane);

// `projection` moved by a fraction of a pixel: `pixels` (x right, y down) of a `width` × `height` image. Perspective
// or orthographic alike: the offset is added in NDC.
glm::mat4 jitteredProjection(const glm::mat4& projection, glm::vec2 pixels, uint32_t width, uint32_t height);

// Sets the fields of a frame's constants that describe its view — `view` and `projection` seen at `width` × `height`
// pixels — with no previous frame (previousViewProjection = viewProjection).
void setFrameView(shader::FrameConstants& frame, const glm::mat4& view, const glm::mat4& projection, uint32_t width,
                  uint32_t height);
// The same for `camera` (perspective, reversed-Z, infinite far plane).
void setFrameView(shader::FrameConstants& frame, const Camera& camera, uint32_t width, uint32_t height);

}  // namespace ssvgi::renderer
