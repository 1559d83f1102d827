#ifndef SSVGI_GI_FRAME_GLSL
#define SSVGI_GI_FRAME_GLSL
#include "shared/gi_frame.h"

layout(binding = kBindGiFrame) uniform GiFrameBlock { GiFrame frame; };

vec3 reconstructPosition(mat4 inverseViewProjection, vec2 pixel, vec2 size, float depth) {
  vec4 world = inverseViewProjection * vec4(giPixelToNdc(pixel, size), depth, 1.0);
  return world.xyz / world.w;
}

#endif
