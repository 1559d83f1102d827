#version 450
// BuildOctree's local levels (voxel_interface.h): levels 5 and 6 of the occupancy grid and of the observed space, whose
// cells are counted from the volume's minimum corner, made again every frame from the level below — the corner moves
// with the camera, and they are a few hundred words. Dispatched once per level, 5 first; each thread makes one word of
// both bit volumes: a cell is occupied when any of its 8 cells of the level below that lie inside the volume is, and
// observed when all of those are.
#define SSVGI_OCCUPANCY_GRID_WRITABLE
#define SSVGI_OBSERVED_SPACE_WRITABLE
#include "gi/voxels/voxel_access.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Push { uint level; };

void main() {
  VolumeLayout volumeLayout = volumeLayout();
  ivec3 cells = gridLevelCells(level, volumeLayout.dimensions);
  uint finerLevel = level - 1u;
  ivec3 finerCells = gridLevelCells(finerLevel, volumeLayout.dimensions);
  uint cellCount = uint(cells.x * cells.y * cells.z);
  uint word = gl_GlobalInvocationID.x;
  if (word * 32u >= cellCount) return;
  uint occupiedBits = 0u;
  uint observedBits = 0u;
  for (uint bit = 0u; bit < 32u; ++bit) {
    uint cellIndex = word * 32u + bit;
    if (cellIndex >= cellCount) break;
    ivec3 cell = ivec3(cellIndex % uint(cells.x), (cellIndex / uint(cells.x)) % uint(cells.y),
                       cellIndex / uint(cells.x * cells.y));
    bool occupied = false;
    bool observed = true;
    for (int child = 0; child < 8; ++child) {
      ivec3 finer = cell * 2 + ivec3(child & 1, (child >> 1) & 1, child >> 2);
      if (any(greaterThanEqual(finer, finerCells))) continue;  // past the volume's far face
      uvec2 address = gridBitAddressOfLocalCell(finerLevel, finer, volumeLayout);
      occupied = occupied || (occupancyGrid[address.x] & address.y) != 0u;
      observed = observed && (observedSpace[address.x] & address.y) != 0u;
    }
    if (occupied) occupiedBits |= 1u << bit;
    if (observed) observedBits |= 1u << bit;
  }
  uint offset = localGridWordOffset(level, volumeLayout.localGridWordOffsets);
  occupancyGrid[offset + word] = occupiedBits;
  observedSpace[offset + word] = observedBits;
}
