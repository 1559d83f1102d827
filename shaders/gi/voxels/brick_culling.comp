#version 450
// BrickCulling: the live bricks to inject this frame (SPEC §4.2): a frustum test, then a Hi-Z occlusion test of the
// brick's screen rectangle at the level where it covers at most 2×2 texels against its nearest depth. Occluded or
// off-screen bricks keep their data untouched. Output: a compact list and its indirect dispatch (one group per brick).
#include "gi/gi_frame.glsl"
#include "gi/voxels/voxel_access.glsl"

layout(local_size_x = 64) in;

layout(binding = kBindPoolState) buffer PoolBlock { BrickPoolState pool; };
layout(binding = kBindCullingHiZ) readonly buffer HiZ { float hiz[]; };
layout(binding = kBindCullingVisibleBricks) buffer VisibleBricks {
  IndirectList visible;
  uint visibleBricks[];
};

bool occludedByHiZ(vec3 lo, vec3 hi) {
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
  // Hi-Z level 0 texels are 2×2 pixels; pick the level at which the rectangle spans at most two texels per axis.
  vec2 extent = max(maxPixel - minPixel, vec2(1.0));
  uint level = min(uint(max(ceil(log2(max(extent.x, extent.y) * 0.5)), 0.0)), frame.hizLevelCount - 1u);
  HiZLevel hizLevel = frame.hizLevels[level];
  float scale = 1.0 / float(2u << level);
  ivec2 first = clamp(ivec2(floor(minPixel * scale)), ivec2(0), ivec2(hizLevel.size) - 1);
  ivec2 last = clamp(ivec2(floor(maxPixel * scale)), ivec2(0), ivec2(hizLevel.size) - 1);
  float farthestDrawn = 1.0;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x)
      farthestDrawn = min(farthestDrawn, hiz[hizLevel.firstTexel + uint(y) * hizLevel.size.x + uint(x)]);
  return nearestDepth < farthestDrawn;  // the brick's nearest point is behind everything drawn over it
}

void main() {
  uint brick = gl_GlobalInvocationID.x;
  if (brick >= pool.bumpCount || bricks[brick].live == 0u) return;
  if ((frame.viewKind & kViewIsExtra) == 0u)  // counted once a frame
    atomicAdd(pool.voxelsValid, uint(bitCount(bricks[brick].occupancy.x) + bitCount(bricks[brick].occupancy.y)));
  // The brick's box grown by a hair (2 % of a voxel, twice heldSurfacePoint's offset): a surface lying on the brick's
  // face — a wall on the brick grid, seen head-on — is drawn at exactly the depth of the box's nearest corner, and
  // rounding alone would otherwise decide whether the brick that holds it counts as hidden behind it.
  vec3 margin = vec3(0.02 * volume.voxelSize);
  vec3 lo = vec3(bricks[brick].coordinate) * volume.brickSize - margin;
  vec3 hi = lo + vec3(volume.brickSize) + 2.0 * margin;
  if (!boxInFrustum(lo, hi, frame.frustumPlanes) || occludedByHiZ(lo, hi)) return;
  uint slot = atomicAdd(visible.count, 1u);
  atomicAdd(visible.groupCountX, 1u);
  visibleBricks[slot] = brick;
  atomicAdd(pool.visibleThisFrame, 1u);
}
