#ifndef SSVGI_GI_FRAME_GLSL
#define SSVGI_GI_FRAME_GLSL
#include "shared/gi_frame.h"

// Constants are std140 read-only storage blocks, never uniform blocks: lavapipe recompiles a shader on every bind when
// its branches read a uniform block (docs/ARCHITECTURE.md, "The Vulkan layer"). The same holds for every constant
// block of the library, the renderer and the reference.
layout(binding = kBindGiFrame, std140) readonly buffer GiFrameBlock { GiFrame frame; };

vec3 reconstructPosition(mat4 inverseViewProjection, vec2 pixel, vec2 size, float depth) {
  vec4 world = inverseViewProjection * vec4(ssvgiPixelToNdc(pixel, size), depth, 1.0);
  return world.xyz / world.w;
}

// The direction a view looks along through a point of its image, towards greater depth: from the eye through the point
// for a perspective view, the view's axis for an orthographic one. Found from the view-projection alone, by
// unprojecting the point at the near plane (NDC depth 1) and halfway to the far plane (0.5; a perspective view's far
// plane, 0, lies at infinity).
vec3 viewRayDirection(mat4 inverseViewProjection, vec2 ndc) {
  vec4 nearPoint = inverseViewProjection * vec4(ndc, 1.0, 1.0);
  vec4 fartherPoint = inverseViewProjection * vec4(ndc, 0.5, 1.0);
  return normalize(fartherPoint.xyz / fartherPoint.w - nearPoint.xyz / nearPoint.w);
}

#endif
