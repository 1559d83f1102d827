#ifndef SSVGI_SHARED_VOXEL_DEBUG_VIEW_H
#define SSVGI_SHARED_VOXEL_DEBUG_VIEW_H
#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

struct VoxelDebugViewPush {
  mat4 inverseViewProjection;  // the debug camera, reversed-Z
  vec4 cameraPosition;
  uvec4 sizeAndMode;           // x, y: image size; z: 0 voxel radiance, 1 brick colours
};
SSVGI_CHECK_SIZE(VoxelDebugViewPush, 96);

SSVGI_SHARED_END

#endif
