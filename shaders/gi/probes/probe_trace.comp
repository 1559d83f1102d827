#version 450
// ProbeTrace (SPEC §4.5; the talk's "Probe Light", GatherRadianceFromVoxelScene): for each listed probe, one thread per
// ray of this update's slice of the fixed 1024-direction set, traced through the voxels from the probe. A hit gives
// the voxel's radiance (black from behind), a miss the sky's: the sky is thereby occluded by geometry ("sky visibility
// matters", the talk). The samples are projected onto SH2 (SPEC §2) — radiance, hit distance and normal-dot — summed
// across the workgroup and blended into the probe's history with α = 1/(m+1). Rays leave from the probe's position plus
// its virtual offset (ProbeRelocate). A new probe starts from the coarser level (SPEC §4.5; the talk's fix for the
// flicker of new probes while moving: "initialise from the higher-level probe volume").
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

// What a new probe of this level starts from: the radiance of the coarser level at its position, trilinear over the
// coarser probes around it that are usable, renormalised. Trilinear rather than nearest: it is what a gather reads
// there, so a probe that appears continues the light that was shown before it, and the levels nest, so half the
// weights are zero (a probe on a coarser probe takes exactly that probe's value). False where no coarser probe around
// it is usable, and always on the coarsest level: the probe then starts from its first trace alone.
bool coarserLevelRadiance(ivec3 probe, out Sh2Rgb radiance) {
  radiance = Sh2Rgb(vec4(0.0), vec4(0.0), vec4(0.0));
  uint coarserLevel = uint(update.originProbe.w) + 1u;
  if (coarserLevel >= kProbeLevels) return false;
  ivec3 base = probe >> 1;  // the coarser cell holding the probe (arithmetic shift: floor for negative coordinates)
  vec3 fraction = vec3(probe & 1) * 0.5;
  float weightSum = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    ivec3 side = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    vec3 axisWeights = mix(vec3(1.0) - fraction, fraction, vec3(side));
    float weight = axisWeights.x * axisWeights.y * axisWeights.z;
    ivec3 coarser = base + side;
    Probe candidate = probes[coarserLevel * uint(update.dimensions.w) + probeSlotIndex(coarser, update.dimensions.xyz)];
    if (weight == 0.0 || !probeIsUsable(candidate, coarser)) continue;
    radiance.r += weight * unpackSh2Half(candidate.radianceRedGreen.xy);
    radiance.g += weight * unpackSh2Half(candidate.radianceRedGreen.zw);
    radiance.b += weight * unpackSh2Half(candidate.radianceBlueAndDistance.xy);
    weightSum += weight;
  }
  if (weightSum == 0.0) return false;
  radiance.r /= weightSum;
  radiance.g /= weightSum;
  radiance.b /= weightSum;
  return true;
}

void main() {
  uint probeIndex = listedProbes[gl_WorkGroupID.x];
  uint ray = gl_LocalInvocationID.x;
  ivec3 dimensions = update.dimensions.xyz;
  ivec3 probe = probeWorldCoordinate(probeIndex % uint(update.dimensions.w), update.originProbe.xyz, dimensions);
  uint state = probes[probeIndex].normalDotAndState.z;
  // History, offset and placement count only if this slot has held this probe (a slot that scrolled to another probe
  // is stale). An invalid probe keeps its history count but has no offset: it is traced from its grid position.
  bool ownsSlot = probePlacement(state) != kProbeStateNeverTraced &&
                  probes[probeIndex].normalDotAndState.w == probeCoordinateTag(probe);
  uint historyCount = ownsSlot ? probeHistoryCount(state) : 0u;
  uint firstDirection = ownsSlot ? probeNextDirection(state) : 0u;
  uint offsetCode = ownsSlot ? probeOffsetCode(state) : 0u;
  uint placement = ownsSlot ? probePlacement(state) : kProbeStateActive;
  vec3 origin = probeWorldPosition(probe, update.distances.x, ownsSlot ? state : 0u);

  for (uint sh = 0u; sh < kSh2PerProbe; ++sh) partialSums[sh][ray] = vec4(0.0);
  uint raysPerProbe = update.settings.x;
  if (ray < raysPerProbe) {
    vec3 direction = probeRayDirection(firstDirection, ray);
    VoxelHit hit = traceVoxelsHierarchical(origin, direction, update.distances.y);
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
  // then an exponential window of about cap updates. A new probe (m = 0) takes its radiance half from the coarser
  // level, half from this first trace — the coarser value counts as one earlier update, so its weight then decays as
  // 1/(m+1) like any update's; without a coarser value, and always for distance and normal-dot (which belong to this
  // probe's own position and spacing), it takes the first trace whole.
  Probe stored = probes[probeIndex];
  uvec2 packedHistory[kSh2PerProbe] = uvec2[](stored.radianceRedGreen.xy, stored.radianceRedGreen.zw,
                                              stored.radianceBlueAndDistance.xy, stored.radianceBlueAndDistance.zw,
                                              stored.normalDotAndState.xy);
  Sh2Rgb startRadiance;
  bool startsFromCoarser = historyCount == 0u && coarserLevelRadiance(probe, startRadiance);
  vec4 start[3] = vec4[](startRadiance.r, startRadiance.g, startRadiance.b);
  uvec2 blended[kSh2PerProbe];
  for (uint sh = 0u; sh < kSh2PerProbe; ++sh) {
    vec4 history = historyCount > 0u ? unpackSh2Half(packedHistory[sh]) : vec4(0.0);  // a stale slot may hold anything
    float alpha = 1.0 / float(historyCount + 1u);
    if (sh < 3u && startsFromCoarser) {
      history = start[sh];
      alpha = 0.5;
    }
    blended[sh] = packSh2Half(mix(history, partialSums[sh][0], alpha));
  }
  uint nextState = packProbeState(min(historyCount + 1u, update.settings.y),
                                  (firstDirection + raysPerProbe) % kProbeRayDirectionCount, placement, offsetCode);
  probes[probeIndex] = Probe(uvec4(blended[0], blended[1]), uvec4(blended[2], blended[3]),
                             uvec4(blended[4], nextState, probeCoordinateTag(probe)));
}
