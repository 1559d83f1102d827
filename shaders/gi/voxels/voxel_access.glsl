// Declarations of the voxel scene's buffers at their shared slots, and the lookups every GI pass needs.
// A shader that writes the voxel scene defines SSVGI_VOXELS_WRITABLE before including this; the others see it
// read-only (which also tells the GPU layer's barrier tracker how each pass uses it).
#ifndef SSVGI_VOXEL_ACCESS_GLSL
#define SSVGI_VOXEL_ACCESS_GLSL

#include "shared/voxel_interface.h"

#ifdef SSVGI_VOXELS_WRITABLE
#define SSVGI_VOXEL_ACCESS
#else
#define SSVGI_VOXEL_ACCESS readonly
#endif
// A shader that writes the occupancy grid but not the voxels (BuildOctree) defines SSVGI_OCCUPANCY_GRID_WRITABLE instead.
#if defined(SSVGI_VOXELS_WRITABLE) || defined(SSVGI_OCCUPANCY_GRID_WRITABLE)
#define SSVGI_OCCUPANCY_GRID_ACCESS
#else
#define SSVGI_OCCUPANCY_GRID_ACCESS readonly
#endif

layout(binding = kBindVoxelVolume, std140) readonly buffer VolumeBlock { VoxelVolume volume; };
layout(binding = kBindBrickLookup) SSVGI_VOXEL_ACCESS buffer BrickLookup { uint brickLookup[]; };
layout(binding = kBindBricks) SSVGI_VOXEL_ACCESS buffer Bricks { Brick bricks[]; };
layout(binding = kBindVoxels) SSVGI_VOXEL_ACCESS buffer Voxels { Voxel voxels[]; };
layout(binding = kBindOccupancyGrid) SSVGI_OCCUPANCY_GRID_ACCESS buffer OccupancyGrid { uint occupancyGrid[]; };
// Observed space (voxel_interface.h): written by ObservedSpace, VolumeScroll and BuildOctree's local levels, which
// define SSVGI_OBSERVED_SPACE_WRITABLE (with the atomics' results read coherently).
#ifdef SSVGI_OBSERVED_SPACE_WRITABLE
layout(binding = kBindObservedSpace) coherent buffer ObservedSpace { uint observedSpace[]; };
#else
layout(binding = kBindObservedSpace) readonly buffer ObservedSpace { uint observedSpace[]; };
#endif

ivec3 volumeDimensions() { return volume.dimensionsBricks; }

// The world brick whose toroidal cell (brickCellIndex) this is: the one inside the volume.
ivec3 worldBrickOfCell(uint cell) {
  ivec3 dimensions = volumeDimensions();
  ivec3 slot = ivec3(int(cell) % dimensions.x, (int(cell) / dimensions.x) % dimensions.y,
                     int(cell) / (dimensions.x * dimensions.y));
  ivec3 origin = volume.originBrick;
  return origin + wrapCoordinate(slot - origin, dimensions);
}

// The world brick containing a world position.
ivec3 worldBrickOf(vec3 position, float bricksPerMetre) { return ivec3(floor(position * bricksPerMetre)); }
ivec3 worldBrickOf(vec3 position) { return worldBrickOf(position, volume.bricksPerMetre); }

// The corner of the scroll step under the camera, which the volume is placed around: its middle, unless the volume
// stands higher or lower to hold more of what the camera sees (VoxelVolume::verticalShiftBricks).
ivec3 volumeViewpointBrick() {
  return volume.originBrick + volume.dimensionsBricks / 2 - ivec3(0, volume.verticalShiftBricks, 0);
}
vec3 volumeViewpoint() { return vec3(volumeViewpointBrick()) * volume.brickSize; }

// The point of the voxel scene that holds a surface point seen at a pixel (BrickAllocate, SceneVoxelization): a hair
// off the surface along its normal, on the side away from the viewpoint (volumeViewpoint). A surface on a voxel
// boundary (a wall on the grid) then lands in one voxel rather than in either by rounding. A face towards the
// viewpoint — what the camera sees — lands on its solid side, behind it, so its voxels do not spread into the free
// side. A face turned away from it (a roof seen by the sun) lands a hair in front of it, on that same side: the two
// faces of a surface with no thickness on a boundary (a ceiling made of one plane) meet in one voxel, which keeps the
// face towards the viewpoint (SceneVoxelization), instead of the outer face lying in the voxel in front of the inner
// one, where the rays from inside met its back and found it black (docs/QUALITY.md, "A plane's two faces"). A surface
// whose plane passes within half a voxel of the viewpoint counts as facing it: the viewpoint lies on the grid (a
// ground at y = 0 holds it), and its side must not flip with the depth's rounding from one pixel to the next.
vec3 heldSurfacePoint(vec3 surface, vec3 normal, vec3 viewpoint, float voxelSize) {
  float behind = dot(normal, viewpoint - surface) < -0.5 * voxelSize ? -1.0 : 1.0;
  return surface - normal * (behind * 0.01 * voxelSize);
}

vec3 heldSurfacePoint(vec3 surface, vec3 normal) {
  return heldSurfacePoint(surface, normal, volumeViewpoint(), volume.voxelSize);
}

// The bit index of the n-th set bit of a 32-bit word (n < bitCount(word)), by halving: 5 steps.
uint nthSetBit(uint word, uint n) {
  uint bit = 0u;
  for (uint width = 16u; width > 0u; width >>= 1u) {
    uint lowerCount = uint(bitCount(word & ((1u << width) - 1u)));
    if (n >= lowerCount) {
      n -= lowerCount;
      word >>= width;
      bit += width;
    }
  }
  return bit;
}

// The bit (x + 4y + 16z) of a brick's n-th occupied voxel, or kVoxelsPerBrick when it has n or fewer. A pass with a
// thread per occupied voxel, rather than per voxel slot, keeps the threads a CPU or GPU runs in lock-step busy: a wall
// fills 16 of a brick's 64 slots, spread over every 8-thread group when it faces x.
uint nthOccupiedVoxel(uint brick, uint n) {
  uvec2 mask = bricks[brick].occupancy;
  uint lowCount = uint(bitCount(mask.x));
  if (n < lowCount) return nthSetBit(mask.x, n);
  n -= lowCount;
  return n < uint(bitCount(mask.y)) ? 32u + nthSetBit(mask.y, n) : kVoxelsPerBrick;
}

// Whether a brick's 64-bit voxel mask (occupancy, observed) has the voxel of bit `bit` (voxelBit).
bool maskHasVoxel(uvec2 mask, uint bit) { return (((bit < 32u ? mask.x : mask.y) >> (bit & 31u)) & 1u) != 0u; }

// The bits of a block of 2×2×2 voxels (level 1 of the hierarchy; `block` in 0–1 on each axis) in its word of a brick's
// mask, the low word for block.z = 0, the high one for 1: bits 0, 1, 4, 5, 16, 17, 20, 21 (x + 4y + 16z) above the
// block's first, which is 2·x + 8·y.
uint blockBitsInWord(uvec3 block) { return 0x00330033u << (2u * block.x + 8u * block.y); }

// Where the bit of a toroidal grid level (2 = brick, 3 = 2×2×2 bricks, 4 = 4×4×4 bricks; only those) for the cell of
// that level with toroidal index `cellIndex` lies: x, the word in occupancyGrid; y, the bit's mask in it.
uvec2 gridBitAddressOfCell(uint level, uint cellIndex, uvec3 gridWordOffsets) {
  uint offset = level == 2u ? gridWordOffsets.x : (level == 3u ? gridWordOffsets.y : gridWordOffsets.z);
  return uvec2(offset + (cellIndex >> 5u), 1u << (cellIndex & 31u));
}

// The same for a cell of a toroidal level (only those) in world units.
uvec2 gridBitAddress(uint level, ivec3 worldCell) {
  uint shift = level - kFirstGridLevel;
  return gridBitAddressOfCell(level, brickCellIndex(worldCell, volumeDimensions() >> shift), volume.gridWordOffsets);
}

// What a walk through the volume reads of its layout at every step, read from the volume's block once: on lavapipe a
// read of a buffer is made lane by lane, and one inside a loop again on every pass through it, one after a store again
// after each store (docs/PERFORMANCE.md, "Constants read once where a store or a loop would read them again").
struct VolumeLayout {
  ivec3 originBrick;       // VoxelVolume::originBrick
  ivec3 dimensions;        // bricks
  ivec3 originCell;        // the toroidal brick cell (brickCellIndex) of the volume's minimum corner
  uvec3 gridWordOffsets;   // VoxelVolume::gridWordOffsets
  uvec2 localGridWordOffsets;  // VoxelVolume::localGridWordOffsets
};

// A walk, which knows each cell's place in the volume, finds the cells' toroidal indices from originCell without a
// division (localCellIndex): integer division has no vector instruction on a CPU, so lavapipe makes it one lane at a
// time.
VolumeLayout volumeLayout() {
  return VolumeLayout(volume.originBrick, volumeDimensions(), wrapCoordinate(volume.originBrick, volumeDimensions()),
                      volume.gridWordOffsets, volume.localGridWordOffsets);
}

// The first word of a local grid level (kFirstLocalGridLevel and up) in its buffer.
uint localGridWordOffset(uint level, uvec2 localGridWordOffsets) {
  return level == kFirstLocalGridLevel ? localGridWordOffsets.x : localGridWordOffsets.y;
}

// Where the bit of the cell of a local grid level at `localCell` (counted from the volume's minimum corner) lies.
uvec2 localGridBitAddress(uint level, ivec3 localCell, ivec3 dimensionsBricks, uvec2 localGridWordOffsets) {
  uint cellIndex = linearCellIndex(localCell, gridLevelCells(level, dimensionsBricks));
  return uvec2(localGridWordOffset(level, localGridWordOffsets) + (cellIndex >> 5u), 1u << (cellIndex & 31u));
}

// The toroidal index of the cell of grid level kFirstGridLevel + `shift` at `localCell`, counted from the volume's
// minimum corner (0 .. dimensions >> shift − 1 on each axis). The volume's origin is a multiple of kScrollStepBricks
// bricks, and so are its dimensions: the corner's cell at a coarser level is its brick cell shifted.
uint localCellIndex(ivec3 localCell, uint shift, VolumeLayout volumeLayout) {
  ivec3 dimensions = volumeLayout.dimensions >> shift;
  ivec3 cell = localCell + (volumeLayout.originCell >> shift);
  cell -= dimensions * ivec3(greaterThanEqual(cell, dimensions));
  return linearCellIndex(cell, dimensions);
}

// Where the bit of the cell of any grid level at `localCell`, counted from the volume's minimum corner, lies, from the
// volume's layout.
uvec2 gridBitAddressOfLocalCell(uint level, ivec3 localCell, VolumeLayout volumeLayout) {
  if (level >= kFirstLocalGridLevel)
    return localGridBitAddress(level, localCell, volumeLayout.dimensions, volumeLayout.localGridWordOffsets);
  uint cellIndex = localCellIndex(localCell, level - kFirstGridLevel, volumeLayout);
  return gridBitAddressOfCell(level, cellIndex, volumeLayout.gridWordOffsets);
}

// gridBitAddress of a cell of a toroidal level in world units that lies in the volume, from the volume's layout.
uvec2 gridBitAddressInVolume(uint level, ivec3 worldCell, VolumeLayout volumeLayout) {
  return gridBitAddressOfLocalCell(level, worldCell - (volumeLayout.originBrick >> (level - kFirstGridLevel)),
                                   volumeLayout);
}

bool gridOccupied(uint level, ivec3 worldCell) {
  uvec2 address = gridBitAddress(level, worldCell);
  return (occupancyGrid[address.x] & address.y) != 0u;
}

#endif
