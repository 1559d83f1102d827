// Whether a box lies wholly behind what the current view drew over it (SPEC §4.2): its screen rectangle, grown by
// `pixelMargin` pixels, read in the Hi-Z levels (HiZBuild) at the level where it spans at most four texels per axis
// (five where it straddles their edges), against the box's nearest depth. BrickCulling's test for a brick,
// SceneVoxelization's for a block of voxels.
#ifndef SSVGI_HIZ_OCCLUSION_GLSL
#define SSVGI_HIZ_OCCLUSION_GLSL

#include "gi/gi_frame.glsl"
#include "shared/voxel_interface.h"

layout(binding = kBindHiZ) readonly buffer HiZ { float hiz[]; };

bool occludedByHiZ(vec3 lo, vec3 hi, float pixelMargin) {
  vec2 minPixel = vec2(1e30), maxPixel = vec2(-1e30);
  float nearestDepth = 0.0;  // reversed-Z: larger is nearer
  for (int corner = 0; corner < 8; ++corner) {
    vec3 p = mix(lo, hi, vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
    vec4 clip = frame.viewProjection * vec4(p, 1.0);
    if (clip.w <= 1e-4) return false;  // reaches behind the camera: assume visible
    vec3 ndc = clip.xyz / clip.w;
    vec2 pixel = ssvgiNdcToPixel(ndc.xy, vec2(frame.size));
    minPixel = min(minPixel, pixel);
    maxPixel = max(maxPixel, pixel);
    nearestDepth = max(nearestDepth, ndc.z);
  }
  minPixel -= pixelMargin;
  maxPixel += pixelMargin;
  // Hi-Z level 0 texels are 2×2 pixels. A coarser level reads fewer texels, but each holds the farthest depth over
  // more than the box covers, and hides fewer boxes (docs/PERFORMANCE.md, "SceneVoxelization by blocks").
  vec2 extent = max(maxPixel - minPixel, vec2(1.0));
  uint level = min(uint(max(ceil(log2(max(extent.x, extent.y) * 0.125)), 0.0)), frame.hizLevelCount - 1u);
  HiZLevel hizLevel = frame.hizLevels[level];
  float scale = 1.0 / float(2u << level);
  ivec2 first = clamp(ivec2(floor(minPixel * scale)), ivec2(0), ivec2(hizLevel.size) - 1);
  ivec2 last = clamp(ivec2(floor(maxPixel * scale)), ivec2(0), ivec2(hizLevel.size) - 1);
  float farthestDrawn = 1.0;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x)
      farthestDrawn = min(farthestDrawn, hiz[hizLevel.firstTexel + uint(y) * hizLevel.size.x + uint(x)]);
  return nearestDepth < farthestDrawn;  // the box's nearest point is behind everything drawn over it
}

// Whether SceneVoxelization can change nothing in a box of voxels (a brick, a block of 2×2×2), `holdsOccupied` where
// any of them is occupied: the box lies wholly behind what the view drew over it. Then every texel an injected voxel
// reads (its point's, the 2×2 nearest it, one of its footprint) shows a surface in front of the voxel's point and
// outside the voxel, so nothing is stored, seen through or observed. Grown by a hair where the box holds no occupied
// voxel (twice heldSurfacePoint's offset: a surface on the box's face, seen head-on, lies at exactly the depth of its
// nearest corner), by a voxel more where it holds one, which takes the colour of a surface up to a voxel away
// (showsSurfaceAt); and by a pixel around its rectangle, for the 2×2 texels nearest a point. A reflective shadow map
// writes its light's shadow into the occupied voxels behind what it shows (SceneVoxelization's litShareOfPlane): for
// it, only a box holding no occupied voxel can be left out — else a floor the sun lit, then a roof high above it hid
// whole, kept its sunlight. Never, with the culling off (GiFrame::occlusionCulling).
bool hiddenFromInjection(vec3 lo, vec3 hi, bool holdsOccupied, float voxelSize) {
  if (frame.occlusionCulling == 0u) return false;
  if (holdsOccupied && (frame.viewKind & kViewIsReflectiveShadowMap) != 0u) return false;
  vec3 margin = vec3(voxelSize * (holdsOccupied ? 1.02 : 0.02));
  return occludedByHiZ(lo - margin, hi + margin, 1.0);
}

#endif
