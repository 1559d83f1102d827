#version 450
// VoxelRelight (SPEC §6.1): recomputes the radiance of the voxels whose view gave them direct light and albedo
// (kVoxelRelit) as direct + albedo/π · E of the probes at their surface, except those the camera's lit frame keeps
// lighting. The bounces after the first then follow the probes where the camera does not look — behind it, on a wall
// an extra view saw once long ago — instead of staying as a view last left them (a light switched off while the
// camera looks away left its bounce light there for good, feeding itself through the probes).
// A frame relights one in Settings::voxelRelightPeriod of the bricks, those whose phase (from their world coordinate)
// is the frame's, up to the bump allocator's count (no brick beyond it was ever used): a few hundred workgroups rather
// than one per brick of the pool, most of which is empty, each going over kRelightBricksAtOnce bricks at a time with
// kRelightVoxelsAtOnce threads per brick walking its occupied voxels. The phase is the brick's place in the world, not
// in the pool: the pool's order is the order in which BrickAllocate's threads happened to run, and a slice of it made
// which voxels are relit on which frame — and with it the GI — differ from run to run (docs/QUALITY.md, "The same
// frames, the same light").
#define SSVGI_VOXELS_WRITABLE
#include "gi/gather/probe_irradiance.glsl"
#include "gi/work_counting.glsl"
#include "shared/sampling.h"

layout(local_size_x = kRelightBricksAtOnce * kRelightVoxelsAtOnce) in;

layout(push_constant) uniform Phase {
  uint phase;   // the frame's: frameIndex % period
  uint period;  // Settings::voxelRelightPeriod
};
layout(binding = kBindPoolState) readonly buffer PoolBlock { BrickPoolState pool; };

// The frames (modulo `period`) on which the brick at world brick coordinate `coordinate` is relit: a hash, so that
// each phase takes its share of every region of the scene.
const uint kRelightPhaseSeed = 0x27d4eb2du;
uint relightPhase(ivec3 coordinate, uint period) {
  return uint(hashToUnitCube(uvec3(coordinate) ^ uvec3(kRelightPhaseSeed)).x * float(period)) % period;
}

// Whether the voxel's light was gathered from the probes (the work counted: shared/work_counters.h).
bool relightVoxel(GatherFrame constants, uint brick, uint occupiedVoxel) {
  uint voxelIndex = nthOccupiedVoxel(brick, occupiedVoxel);
  uvec3 voxelInBrick = uvec3(voxelIndex & 3u, (voxelIndex >> 2u) & 3u, voxelIndex >> 4u);
  uint index = brick * kVoxelsPerBrick + voxelIndex;
  Voxel voxel = voxels[index];
  if ((voxel.albedo & kVoxelRelit) == 0u) return false;  // its view gave all of its light: it stays as given
  // The camera's lit frame keeps the voxels it lights current with the gather's light (SceneVoxelization): those it
  // lit last and no extra view has seen since are left to it; a voxel off screen is relit once a view sees it.
  if (voxelExtraViewsSinceLitFrame(voxel) == 0u) return false;

  ivec3 worldVoxel = bricks[brick].coordinate * int(kBrickSizeVoxels) + ivec3(voxelInBrick);
  float voxelSize = constants.trace.voxelSize;
  vec3 normal = voxelNormal(voxel);
  uint planeCode = voxelPlaneCode(voxel);
  float planeOffset = planeCode != 0u ? unpackVoxelPlane(planeCode) : 0.0;
  vec3 surface = (vec3(worldVoxel) + 0.5) * voxelSize + normal * (planeOffset * voxelSize);
  // The level-boundary noise is the voxel's own, the same every frame: the voxel's light must not flicker between
  // two levels' answers (the gather's noise is averaged by its temporal filter, a voxel's is not).
  float noise = hashToUnitCube(uvec3(worldVoxel)).x;
  // With the gather's visibility trace (this pass writes only radiance, which no trace reads): without it the lit
  // room's probes lit the dark side of `two-rooms`' wall (docs/QUALITY.md, "Voxels follow the light").
  vec4 irradiance = probeIrradiance(constants, surface, normal, noise);
  if (irradiance.a == 0.0) return true;  // no probe knows its surroundings yet: it keeps the light it has
  vec3 direct = unpackR11G11B10F(voxel.directRadiance);
  voxels[index].radiance = packR11G11B10F(direct + unpackVoxelAlbedo(voxel.albedo) * (1.0 / kPi) * irradiance.rgb);
  return true;
}

// Whether the brick at pool index `brick` is live and relit this frame.
bool relitThisFrame(uint brick) {
  return bricks[brick].live != 0u && relightPhase(bricks[brick].coordinate, period) == phase;
}

void main() {
  uint end = pool.bumpCount;
  // Read once, not in the loops (gi/voxels/voxel_access.glsl's VolumeLayout says why).
  GatherFrame constants = gatherFrame();
  uint relitVoxels = 0u;
  uint brickOfWorkgroup = gl_LocalInvocationID.x / kRelightVoxelsAtOnce;
  uint firstVoxel = gl_LocalInvocationID.x % kRelightVoxelsAtOnce;
  uint stride = gl_NumWorkGroups.x * kRelightBricksAtOnce;
  uint brick = gl_WorkGroupID.x * kRelightBricksAtOnce + brickOfWorkgroup;
  for (;;) {
    // The bricks of other phases are passed over in a loop of their own: lavapipe runs the whole body of a loop, every
    // branch, on each pass of any lane, and the relight below is the heavy part.
    while (brick < end && !relitThisFrame(brick)) brick += stride;
    if (brick >= end) break;
    uvec2 occupancy = bricks[brick].occupancy;
    uint occupied = uint(bitCount(occupancy.x) + bitCount(occupancy.y));
    for (uint voxel = firstVoxel; voxel < occupied; voxel += kRelightVoxelsAtOnce)
      if (relightVoxel(constants, brick, voxel)) ++relitVoxels;
    brick += stride;
  }
  if (countsWork()) {
    atomicAdd(work.relightVoxels, relitVoxels);
    atomicAdd(work.relightRays, tracedWork.rays);
    atomicAdd(work.relightReads, tracedWork.reads);
  }
}
