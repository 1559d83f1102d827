// The debug views of Context::debugView (SPEC §6.6): what ssvgi knows, ray-traced from a camera through its voxels.
#ifndef SSVGI_SHARED_DEBUG_VIEW_H
#define SSVGI_SHARED_DEBUG_VIEW_H
#include "shared/glsl_cpp.h"
#include "ssvgi/pixel_coordinates.h"

SSVGI_SHARED_BEGIN

struct DebugViewCamera {
  mat4 inverseViewProjection;  // the debug camera, reversed-Z
  vec3 position;
  uint mode;                   // the view's mode (each pass says what its modes are)
  uvec2 size;                  // the image's, pixels
  uvec2 unused;
};
SSVGI_CHECK_SIZE(DebugViewCamera, 96);

// VoxelDebugView: mode 0 the voxels' radiance, 1 a colour per brick, 2 the voxels' radiance up to unobserved space.
struct VoxelDebugViewPush {
  DebugViewCamera camera;
};
SSVGI_CHECK_SIZE(VoxelDebugViewPush, 96);

// ProbeDebugView: the finest probe level as it stood in the last dispatch.
struct ProbeDebugViewPush {
  DebugViewCamera camera;
  ivec3 probeOrigin;      // world probe coordinate of level 0's minimum corner
  float probeSpacing;     // level 0's, metres
  ivec3 probeDimensions;  // probes per level and axis
  int probesPerLevel;
};
SSVGI_CHECK_SIZE(ProbeDebugViewPush, 128);

// ConfidenceDebugView: the confidence the gather gives the surfaces the camera's rays meet in the voxels.
struct ConfidenceDebugViewPush {
  DebugViewCamera camera;
};
SSVGI_CHECK_SIZE(ConfidenceDebugViewPush, 96);

// The unit direction of the camera ray through a pixel's centre (rows top to bottom).
SSVGI_INLINE vec3 debugViewDirection(DebugViewCamera camera, uvec2 pixel) {
  vec2 ndc = ssvgiPixelToNdc(vec2(pixel), vec2(camera.size));
  vec4 onPlane = camera.inverseViewProjection * vec4(ndc, 0.5f, 1.0f);
  return normalize(vec3(onPlane) / onPlane.w - vec3(camera.position));
}

SSVGI_SHARED_END

#endif
