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

// Sets the fields of a frame's constants that describe its view: `camera` seen at `width` × `height` pixels, with no
// previous frame (previousViewProjection = viewProjection).
void setFrameView(shader::FrameConstants& frame, const Camera& camera, uint32_t width, uint32_t height);

}  // namespace ssvgi::renderer
