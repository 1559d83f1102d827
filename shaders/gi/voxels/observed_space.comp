#version 450
// ObservedSpace: marks the brick cells a view has observed (SPEC §6.4, "unknown is not sky"; voxel_interface.h). One
// thread per pixel in stride × stride (the offset inside the block moves every frame, so over stride² frames every
// pixel is visited) walks the brick cells along the pixel's ray from the near plane to the surface it shows, that
// surface's cell included, or — where nothing was drawn — out of the volume: the view saw through them. A view that
// only observes (kViewObservesOnly) writes no voxels: the cell of the surface it shows is left as it was, so that a
// probe ray crossing it without meeting a voxel is unknown, not sky.
#define SSVGI_OBSERVED_SPACE_WRITABLE
#include "gi/gi_frame.glsl"
#include "gi/voxels/voxel_access.glsl"
#include "gi/work_counting.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindFirstPassSlot) uniform sampler2D depthBuffer;

layout(push_constant) uniform Push { uint pixelStride; };

// The depth at which a pixel where nothing was drawn is followed: a perspective view's far plane (depth 0) lies at
// infinity, and this one lies beyond any volume (near plane / 1e-6); an orthographic view's is its far plane.
const float kNothingDrawnDepth = 1e-6;

// Marks a brick cell observed. The walk that observes the last brick cell of a level-3 cell marks that one too, and so
// on for level 4. (Two walks that observe a cell's last two bricks at once may both miss it; the trace then goes
// down to the bricks, which is only slower.)
void markObserved(ivec3 worldBrick) {
  uvec2 address = gridBitAddress(kFirstGridLevel, worldBrick);
  if ((observedSpace[address.x] & address.y) != 0u) return;
  if ((atomicOr(observedSpace[address.x], address.y) & address.y) != 0u) return;
  for (uint level = kFirstGridLevel + 1u; level < kOccupancyLevels; ++level) {
    ivec3 cell = worldBrick >> (level - kFirstGridLevel);
    for (int child = 0; child < 8; ++child)
      if (!cellObserved(level - 1u, cell * 2 + ivec3(child & 1, (child >> 1) & 1, child >> 2))) return;
    uvec2 parent = gridBitAddress(level, cell);
    atomicOr(observedSpace[parent.x], parent.y);
  }
}

void main() {
  uint offset = frame.frameIndex % (pixelStride * pixelStride);
  uvec2 pixel = gl_GlobalInvocationID.xy * pixelStride + uvec2(offset % pixelStride, offset / pixelStride);
  if (any(greaterThanEqual(pixel, frame.size))) return;
  float depth = texelFetch(depthBuffer, ivec2(pixel), 0).r;
  vec2 size = vec2(frame.size);
  // The segment in brick units, clipped to the volume.
  float bricksPerMetre = volume.bricksPerMetre;
  vec3 start = reconstructPosition(frame.inverseViewProjection, vec2(pixel), size, 1.0) * bricksPerMetre;
  vec3 end = reconstructPosition(frame.inverseViewProjection, vec2(pixel), size, max(depth, kNothingDrawnDepth)) *
             bricksPerMetre;
  vec3 segment = end - start;
  vec3 volumeMin = vec3(volume.originBrick);
  vec3 volumeMax = volumeMin + vec3(volumeDimensions());
  vec3 inverse = 1.0 / mix(segment, vec3(1.0), equal(segment, vec3(0.0)));
  vec3 entries = vec3(-1.0), exits = vec3(2.0);
  for (int axis = 0; axis < 3; ++axis) {
    if (segment[axis] == 0.0) {
      if (start[axis] < volumeMin[axis] || start[axis] >= volumeMax[axis]) return;
      continue;
    }
    bool increasing = segment[axis] > 0.0;
    entries[axis] = ((increasing ? volumeMin[axis] : volumeMax[axis]) - start[axis]) * inverse[axis];
    exits[axis] = ((increasing ? volumeMax[axis] : volumeMin[axis]) - start[axis]) * inverse[axis];
  }
  float first = max(0.0, max(max(entries.x, entries.y), entries.z));
  float last = min(1.0, min(min(exits.x, exits.y), exits.z));
  if (first > last) return;

  // A voxel DDA over brick cells (Amanatides & Woo), in the segment's parameter t ∈ [first, last].
  ivec3 lowest = volume.originBrick, highest = lowest + volumeDimensions() - 1;
  ivec3 cell = clamp(ivec3(floor(start + segment * first)), lowest, highest);
  ivec3 lastCell = clamp(ivec3(floor(start + segment * last)), lowest, highest);
  ivec3 stepDirection = ivec3(sign(segment));
  vec3 nextCrossing = (vec3(cell + max(stepDirection, ivec3(0))) - start) * inverse;
  nextCrossing = mix(nextCrossing, vec3(2.0), equal(stepDirection, ivec3(0)));
  vec3 crossingStep = abs(inverse);
  int maxSteps = volumeDimensions().x + volumeDimensions().y + volumeDimensions().z;
  bool surfaceCellKept = (frame.viewKind & kViewObservesOnly) != 0u && depth > 0.0 && last == 1.0;
  uint crossedCells = 0u;
  for (int stepCount = 0; stepCount < maxSteps; ++stepCount) {
    bool atLastCell = all(equal(cell, lastCell));
    if (atLastCell && surfaceCellKept) break;
    markObserved(cell);
    ++crossedCells;
    if (atLastCell) break;
    int axis = nextCrossing.x <= nextCrossing.y && nextCrossing.x <= nextCrossing.z ? 0
                                                                                   : (nextCrossing.y <= nextCrossing.z ? 1 : 2);
    if (nextCrossing[axis] > last) break;
    cell[axis] += stepDirection[axis];
    if (cell[axis] < lowest[axis] || cell[axis] > highest[axis]) break;
    nextCrossing[axis] += crossingStep[axis];
  }
  if (countsWork()) {
    atomicAdd(work.observedSpaceRays, 1u);
    atomicAdd(work.observedSpaceCells, crossedCells);
  }
}
