#version 450
// VoxelDebugView: the voxel scene seen from a camera, one ray per pixel through the occupancy hierarchy. Mode 0: the
// radiance stored in the first voxel hit (black on back faces, as the probes would see it); mode 1: a colour per
// brick, shaded by the voxel normal so the bricks' shapes read; mode 2: as mode 0, watching observed space as the
// probes' rays do (SPEC §6.4): magenta where a ray crossed space no view has observed and met nothing (a probe's ray
// there finds neither a surface nor the sky), half magenta where it met a voxel beyond such space.
#include "gi/voxels/voxel_trace.glsl"
#include "shared/sampling.h"
#include "shared/debug_view.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindFirstPassSlot, rgba32f) writeonly uniform image2D target;
layout(push_constant) uniform Push { VoxelDebugViewPush push; };

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, push.camera.size))) return;
  vec3 origin = push.camera.position;
  vec3 direction = debugViewDirection(push.camera, pixel);
  float range = length(vec3(volume.dimensionsBricks)) * volume.brickSize;  // crosses the whole volume
  uint mode = push.camera.mode;
  VoxelHit hit = traceVoxelsHierarchical(origin, direction, range, mode == 2u);
  vec3 colour = hit.unobserved ? vec3(1.0, 0.0, 1.0) : vec3(0.0);
  if (hit.hit) {
    if (mode != 1u) {
      colour = hit.unobserved ? 0.5 * (hit.radiance + vec3(1.0, 0.0, 1.0)) : hit.radiance;
    } else {
      vec3 brickColour = vec3(0.25) + 0.75 * hashToUnitCube(uvec3(bricks[hit.brick].coordinate + ivec3(1 << 16)));
      colour = brickColour * (0.35 + 0.65 * abs(dot(hit.normal, direction)));
    }
  }
  imageStore(target, ivec2(pixel), vec4(colour, 1.0));
}
