// What the GI passes know of the frame: the current view and the latest lit frame's (SPEC §3), the Hi-Z pyramid's
// layout, and the culling planes. One uniform buffer per frame in flight.
#ifndef SSVGI_SHARED_GI_FRAME_H
#define SSVGI_SHARED_GI_FRAME_H

#include "shared/glsl_cpp.h"
#include "ssvgi/pixel_coordinates.h"

SSVGI_SHARED_BEGIN

SSVGI_CONSTANT(uint, kBindGiFrame, 5u);  // GiFrame (uniform), beside the voxel scene's shared slots
SSVGI_CONSTANT(uint, kMaxHiZLevels, 16u);

// The views the voxels are injected from (SPEC §3, §6.3). The voxel passes run once per view with that view's GiFrame,
// in which the "current" and the "lit" camera are both the view's (for the camera, they are this frame's and the
// lit frame's). The view's kind is a combination of these bits (none: the camera's lit frame, its colour all light):
SSVGI_CONSTANT(uint, kViewIsExtra, 1u);       // one of the host's extra views, not the camera's lit frame
SSVGI_CONSTANT(uint, kViewIsDirectOnly, 2u);  // its colour holds direct and emitted light only and its albedo is
                                              // given: the voxels keep both and VoxelRelight adds the probes' light
SSVGI_CONSTANT(uint, kViewIsLitWithOutput, 4u);  // (the camera's, direct only) the host lit it with ssvgi's last
                                                 // output: injection adds albedo/π · that E, as the host did
SSVGI_CONSTANT(uint, kViewIsReflectiveShadowMap, 16u);  // (an extra view, direct only) its eye is its colour's one
                                                       // light: what it cannot see of a surface is in that shadow

// A view's projection may be perspective or orthographic (any view-projection that maps depth to reversed-Z): what the
// passes need of its geometry they find from the matrices (gi_frame.glsl: viewRayDirection), not from a position.
// Where a level of the Hi-Z pyramid lies in its buffer.
struct HiZLevel {
  uvec2 size;       // texels
  uint firstTexel;  // its first float in the pyramid buffer
  uint unused;
};
SSVGI_CHECK_SIZE(HiZLevel, 16);

struct GiFrame {
  mat4 viewProjection;             // current camera, reversed-Z
  mat4 inverseViewProjection;
  mat4 litViewProjection;          // the camera the lit frame was rendered with
  mat4 litInverseViewProjection;
  vec3 cameraPosition;             // current camera position (the host's camera: the gather's distances)
  uint frameIndex;
  uvec2 size;                      // current depth size, pixels
  uvec2 litSize;                   // lit frame size, pixels
  uint allocationPixelStride;      // BrickAllocate reads every Nth pixel in X and Y
  uint hizLevelCount;
  uint viewKind;                   // kViewIs… bits
  uint occlusionCulling;           // 1: the injection leaves out what lies behind the Hi-Z (Settings::occlusionCulling)
  vec4 frustumPlanes[6];           // current camera, world space, normals pointing inwards: dot(n, p) + w >= 0 inside
  HiZLevel hizLevels[kMaxHiZLevels];
};
SSVGI_CHECK_SIZE(GiFrame, 4 * 64 + 3 * 16 + 6 * 16 + 16 * 16);

// Whether an axis-aligned box reaches into a frustum given by inward planes (frustumPlanes): for each plane, the box's
// corner farthest along its normal must lie inside. Conservative: a box outside near a frustum corner may pass.
SSVGI_INLINE bool boxInFrustum(vec3 lo, vec3 hi, const vec4 planes[6]) {
  for (int i = 0; i < 6; ++i) {
    vec3 normal = vec3(planes[i]);
    vec3 farthestAlongNormal = mix(lo, hi, greaterThan(normal, vec3(0.0f)));
    if (dot(normal, farthestAlongNormal) + planes[i].w < 0.0f) return false;
  }
  return true;
}

SSVGI_SHARED_END

#endif
