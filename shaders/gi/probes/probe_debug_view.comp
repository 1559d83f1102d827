#version 450
// ProbeDebugView (SPEC §6.6, "probes as spheres showing their SH, probe states"): the finest probe level as small
// spheres in front of the voxel scene, one camera ray per pixel. A sphere at the probe's position (with its virtual
// offset) shows what the probe holds: diffuse radiance E(n)/π for its surface normal n, so a probe reads like a white
// ball lit by its SH; magenta: invalid (inside geometry, left out of gathers); yellow: just moved by the virtual
// offset, not traced since. Probes never traced are not drawn.
#include "gi/voxels/voxel_trace.glsl"
#include "shared/debug_view.h"
#include "shared/probe_interface.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindFirstPassSlot, rgba32f) writeonly uniform image2D target;
layout(binding = kBindProbes) readonly buffer Probes { Probe probes[]; };
layout(push_constant) uniform Push { ProbeDebugViewPush push; };

const float kSphereRadiusSpacings = 0.12;
const uint kMaxCellSteps = 512u;

// The nearest distance along the ray at which it enters the sphere, or -1.
float intersectSphere(vec3 origin, vec3 direction, vec3 centre, float radius) {
  vec3 toOrigin = origin - centre;
  float halfB = dot(toOrigin, direction);
  float discriminant = halfB * halfB - (dot(toOrigin, toOrigin) - radius * radius);
  if (discriminant < 0.0) return -1.0;
  float t = -halfB - sqrt(discriminant);
  return t > 0.0 ? t : -1.0;
}

vec3 probeColour(Probe probe, vec3 normal) {
  uint state = probe.state;
  if (probePlacement(state) == kProbeStateInvalid) return vec3(1.0, 0.0, 1.0);
  if (probeHistoryCount(state) == 0u) return vec3(1.0, 0.85, 0.0);
  Sh2Rgb radiance = probeRadianceSh(probe);
  // As the gather reads a probe without sky: this view has not the host's sky, which readProbeIrradiance reads apart.
  return sh2IrradianceWithoutRinging(radiance, normal) / kPi;
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, push.camera.size))) return;
  vec3 origin = push.camera.position;
  vec3 direction = debugViewDirection(push.camera, pixel);
  float range = length(vec3(volume.dimensionsBricks)) * volume.brickSize;
  VoxelHit scene = traceVoxelsHierarchical(origin, direction, range, kIgnoreObservedSpace);
  vec3 colour = scene.radiance;
  float nearest = scene.distance;

  // Walk the cells of the probe grid centred on the probes (a 3D DDA, Amanatides and Woo) and test the probe of each.
  // A virtual offset may move a sphere partly into a neighbouring cell, where that cell's walk does not see it: a
  // clipped sphere is good enough for a debug picture.
  float spacing = push.probeSpacing;
  ivec3 first = push.probeOrigin, dimensions = push.probeDimensions;
  vec3 grid = origin / spacing + 0.5;
  ivec3 cell = ivec3(floor(grid));
  ivec3 stepDirection = ivec3(sign(direction));
  vec3 inverse = 1.0 / max(abs(direction), vec3(1e-8));
  vec3 toBoundary = mix(grid - vec3(cell), vec3(cell) + 1.0 - grid, greaterThan(direction, vec3(0.0)));
  vec3 nextCrossing = toBoundary * inverse * spacing;  // ray distance to the next cell boundary on each axis
  vec3 crossingStep = inverse * spacing;
  float entered = 0.0;
  for (uint step = 0u; step < kMaxCellSteps && entered < nearest; ++step) {
    if (any(lessThan(cell, first)) || any(greaterThanEqual(cell, first + dimensions))) break;
    Probe probe = probes[probeSlotIndex(cell, dimensions)];  // level 0 comes first in the buffer
    uint state = probe.state;
    if (probeSlotHolds(probe, cell)) {
      vec3 centre = probeWorldPosition(cell, spacing, state);
      float t = intersectSphere(origin, direction, centre, kSphereRadiusSpacings * spacing);
      if (t > 0.0 && t < nearest) {
        nearest = t;
        colour = probeColour(probe, normalize(origin + t * direction - centre));
      }
    }
    float exitDistance = min(nextCrossing.x, min(nextCrossing.y, nextCrossing.z));
    bvec3 axis = equal(nextCrossing, vec3(exitDistance));
    entered = exitDistance;
    cell += ivec3(axis) * stepDirection;
    nextCrossing += vec3(axis) * crossingStep;
  }
  imageStore(target, ivec2(pixel), vec4(colour, 1.0));
}
