#version 450
// VolumeScroll: after the volume's origin moved, releases every brick that is now outside it (SPEC §4.1: a brick that
// scrolls out returns its index to the free list the same frame). Dispatched only on frames where the origin moved.
#include "gi/voxels/brick_pool.glsl"

layout(local_size_x = 64) in;

void main() {
  uint cell = gl_GlobalInvocationID.x;
  ivec3 dimensions = volumeDimensions();
  if (cell >= uint(dimensions.x * dimensions.y * dimensions.z)) return;
  uint brick = brickLookup[cell];
  if (brick == kInvalidBrick) return;
  if (!brickInVolume(bricks[brick].coordinate.xyz, volume)) releaseBrick(brick, cell);
}
