// A ray against an axis-aligned box (the slab test), shared by the reference's BVH traversal and the GI passes that
// follow a line of sight through a voxel.
#ifndef SSVGI_SHARED_RAY_BOX_H
#define SSVGI_SHARED_RAY_BOX_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

// 1/direction with zero components replaced by a huge finite value of the same sign, so that the slab test below
// never multiplies 0 by infinity (a ray starting on a slab plane would get NaN).
SSVGI_INLINE vec3 safeInverseDirection(vec3 direction) {
  vec3 magnitude = max(abs(direction), vec3(1e-20f));
  return vec3(direction.x < 0.0f ? -1.0f : 1.0f, direction.y < 0.0f ? -1.0f : 1.0f,
              direction.z < 0.0f ? -1.0f : 1.0f) / magnitude;
}

// The ray parameters (entry, exit) of an axis-aligned box; the ray misses it when entry > exit.
SSVGI_INLINE vec2 intersectBounds(vec3 origin, vec3 inverseDirection, vec3 boundsMin, vec3 boundsMax) {
  vec3 toMin = (boundsMin - origin) * inverseDirection;
  vec3 toMax = (boundsMax - origin) * inverseDirection;
  vec3 entries = min(toMin, toMax);
  vec3 exits = max(toMin, toMax);
  return vec2(max(max(entries.x, entries.y), entries.z), min(min(exits.x, exits.y), exits.z));
}

SSVGI_SHARED_END

#endif
