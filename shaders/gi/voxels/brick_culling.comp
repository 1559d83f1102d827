#version 450
// BrickCulling: the live bricks to inject this frame (SPEC §4.2): a frustum test, then a Hi-Z occlusion test of the
// brick's screen rectangle at the level where it covers at most 2×2 texels against its nearest depth. Occluded or
// off-screen bricks keep their data untouched. Output: a compact list and its indirect dispatch (SceneVoxelization's
// workgroups, kInjectionBricksPerGroup bricks each).
#include "gi/gi_frame.glsl"
#include "gi/voxels/hiz_occlusion.glsl"
#include "gi/voxels/voxel_access.glsl"

layout(local_size_x = 64) in;

layout(binding = kBindPoolState) buffer PoolBlock { BrickPoolState pool; };
layout(binding = kBindCullingVisibleBricks) buffer VisibleBricks {
  IndirectList visible;
  uint visibleBricks[];
};

void main() {
  uint brick = gl_GlobalInvocationID.x;
  if (brick >= pool.bumpCount || bricks[brick].live == 0u) return;
  if ((frame.viewKind & kViewIsExtra) == 0u)  // counted once a frame
    atomicAdd(pool.voxelsValid, uint(bitCount(bricks[brick].occupancy.x) + bitCount(bricks[brick].occupancy.y)));
  vec3 lo = vec3(bricks[brick].coordinate) * volume.brickSize;
  vec3 hi = lo + vec3(volume.brickSize);
  bool holdsOccupied = bricks[brick].occupancy != uvec2(0u);
  if (!boxInFrustum(lo, hi, frame.frustumPlanes)) return;
  if (hiddenFromInjection(lo, hi, holdsOccupied, volume.voxelSize)) return;
  uint slot = atomicAdd(visible.count, 1u);
  if (slot % kInjectionBricksPerGroup == 0u) atomicAdd(visible.groupCountX, 1u);
  visibleBricks[slot] = brick;
  atomicAdd(pool.visibleThisFrame, 1u);
}
