#version 450
// BrickAllocate: every brick that holds on-screen surface gets a pool slot (SPEC §4.2). Surface points come from the
// current depth at one pixel in stride × stride (the offset inside the block moves every frame, so over stride² frames
// every pixel is visited), 2×2 of them an invocation; the first to claim an empty cell allocates it, with a
// compare-exchange.
// On some of the camera's frames it also counts the surface pixels it read within the volume across by height band
// (BrickPoolState::surfacePixelsByHeight), above or below it as well as inside: how high VoxelScene::place stands the
// volume next.
#include "gi/gi_frame.glsl"
#include "gi/voxels/brick_pool.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(constant_id = 0) const bool kCountsHeights = false;

layout(binding = kBindAllocationDepth) uniform sampler2D depthBuffer;
layout(binding = kBindAllocationNormal) uniform sampler2D normalBuffer;

// The workgroup's count of each band, added to the pool's once: a global atomic a pixel cost more than the pass.
shared uint bandPixels[kSurfaceHeightBands];

// The frame's and the volume's constants, read once at the start: each sample pixel's allocation stores (its
// compare-exchange, the new brick), and a read of them after a store would be made again, lane by lane on lavapipe
// (docs/PERFORMANCE.md, "Constants read once where a store or a loop would read them again").
mat4 inverseViewProjection;
uvec2 frameSize;
ivec3 originBrick;
ivec3 dimensions;
vec3 viewpoint;
float voxelSize;
float bricksPerMetre;

// Whether a brick lies within the volume across (x and z): only those, moving the volume up or down may hold.
bool withinVolumeAcross(ivec3 worldBrick) {
  ivec3 fromOrigin = worldBrick - originBrick;
  return fromOrigin.x >= 0 && fromOrigin.z >= 0 && fromOrigin.x < dimensions.x && fromOrigin.z < dimensions.z;
}

// The band of a brick's height: its scroll step's, counted from the viewpoint's step, which is the middle band.
uint heightBand(ivec3 worldBrick) {
  int step = int(floor(float(worldBrick.y) / float(kScrollStepBricks)));
  int viewpointStep = volumeViewpointBrick().y / kScrollStepBricks;  // the viewpoint lies on a step's corner
  return uint(clamp(step - viewpointStep + int(kSurfaceHeightBands / 2u), 0, int(kSurfaceHeightBands) - 1));
}

void allocate(ivec3 worldBrick) {
  if (!brickInVolume(worldBrick, originBrick, dimensions)) return;
  uint cell = brickCellIndex(worldBrick, dimensions);
  if (brickLookup[cell] != kInvalidBrick) return;  // cheap test first: almost every surface brick already exists
  if (atomicCompSwap(brickLookup[cell], kInvalidBrick, kAllocatingBrick) != kInvalidBrick) return;

  uint brick = allocateBrickIndex();
  if (brick == kInvalidBrick) {
    atomicAdd(pool.droppedThisFrame, 1u);
    atomicAdd(pool.droppedTotal, 1u);
    brickLookup[cell] = kInvalidBrick;
    return;
  }
  bricks[brick] = Brick(worldBrick, 1u, uvec2(0u), uvec2(0u), 0u, 0u, uvec2(0u));
  for (uint voxel = 0u; voxel < kVoxelsPerBrick; ++voxel) voxels[brick * kVoxelsPerBrick + voxel] = Voxel(0u, 0u, 0u, 0u);
  atomicAdd(pool.allocatedThisFrame, 1u);
  brickLookup[cell] = brick;
}

// The brick holding the surface a sample pixel shows; false where it shows none (or lies past the image).
bool surfaceBrick(uvec2 pixel, out ivec3 worldBrick) {
  worldBrick = ivec3(0);
  if (any(greaterThanEqual(pixel, frameSize))) return false;
  float depth = texelFetch(depthBuffer, ivec2(pixel), 0).r;
  if (depth <= 0.0) return false;  // 0: nothing drawn, infinitely far
  vec3 position = reconstructPosition(inverseViewProjection, vec2(pixel), vec2(frameSize), depth);
  vec3 normal = normalize(texelFetch(normalBuffer, ivec2(pixel), 0).xyz);
  worldBrick = worldBrickOf(heldSurfacePoint(position, normal, viewpoint, voxelSize), bricksPerMetre);
  return true;
}

// An invocation takes 2×2 sample pixels, and allocates each brick they show once (neighbouring samples often show
// the same).
void main() {
  uint thread = gl_LocalInvocationIndex;
  if (kCountsHeights) {
    for (uint band = thread; band < kSurfaceHeightBands; band += gl_WorkGroupSize.x * gl_WorkGroupSize.y)
      bandPixels[band] = 0u;
    barrier();
  }
  inverseViewProjection = frame.inverseViewProjection;
  frameSize = frame.size;
  originBrick = volume.originBrick;
  dimensions = volumeDimensions();
  viewpoint = volumeViewpoint();
  voxelSize = volume.voxelSize;
  bricksPerMetre = volume.bricksPerMetre;
  uint stride = frame.allocationPixelStride;
  uint offset = frame.frameIndex % (stride * stride);
  uvec2 firstPixel = 2u * gl_GlobalInvocationID.xy * stride + uvec2(offset % stride, offset / stride);
  ivec3 bricks0, bricks1, bricks2, bricks3;
  bool surface0 = surfaceBrick(firstPixel, bricks0);
  bool surface1 = surfaceBrick(firstPixel + uvec2(stride, 0u), bricks1);
  bool surface2 = surfaceBrick(firstPixel + uvec2(0u, stride), bricks2);
  bool surface3 = surfaceBrick(firstPixel + uvec2(stride), bricks3);
  if (kCountsHeights) {
    if (surface0 && withinVolumeAcross(bricks0)) atomicAdd(bandPixels[heightBand(bricks0)], 1u);
    if (surface1 && withinVolumeAcross(bricks1)) atomicAdd(bandPixels[heightBand(bricks1)], 1u);
    if (surface2 && withinVolumeAcross(bricks2)) atomicAdd(bandPixels[heightBand(bricks2)], 1u);
    if (surface3 && withinVolumeAcross(bricks3)) atomicAdd(bandPixels[heightBand(bricks3)], 1u);
    barrier();
    for (uint band = thread; band < kSurfaceHeightBands; band += gl_WorkGroupSize.x * gl_WorkGroupSize.y)
      if (bandPixels[band] > 0u) atomicAdd(pool.surfacePixelsByHeight[band], bandPixels[band]);
  }
  if (surface0) allocate(bricks0);
  if (surface1 && bricks1 != bricks0) allocate(bricks1);
  if (surface2 && bricks2 != bricks0 && bricks2 != bricks1) allocate(bricks2);
  if (surface3 && bricks3 != bricks0 && bricks3 != bricks1 && bricks3 != bricks2) allocate(bricks3);
}
