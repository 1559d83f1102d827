#version 450
// VoxelDebugView: the voxel scene seen from a camera, one ray per pixel through the occupancy hierarchy. Mode 0: the
// radiance stored in the first voxel hit (black on back faces, as the probes would see it); mode 1: a colour per
// brick, shaded by the voxel normal so the bricks' shapes read.
#include "gi/voxels/voxel_trace.glsl"
#include "shared/sampling.h"
#include "shared/debug_view.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindFirstPassSlot, rgba32f) writeonly uniform image2D target;
layout(push_constant) uniform Push { VoxelDebugViewPush push; };

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, push.camera.sizeAndMode.xy))) return;
  vec3 origin = push.camera.position.xyz;
  vec3 direction = debugViewDirection(push.camera, pixel);
  float range = length(vec3(volume.dimensionsBricks.xyz)) * volume.voxelSize.y;  // crosses the whole volume
  VoxelHit hit = traceVoxelsHierarchical(origin, direction, range, kCrossUnobservedSpace);
  vec3 colour = vec3(0.0);
  if (hit.hit) {
    if (push.camera.sizeAndMode.z == 0u) {
      colour = hit.radiance;
    } else {
      vec3 brickColour = vec3(0.25) + 0.75 * hashToUnitCube(uvec3(bricks[hit.brick].coordinate.xyz + ivec3(1 << 16)));
      colour = brickColour * (0.35 + 0.65 * abs(dot(hit.normal, direction)));
    }
  }
  imageStore(target, ivec2(pixel), vec4(colour, 1.0));
}
