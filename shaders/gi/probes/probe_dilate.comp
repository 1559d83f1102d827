#version 450
// ProbeDilate (SPEC §4.5; the talk's "Probe Dilation": "blend the neighbouring probes"): each listed probe that
// ProbeRelocate left invalid takes the mean radiance of its usable neighbours on its level (the 26 around it). Gathers
// leave invalid probes out anyway; the fill is for what reads a probe without asking — a finer level starting a new
// probe, hardware-filtered copies, debug views — so that they see the light around it rather than the black inside a
// wall. Only radiance is filled: distance and normal-dot stay the probe's own, which ProbeRelocate re-checks.
#include "shared/probe_interface.h"

layout(local_size_x = kProbeTraceGroupSize) in;  // one workgroup per listed probe; thread i < 26: neighbour i

layout(binding = kBindProbeUpdate, std140) readonly buffer ProbeUpdateBlock { ProbeUpdate update; };
layout(binding = kBindProbes) buffer Probes { Probe probes[]; };
layout(binding = kBindProbeList) readonly buffer ProbeList {
  IndirectList list;
  uint listedProbes[];
};

shared Sh2Rgb neighbourRadiance[kProbeTraceGroupSize];
shared float neighbourUsable[kProbeTraceGroupSize];
shared vec4 neighbourSkyVisibility[kProbeTraceGroupSize];

void main() {
  uint probeIndex = listedProbes[gl_WorkGroupID.x];
  // The same for the whole workgroup: it leaves together, before the barrier.
  if (probePlacement(probes[probeIndex].state) != kProbeStateInvalid) return;

  uint thread = gl_LocalInvocationID.x;
  uint levelStart = uint(update.level) * uint(update.probesPerLevel);
  ivec3 probe = probeWorldCoordinate(probeIndex % uint(update.probesPerLevel), update.originProbe, update.probesPerAxis);
  neighbourRadiance[thread] = sh2Zero();
  neighbourUsable[thread] = 0.0;
  neighbourSkyVisibility[thread] = vec4(0.0);
  if (thread < kProbeNeighbourCount) {
    ivec3 coordinate = probe + probeNeighbourOffset(thread);
    Probe neighbour = probes[levelStart + probeSlotIndex(coordinate, update.probesPerAxis)];
    // Invalid neighbours are not usable, so no workgroup reads a probe that another one writes.
    if (probeIsUsable(neighbour, coordinate)) {
      neighbourRadiance[thread] = probeRadianceSh(neighbour);
      neighbourUsable[thread] = 1.0;
      neighbourSkyVisibility[thread] = probeSkyVisibilitySh(neighbour);
    }
  }
  barrier();
  if (thread != 0u) return;

  Sh2Rgb sum = sh2Zero();
  float count = 0.0;
  vec4 skyVisibilitySum = vec4(0.0);
  for (uint i = 0u; i < kProbeNeighbourCount; ++i) {
    sum = sh2Add(sum, neighbourRadiance[i]);
    skyVisibilitySum += neighbourSkyVisibility[i];
    count += neighbourUsable[i];
  }
  if (count == 0.0) return;  // nothing around to fill from: it keeps what it has until a neighbour is traced
  Sh2Rgb mean = sh2Divide(sum, count);
  probes[probeIndex].radianceRed = packSh2Half(mean.r);
  probes[probeIndex].radianceGreen = packSh2Half(mean.g);
  probes[probeIndex].radianceBlue = packSh2Half(mean.b);
  probes[probeIndex].skyVisibility = packSh2Half(skyVisibilitySum / count);
}
