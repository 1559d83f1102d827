// The flat voxel DDA (SPEC §7's baseline, and the tests' oracle for the hierarchical DDA): every voxel along the ray in
// turn, on the walk of voxel_trace.glsl, whose comments say why the two agree exactly. Only TraceRays traces with it,
// so it stays out of the library's shaders.
#ifndef SSVGI_FLAT_VOXEL_TRACE_GLSL
#define SSVGI_FLAT_VOXEL_TRACE_GLSL

#include "gi/voxels/voxel_trace.glsl"

// Reads each brick's lookup and mask once.
VoxelHit traceVoxelsFlat(vec3 origin, vec3 direction, float maxDistance, bool watchesObservedSpace) {
  VoxelWalk walk;
  if (!beginVoxelWalk(voxelTraceFrame(), origin, direction, maxDistance, walk)) return voxelMiss(maxDistance, 0u);
  ivec3 size = walk.sizeVoxels;
  vec3 nextCrossing;
  for (int axis = 0; axis < 3; ++axis)
    nextCrossing[axis] = crossingDistance(walk, axis, exitPlane(walk.voxel[axis], kVoxelLevel, walk.step[axis]));
  CachedBrick cached = noCachedBrick();
  CachedGridWords observed = noCachedGridWords();
  uint reads = 0u;
  bool unobserved = false;
  float unobservedDistance = maxDistance;
  UnobservedVoxelPassed passed = kNoUnobservedVoxelPassed;
  for (;;) {
    bool newBrick = !isCached(cached, walk.voxel >> kBrickLevel);
    loadBrick(cached, walk, watchesObservedSpace, reads);
    if (watchesObservedSpace && !unobserved && newBrick && brickUnobserved(walk, cached, observed, reads)) {
      unobserved = true;
      unobservedDistance = walk.distance;
    }
    if (voxelBitSet(cached.mask, voxelInBrick(walk.voxel))) {
      VoxelHit hit = voxelHitAt(walk, cached, direction, reads);
      if (hit.hit) return withObservation(hit, unobserved, unobservedDistance);
      reads = hit.reads;
    } else if (countsAsUnobservedVoxel(walk, watchedUnobservedVoxels(cached, unobserved))) {
      VoxelHit met;
      if (meetsSurfaceBeside(walk, cached, direction, reads, met))
        return withObservation(met, unobserved, unobservedDistance);
      passUnobservedVoxel(passed, walk, cached, direction, unobserved, unobservedDistance);
    }
    int axis = firstCrossingAxis(nextCrossing);
    if (nextCrossing[axis] > maxDistance) break;
    walk.distance = nextCrossing[axis];
    walk.voxel[axis] += walk.step[axis];
    if (walk.voxel[axis] < 0 || walk.voxel[axis] >= size[axis]) break;
    if (leftUnobservedVoxelsBrick(passed, walk)) {
      if (passed.besideSurface) return unknownBesideSurface(passed, direction, maxDistance, reads);
      goOnPastUnobservedAir(passed, unobserved, unobservedDistance);
    }
    nextCrossing[axis] = crossingDistance(walk, axis, exitPlane(walk.voxel[axis], kVoxelLevel, walk.step[axis]));
  }
  return walkMissed(passed, direction, unobserved, unobservedDistance, maxDistance, reads);
}

#endif
