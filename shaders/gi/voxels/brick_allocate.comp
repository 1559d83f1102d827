#version 450
// BrickAllocate: every brick that holds on-screen surface gets a pool slot (SPEC §4.2). Surface points come from the
// current depth at one pixel in stride × stride (the offset inside the block moves every frame, so over stride² frames
// every pixel is visited); the first thread to claim an empty cell allocates it, with a compare-exchange.
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

// Whether a brick lies within the volume across (x and z): only those, moving the volume up or down may hold.
bool withinVolumeAcross(ivec3 worldBrick) {
  ivec3 fromOrigin = worldBrick - volume.originBrick;
  return fromOrigin.x >= 0 && fromOrigin.z >= 0 && fromOrigin.x < volume.dimensionsBricks.x &&
         fromOrigin.z < volume.dimensionsBricks.z;
}

// The band of a brick's height: its scroll step's, counted from the viewpoint's step, which is the middle band.
uint heightBand(ivec3 worldBrick) {
  int step = int(floor(float(worldBrick.y) / float(kScrollStepBricks)));
  int viewpointStep = volumeViewpointBrick().y / kScrollStepBricks;  // the viewpoint lies on a step's corner
  return uint(clamp(step - viewpointStep + int(kSurfaceHeightBands / 2u), 0, int(kSurfaceHeightBands) - 1));
}

void allocate(ivec3 worldBrick) {
  if (!brickInVolume(worldBrick, volume)) return;
  uint cell = brickCellIndex(worldBrick, volumeDimensions());
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

void main() {
  uint thread = gl_LocalInvocationIndex;
  if (kCountsHeights) {
    for (uint band = thread; band < kSurfaceHeightBands; band += gl_WorkGroupSize.x * gl_WorkGroupSize.y)
      bandPixels[band] = 0u;
    barrier();
  }

  uint stride = frame.allocationPixelStride;
  uint offset = frame.frameIndex % (stride * stride);
  uvec2 pixel = gl_GlobalInvocationID.xy * stride + uvec2(offset % stride, offset / stride);
  bool surface = false;
  ivec3 worldBrick = ivec3(0);
  if (all(lessThan(pixel, frame.size))) {
    float depth = texelFetch(depthBuffer, ivec2(pixel), 0).r;
    surface = depth > 0.0;  // 0: nothing drawn, infinitely far
    if (surface) {
      vec3 position = reconstructPosition(frame.inverseViewProjection, vec2(pixel), vec2(frame.size), depth);
      vec3 normal = normalize(texelFetch(normalBuffer, ivec2(pixel), 0).xyz);
      worldBrick = worldBrickOf(heldSurfacePoint(position, normal));
    }
  }
  if (kCountsHeights) {
    if (surface && withinVolumeAcross(worldBrick)) atomicAdd(bandPixels[heightBand(worldBrick)], 1u);
    barrier();
    for (uint band = thread; band < kSurfaceHeightBands; band += gl_WorkGroupSize.x * gl_WorkGroupSize.y)
      if (bandPixels[band] > 0u) atomicAdd(pool.surfacePixelsByHeight[band], bandPixels[band]);
  }
  if (surface) allocate(worldBrick);
}
