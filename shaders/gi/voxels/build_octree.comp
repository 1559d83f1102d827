#version 450
// BuildOctree (SPEC §4.4; the talk's "Voxel-Build Octree": 5 levels, 2×2×2 per level, 64 bits per brick): brings the
// toroidal grid levels of the occupancy hierarchy (2–4) up to date for the brick cells listed in changedCells; the
// local levels 5 and 6 are made after them (build_octree_local_levels.comp). Dispatched once per toroidal level,
// finest first; each thread takes one listed cell and sets or clears the bit of the cell's ancestor at that level:
//   level 2 (brick):            the cell holds a live brick whose occupancy mask is not empty;
//   level 3, 4 (2, 4 bricks):   any of the ancestor's 8 children at the level below, which the previous dispatch
//                               brought up to date.
// Threads of siblings compute the same ancestor from the same children, so they write the same value; atomicOr and
// atomicAnd keep the other bits of the shared word intact.
#define SSVGI_OCCUPANCY_GRID_WRITABLE
#include "gi/voxels/voxel_access.glsl"

// One workgroup per 64 entries: the group size of the list's appenders (brick_pool.glsl, markCellChanged).
layout(local_size_x = 64) in;

layout(binding = kBindChangedCells) readonly buffer ChangedCells {
  IndirectList changed;
  uint changedCells[];
};

layout(push_constant) uniform Push { uint level; };

void main() {
  uint entry = gl_GlobalInvocationID.x;
  if (entry >= changed.count) return;
  uint cell = changedCells[entry];
  ivec3 worldBrick = worldBrickOfCell(cell);
  ivec3 worldCell = worldBrick >> (level - kFirstGridLevel);

  bool occupied = false;
  if (level == kFirstGridLevel) {
    uint brick = brickLookup[cell];
    occupied = brick < volume.brickPoolCapacity && any(notEqual(bricks[brick].occupancy, uvec2(0u)));
  } else {
    for (int child = 0; child < 8; ++child)
      occupied = occupied || gridOccupied(level - 1u, worldCell * 2 + ivec3(child & 1, (child >> 1) & 1, child >> 2));
  }
  uvec2 address = gridBitAddress(level, worldCell);
  if (occupied) {
    atomicOr(occupancyGrid[address.x], address.y);
  } else {
    atomicAnd(occupancyGrid[address.x], ~address.y);
  }
}
