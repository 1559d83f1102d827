#version 450
// VolumeScroll: after the volume's origin moved, releases every brick that is now outside it (SPEC §4.1: a brick that
// scrolls out returns its index to the free list the same frame), and forgets that the cells which scrolled in were
// observed: their bits described the cells that left (SPEC §6.4). Dispatched only on frames where the origin moved.
#define SSVGI_OBSERVED_SPACE_WRITABLE
#include "gi/voxels/brick_pool.glsl"

layout(local_size_x = 64) in;

// Clears the observed bit of a brick cell and of the level-3 and level-4 cells holding it (BuildOctree makes levels 5
// and 6 again).
void forgetObserved(ivec3 worldBrick) {
  for (uint level = kFirstGridLevel; level < kFirstLocalGridLevel; ++level) {
    uvec2 address = gridBitAddress(level, worldBrick >> (level - kFirstGridLevel));
    atomicAnd(observedSpace[address.x], ~address.y);
  }
}

void main() {
  uint cell = gl_GlobalInvocationID.x;
  ivec3 dimensions = volumeDimensions();
  if (cell >= uint(dimensions.x * dimensions.y * dimensions.z)) return;
  ivec3 worldBrick = worldBrickOfCell(cell);
  ivec3 local = worldBrick - volume.previousOriginBrick;
  if (any(lessThan(local, ivec3(0))) || any(greaterThanEqual(local, dimensions))) forgetObserved(worldBrick);

  uint brick = brickLookup[cell];
  if (brick == kInvalidBrick) return;
  if (!brickInVolume(bricks[brick].coordinate, volume)) releaseBrick(brick, cell);
}
