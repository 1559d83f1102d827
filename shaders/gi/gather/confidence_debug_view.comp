#version 450
// ConfidenceDebugView (SPEC §6.4 "a debug view shows it", §6.6): the confidence the gather gives each surface a camera
// sees, one ray per pixel through the voxels. At the first voxel a ray meets, the probes are gathered as FinalGather
// gathers them (the same level choice, weights and visibility test, probe_irradiance.glsl) and their known fraction
// drawn in grey: white, everything the probes' rays met was observed; black, nothing. Where a ray meets no voxel there
// is no surface to gather for: dark blue.
#include "gi/gather/probe_irradiance.glsl"
#include "shared/debug_view.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherDebugTarget, rgba32f) writeonly uniform image2D target;
layout(push_constant) uniform Push { ConfidenceDebugViewPush push; };

const vec3 kNoSurface = vec3(0.0, 0.0, 0.25);

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, push.camera.size))) return;
  vec3 origin = push.camera.position;
  vec3 direction = debugViewDirection(push.camera, pixel);
  float range = length(vec3(volume.dimensionsBricks)) * volume.brickSize;
  VoxelHit hit = traceVoxelsHierarchical(origin, direction, range, kIgnoreObservedSpace);
  vec3 colour = kNoSurface;
  if (hit.hit) {
    // The voxel's stored normal; a ray that meets it from behind sees the surface's back, facing the ray.
    vec3 normal = dot(hit.normal, direction) < 0.0 ? hit.normal : -direction;
    vec3 position = origin + hit.distance * direction;
    bool watchesObservedSpace = volume.skyOnlyThroughObservedSpace != 0u;
    float noise = hashToUnitCube(uvec3(pixel, 0u)).x;
    colour = vec3(probeLight(gatherFrame(), position, normal, noise, watchesObservedSpace).confidence);
  }
  imageStore(target, ivec2(pixel), vec4(colour, 1.0));
}
