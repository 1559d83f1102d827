#version 450
// BrickAllocate: every brick that holds on-screen surface gets a pool slot (SPEC §4.2). Surface points come from the
// current depth at one pixel in stride × stride (the offset inside the block moves every frame, so over stride² frames
// every pixel is visited); the first thread to claim an empty cell allocates it, with a compare-exchange.
#include "gi/gi_frame.glsl"
#include "gi/voxels/brick_pool.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindAllocationDepth) uniform sampler2D depthBuffer;
layout(binding = kBindAllocationNormal) uniform sampler2D normalBuffer;

void main() {
  uint stride = frame.allocationPixelStride;
  uint offset = frame.frameIndex % (stride * stride);
  uvec2 pixel = gl_GlobalInvocationID.xy * stride + uvec2(offset % stride, offset / stride);
  if (any(greaterThanEqual(pixel, frame.size))) return;
  float depth = texelFetch(depthBuffer, ivec2(pixel), 0).r;
  if (depth <= 0.0) return;  // nothing drawn: infinitely far

  vec3 position = reconstructPosition(frame.inverseViewProjection, vec2(pixel), vec2(frame.size), depth);
  vec3 normal = normalize(texelFetch(normalBuffer, ivec2(pixel), 0).xyz);
  ivec3 worldBrick = worldBrickOf(heldSurfacePoint(position, normal));
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
