// TraceRays (trace_rays.comp): a buffer of rays traced through the voxel scene with the hierarchical or the flat voxel
// DDA, for the tests and for the benchmark that compares the two on the same rays (SPEC §7 baselines).
#ifndef SSVGI_SHARED_VOXEL_TRACE_INTERFACE_H
#define SSVGI_SHARED_VOXEL_TRACE_INTERFACE_H

#include "shared/voxel_interface.h"

SSVGI_SHARED_BEGIN

SSVGI_CONSTANT(uint, kBindTraceRaysRays, kBindFirstPassSlot);      // VoxelTraceRay[rayCount]
SSVGI_CONSTANT(uint, kBindTraceRaysHits, kBindFirstPassSlot + 1u);  // VoxelTraceHit[rayCount]

// TraceRays' specialization constant 0.
SSVGI_CONSTANT(uint, kTraceMethodHierarchical, 0u);  // over the occupancy hierarchy (SPEC §4.4)
SSVGI_CONSTANT(uint, kTraceMethodFlat, 1u);          // voxel by voxel: the baseline
SSVGI_CONSTANT(uint, kTraceMethodNearSurfaces, 2u);  // hierarchical from the brick level: traceVoxelsNearSurfaces

struct VoxelTraceRay {
  vec3 origin;                // world position, m
  float maxDistance;          // how far to trace, m
  vec3 direction;             // unit
  uint watchesObservedSpace;  // 1: as the probes' rays (SPEC §6.4)
};
SSVGI_CHECK_SIZE(VoxelTraceRay, 32);

struct VoxelTraceHit {
  vec3 radiance;                // the hit voxel's, black for a miss or a back face
  float distance;               // m to where the ray enters the hit voxel; the ray's maximum distance for a miss
  vec3 normal;                  // the hit voxel's, zero for a miss
  uint brick;                   // pool index of the hit voxel's brick (of the surface's voxel beside which a miss
                                // ended, kTraceEndedBesideSurface), kInvalidBrick for another miss
  uint voxelBit;                // the voxel's bit in its brick (voxelBit)
  uint reads;                   // buffer reads the trace made
  uint unobserved;              // kTraceObserved, kTraceCrossedUnobservedSpace or kTraceEndedBesideSurface (below)
  float unobservedDistance;     // m to where it first entered unobserved space; `distance` where it did not
};
SSVGI_CHECK_SIZE(VoxelTraceHit, 48);

// VoxelTraceHit::unobserved, for a trace that watches observed space (SPEC §6.4): the ray crossed no unobserved
// space; it crossed some before its hit or its end; it ended unknown at unobserved voxels beside seen surfaces
// (voxel_trace.glsl).
SSVGI_CONSTANT(uint, kTraceObserved, 0u);
SSVGI_CONSTANT(uint, kTraceCrossedUnobservedSpace, 1u);
SSVGI_CONSTANT(uint, kTraceEndedBesideSurface, 2u);

SSVGI_SHARED_END

#endif
