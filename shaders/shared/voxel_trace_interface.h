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

struct VoxelTraceRay {
  vec4 originAndMaxDistance;  // xyz: world position (m); w: how far to trace (m)
  vec4 direction;             // xyz: unit direction; w: 1 to watch observed space (as the probes' rays, SPEC §6.4)
};
SSVGI_CHECK_SIZE(VoxelTraceRay, 32);

struct VoxelTraceHit {
  vec4 radianceAndDistance;  // rgb: the hit voxel's radiance, black for a miss or a back face; a: distance (m) to
                             // where the ray enters the hit voxel, the ray's maximum distance for a miss
  vec4 normal;               // xyz: the hit voxel's normal, zero for a miss; w: unused
  uvec4 voxel;               // x: pool index of the hit voxel's brick, kInvalidBrick for a miss; y: the voxel's bit
                             // in its brick (voxelBit); z: buffer reads the trace made; w: 1 when the ray crossed
                             // unobserved space before its hit or its end, else 0
};
SSVGI_CHECK_SIZE(VoxelTraceHit, 48);

SSVGI_SHARED_END

#endif
