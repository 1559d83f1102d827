// Low-discrepancy directions on the sphere (SPEC §2): the Halton (2,3) sequence mapped to the unit sphere. The probes'
// fixed ray-direction set is its first kProbeRayDirectionCount points; the host uses the same sequence, longer, to
// project the sky onto SH. Shared so that the shaders and the host draw identical directions.
#ifndef SSVGI_SHARED_SAMPLING_H
#define SSVGI_SHARED_SAMPLING_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

// SPEC §2: 1024 directions, consumed 32 per probe update, so a probe has seen them all after 32 updates.
SSVGI_CONSTANT(uint, kProbeRayDirectionCount, 1024u);

// The radical inverse of `index` in `base`: its base-`base` digits mirrored about the radix point
// (e.g. base 2: 6 = 110b -> 0.011b = 0.375). Exact in float for the indices used here (< 2^24).
SSVGI_INLINE float radicalInverse(uint index, uint base) {
  float inverseBase = 1.0f / float(base);
  float digitWeight = inverseBase;
  float result = 0.0f;
  while (index > 0u) {
    result += float(index % base) * digitWeight;
    index /= base;
    digitWeight *= inverseBase;
  }
  return result;
}

// The index-th point of the 2-D Halton sequence in bases 2 and 3, in [0, 1)^2.
SSVGI_INLINE vec2 halton23(uint index) {
  return vec2(radicalInverse(index, 2u), radicalInverse(index, 3u));
}

// Maps a point of the unit square to a direction on the unit sphere, preserving uniformity: z = 1 - 2u is uniform in
// [-1, 1] (Archimedes' hat-box theorem: equal z intervals cut equal areas), φ = 2πv.
SSVGI_INLINE vec3 uniformSphereDirection(vec2 unitSquarePoint) {
  float z = 1.0f - 2.0f * unitSquarePoint.x;
  float radius = sqrt(max(0.0f, 1.0f - z * z));
  float phi = 2.0f * kPi * unitSquarePoint.y;
  return vec3(radius * cos(phi), radius * sin(phi), z);
}

// The index-th Halton direction. Indices 0 .. kProbeRayDirectionCount-1 are the probes' ray-direction set; every
// aligned block of 32 of them covers the sphere evenly on its own, because the base-2 coordinate of 32 consecutive
// indices starting at a multiple of 32 takes all 32 strata of z.
SSVGI_INLINE vec3 haltonSphereDirection(uint index) {
  return uniformSphereDirection(halton23(index));
}

// A uniformly distributed random rotation, as a unit quaternion (xyz, w), from a point of the unit cube (Shoemake,
// "Uniform random rotations", Graphics Gems III, 1992).
SSVGI_INLINE vec4 uniformRandomRotation(vec3 unitCubePoint) {
  float lower = sqrt(1.0f - unitCubePoint.x), upper = sqrt(unitCubePoint.x);
  float first = 2.0f * kPi * unitCubePoint.y, second = 2.0f * kPi * unitCubePoint.z;
  return vec4(lower * sin(first), lower * cos(first), upper * sin(second), upper * cos(second));
}

// `direction` turned by the unit quaternion `rotation`.
SSVGI_INLINE vec3 rotateByQuaternion(vec3 direction, vec4 rotation) {
  vec3 axis = vec3(rotation.x, rotation.y, rotation.z);
  return direction + 2.0f * cross(axis, cross(axis, direction) + rotation.w * direction);
}

// A well-mixed hash of three integers (PCG3D: Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020):
// per-voxel, per-frame random numbers that the host can reproduce exactly.
SSVGI_INLINE uvec3 pcg3d(uvec3 v) {
  v = v * 1664525u + uvec3(1013904223u);
  v.x += v.y * v.z;
  v.y += v.z * v.x;
  v.z += v.x * v.y;
  v = v ^ (v >> 16u);
  v.x += v.y * v.z;
  v.y += v.z * v.x;
  v.z += v.x * v.y;
  return v;
}

// Three uniform numbers in [0, 1) from a hash (24 bits each: exact in float).
SSVGI_INLINE vec3 hashToUnitCube(uvec3 v) { return vec3(pcg3d(v) >> 8u) * (1.0f / 16777216.0f); }

SSVGI_SHARED_END

#endif
