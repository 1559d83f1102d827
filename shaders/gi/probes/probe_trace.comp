#version 450
// ProbeTrace (SPEC §4.5; the talk's "Probe Light", GatherRadianceFromVoxelScene): for each listed probe, one thread per
// ray of this update's slice of the fixed 1024-direction set, traced through the voxels from the probe. A hit gives
// the voxel's radiance (black from behind), a miss the sky's: the sky is thereby occluded by geometry ("sky visibility
// matters", the talk). The samples are projected onto SH2 (SPEC §2) — radiance, hit distance and normal-dot — summed
// across the workgroup and blended into the probe's history with α = 1/(m+1).
#include "gi/voxels/voxel_trace.glsl"
#include "shared/probe_interface.h"

layout(local_size_x = kProbeTraceGroupSize) in;

layout(binding = kBindProbeUpdate) uniform ProbeUpdateBlock { ProbeUpdate update; };
layout(binding = kBindProbes) buffer Probes { Probe probes[]; };
layout(binding = kBindProbeList) readonly buffer ProbeList {
  IndirectList list;
  uint listedProbes[];
};

// Per thread: its sample times the basis, for the five SH2 of a probe (radiance R, G, B, distance, normal-dot).
const uint kSh2PerProbe = 5u;
shared vec4 partialSums[kSh2PerProbe][kProbeTraceGroupSize];

vec3 skyRadiance(vec3 direction) {
  vec4 basis = sh2Basis(direction);
  Sh2Rgb sky = update.skyRadiance;
  // SH2 rings below zero opposite a bright sky; negative radiance is not light.
  return max(vec3(dot(sky.r, basis), dot(sky.g, basis), dot(sky.b, basis)), vec3(0.0));
}

void main() {
  uint probeIndex = listedProbes[gl_WorkGroupID.x];
  uint ray = gl_LocalInvocationID.x;
  ivec3 dimensions = update.dimensions.xyz;
  ivec3 probe = probeWorldCoordinate(probeIndex % uint(update.dimensions.w), update.originProbe.xyz, dimensions);
  uint state = probes[probeIndex].normalDotAndState.z;
  // History counts only if this slot has held this probe (a slot that scrolled to another probe is stale).
  bool hasHistory = probePlacement(state) == kProbeStateActive &&
                    probes[probeIndex].normalDotAndState.w == probeCoordinateTag(probe);
  uint historyCount = hasHistory ? probeHistoryCount(state) : 0u;
  uint firstDirection = hasHistory ? probeNextDirection(state) : 0u;

  for (uint sh = 0u; sh < kSh2PerProbe; ++sh) partialSums[sh][ray] = vec4(0.0);
  uint raysPerProbe = update.settings.x;
  if (ray < raysPerProbe) {
    vec3 direction = probeRayDirection(firstDirection, ray);
    VoxelHit hit = traceVoxelsHierarchical(vec3(probe) * update.distances.x, direction, update.distances.y);
    vec3 radiance = hit.hit ? hit.radiance : skyRadiance(direction);
    // A miss meets no surface, front or back: +1 (a front face head-on) keeps it from suggesting the probe is inside
    // geometry, which is what negative values will tell the virtual offset.
    float normalDot = hit.hit ? dot(-direction, hit.normal) : 1.0;
    float distance = min(hit.distance, update.distances.z);
    // L_lm = (4π/N) Σ L(ω_i) Y_lm(ω_i) (SPEC §2): each thread contributes its term.
    vec4 weightedBasis = sh2Basis(direction) * update.distances.w;
    partialSums[0][ray] = radiance.r * weightedBasis;
    partialSums[1][ray] = radiance.g * weightedBasis;
    partialSums[2][ray] = radiance.b * weightedBasis;
    partialSums[3][ray] = distance * weightedBasis;
    partialSums[4][ray] = normalDot * weightedBasis;
  }
  barrier();
  for (uint stride = kProbeTraceGroupSize / 2u; stride > 0u; stride /= 2u) {
    if (ray < stride)
      for (uint sh = 0u; sh < kSh2PerProbe; ++sh) partialSums[sh][ray] += partialSums[sh][ray + stride];
    barrier();
  }
  if (ray != 0u) return;

  // S = (1-α)·S_hist + α·S_new with α = 1/(m+1) (SPEC §4.5): the mean of the updates so far until m reaches its cap,
  // then an exponential window of about cap updates. A probe without history takes the new value whole.
  float alpha = 1.0 / float(historyCount + 1u);
  Probe stored = probes[probeIndex];
  uvec2 packedHistory[kSh2PerProbe] = uvec2[](stored.radianceRedGreen.xy, stored.radianceRedGreen.zw,
                                              stored.radianceBlueAndDistance.xy, stored.radianceBlueAndDistance.zw,
                                              stored.normalDotAndState.xy);
  uvec2 blended[kSh2PerProbe];
  for (uint sh = 0u; sh < kSh2PerProbe; ++sh) {
    vec4 history = historyCount == 0u ? vec4(0.0) : unpackSh2Half(packedHistory[sh]);  // a stale slot may hold anything
    blended[sh] = packSh2Half(mix(history, partialSums[sh][0], alpha));
  }
  uint nextState = packProbeState(min(historyCount + 1u, update.settings.y),
                                  (firstDirection + raysPerProbe) % kProbeRayDirectionCount, kProbeStateActive);
  probes[probeIndex] = Probe(uvec4(blended[0], blended[1]), uvec4(blended[2], blended[3]),
                             uvec4(blended[4], nextState, probeCoordinateTag(probe)));
}
