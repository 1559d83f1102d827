#version 450
// PointRadiance: the radiance arriving at free points (a probe's position) from every direction, projected onto SH2
// (SPEC §2: L_lm = (4π/N) Σ L(ω_i) Y_lm(ω_i) over N uniform directions) — the ground truth of what a probe of the GI
// should hold there. Each direction's radiance is a whole path (reference/path_radiance.glsl): emission, the sky, and
// light reflected any number of times, as PathTrace finds it for a pixel; the delta lights themselves are never seen
// (a ray cannot hit a point), only their light reflected by surfaces. The emission a direction sees first counts
// fully: a free point has no surface from which to sample the emitters. From the path's first vertex on, the emitters
// are sampled directly (next-event estimation, weighted against the paths' own hits by multiple importance sampling)
// unless that is off.
//
// One workgroup per point; a round gives every lane one antithetic pair of uniform directions (ω, -ω). The group sums
// its lanes' L·Y and adds the total to the point's sums, in lane order, so the sums are a function of (scene, points,
// seed, rounds) only, whatever the batches were. The host scales by 4π/N.
#include "reference/path_radiance.glsl"
#include "shared/sampling.h"
#include "shared/sh.h"

layout(local_size_x = kPointRadianceLanes) in;

layout(push_constant) uniform Push { PointRadiancePush push; };

layout(binding = kBindPointPositions) readonly buffer Points { vec4 points[]; };
layout(binding = kBindPointRadianceSums) buffer Sums { PointRadianceSums sums[]; };

shared PointRadianceSums laneSums[kPointRadianceLanes];

// The radiance arriving at `origin` from `direction` (the path runs the other way, from the point outwards).
vec3 arrivingRadiance(vec3 origin, vec3 direction, uint random) {
  Path path = startPath(origin, direction, false, 0.0, random);
  while (extendPath(path, push.maxBounces, push.emitterCount, push.emittedPower)) {
  }
  return path.radiance;
}

void addSample(inout PointRadianceSums sum, vec3 origin, vec3 direction, uint random) {
  vec3 radiance = arrivingRadiance(origin, direction, random);
  sum.radiance = sh2Add(sum.radiance, sh2Project(radiance, sh2Basis(direction)));
  for (uint axis = 0u; axis < kPointAxisNormals; ++axis)
    sum.axisIrradiance[axis].rgb += radiance * max(dot(direction, pointAxisNormal(axis)), 0.0);
}

void addSums(inout PointRadianceSums total, PointRadianceSums part) {
  total.radiance = sh2Add(total.radiance, part.radiance);
  for (uint axis = 0u; axis < kPointAxisNormals; ++axis) total.axisIrradiance[axis] += part.axisIrradiance[axis];
}

void main() {
  uint point = gl_WorkGroupID.x;
  uint lane = gl_LocalInvocationID.x;
  vec3 origin = points[point].xyz;
  PointRadianceSums sum;
  sum.radiance = sh2Zero();
  for (uint axis = 0u; axis < kPointAxisNormals; ++axis) sum.axisIrradiance[axis] = vec4(0.0);
  for (uint roundIndex = push.firstRound; roundIndex < push.firstRound + push.roundCount; ++roundIndex) {
    // Each path of the pair has random numbers of its own: sample indices 2·pair and 2·pair + 1.
    uint pair = roundIndex * kPointRadianceLanes + lane;
    uint random = sampleRandomState(point, 2u * pair, push.seed);
    vec3 direction = uniformSphereDirection(nextRandom2(random));
    addSample(sum, origin, direction, random);
    addSample(sum, origin, -direction, sampleRandomState(point, 2u * pair + 1u, push.seed));
  }
  laneSums[lane] = sum;
  barrier();
  if (lane != 0u) return;
  PointRadianceSums total = sums[point];
  for (uint i = 0u; i < kPointRadianceLanes; ++i) addSums(total, laneSums[i]);
  sums[point] = total;
}
