#version 450
// TraceRays: one thread per ray of a buffer, traced through the voxel scene with the hierarchical or the flat voxel
// DDA (voxel_trace.glsl, flat_voxel_trace.glsl), for the tests and for the benchmark that compares the two on the same
// rays (SPEC §7); or, for the tests, with the hierarchical DDA from the brick level (traceVoxelsNearSurfaces: the
// probes' rays and the visibility tests).
#include "bench/flat_voxel_trace.glsl"
#include "shared/voxel_trace_interface.h"

layout(local_size_x = 64) in;

layout(constant_id = 0) const uint kTraceMethod = kTraceMethodHierarchical;

layout(binding = kBindTraceRaysRays) readonly buffer Rays { VoxelTraceRay rays[]; };
layout(binding = kBindTraceRaysHits) writeonly buffer Hits { VoxelTraceHit hits[]; };

layout(push_constant) uniform Push { uint rayCount; };

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= rayCount) return;
  VoxelTraceRay ray = rays[index];
  vec3 origin = ray.origin;
  float maxDistance = ray.maxDistance;
  vec3 direction = ray.direction;
  bool watchesObservedSpace = ray.watchesObservedSpace != 0u;
  VoxelHit hit;
  if (kTraceMethod == kTraceMethodFlat)
    hit = traceVoxelsFlat(origin, direction, maxDistance, watchesObservedSpace);
  else if (kTraceMethod == kTraceMethodNearSurfaces)
    hit = traceVoxelsNearSurfaces(origin, direction, maxDistance, watchesObservedSpace);
  else
    hit = traceVoxelsHierarchical(origin, direction, maxDistance, watchesObservedSpace);
  hits[index] = VoxelTraceHit(hit.radiance, hit.distance, hit.normal, hit.brick, hit.voxelIndex, hit.reads,
                              hit.endedBesideSurface ? kTraceEndedBesideSurface
                                                     : (hit.unobserved ? kTraceCrossedUnobservedSpace : kTraceObserved),
                              hit.unobservedDistance);
}
