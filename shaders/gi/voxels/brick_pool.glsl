// The brick pool's allocator (SPEC §4.1): pop from the free list first, else bump; release pushes onto the free list.
// Pops and pushes never run in the same dispatch (BrickAllocate only pops; VolumeScroll and SceneVoxelization only
// push), so a plain atomic counter is a correct stack for each.
#ifndef SSVGI_BRICK_POOL_GLSL
#define SSVGI_BRICK_POOL_GLSL
#define SSVGI_VOXELS_WRITABLE
#include "gi/voxels/voxel_access.glsl"

layout(binding = kBindPoolState) buffer PoolBlock {
  BrickPoolState pool;
  uint freeList[];
};
layout(binding = kBindChangedCells) buffer ChangedCells {
  IndirectList changed;
  uint changedCells[];
};

// Appends a brick cell to the list BuildOctree works through (one workgroup of 64 per 64 entries).
void markCellChanged(uint cell) {
  uint slot = atomicAdd(changed.count, 1u);
  if (slot % 64u == 0u) atomicAdd(changed.groupCountX, 1u);
  changedCells[slot] = cell;
}

// A free pool index, or kInvalidBrick when the pool is full (the caller counts the drop).
uint allocateBrickIndex() {
  uint available = atomicAdd(pool.freeCount, uint(-1));
  if (available != 0u && available <= volume.brickPoolCapacity) return freeList[available - 1u];
  atomicAdd(pool.freeCount, 1u);  // the list was empty: undo
  uint fresh = atomicAdd(pool.bumpCount, 1u);
  if (fresh < volume.brickPoolCapacity) return fresh;
  atomicAdd(pool.bumpCount, uint(-1));  // the pool is full: undo
  return kInvalidBrick;
}

// Returns a live brick to the pool and empties its cell, the same frame (SPEC §4.1).
void releaseBrick(uint brick, uint cell) {
  bricks[brick] = Brick(bricks[brick].coordinate, 0u, uvec2(0u), uvec2(0u), 0u, 0u, uvec2(0u));
  brickLookup[cell] = kInvalidBrick;
  freeList[atomicAdd(pool.freeCount, 1u)] = brick;
  atomicAdd(pool.releasedThisFrame, 1u);
  markCellChanged(cell);
}

#endif
