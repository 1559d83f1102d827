#version 450
// ProbeDilate (SPEC §4.5; the talk's "Probe Dilation": "blend the neighbouring probes"): each listed probe that
// ProbeRelocate left invalid takes the mean radiance of its usable neighbours on its level (the 26 around it). Gathers
// leave invalid probes out anyway; the fill is for what reads a probe without asking — a finer level starting a new
// probe, hardware-filtered copies, debug views — so that they see the light around it rather than the black inside a
// wall. Only radiance is filled: distance and normal-dot stay the probe's own, which ProbeRelocate re-checks.
#include "shared/probe_interface.h"

layout(local_size_x = kProbeListGroupSize) in;  // one thread per listed probe

layout(binding = kBindProbeUpdate, std140) readonly buffer ProbeUpdateBlock { ProbeUpdate update; };
layout(binding = kBindProbes) buffer Probes { Probe probes[]; };
layout(binding = kBindProbeList) readonly buffer ProbeList {
  IndirectList list;
  uint listedProbes[];
};

void main() {
  if (gl_GlobalInvocationID.x >= list.count) return;
  uint probeIndex = listedProbes[gl_GlobalInvocationID.x];
  if (probePlacement(probes[probeIndex].state) != kProbeStateInvalid) return;

  uint levelStart = uint(update.level) * uint(update.probesPerLevel);
  ivec3 probesPerAxis = update.probesPerAxis;
  ivec3 probe = probeWorldCoordinate(probeIndex % uint(update.probesPerLevel), update.originProbe, probesPerAxis);
  Sh2Rgb sum = sh2Zero();
  float count = 0.0;
  vec4 skyVisibilitySum = vec4(0.0);
  for (uint i = 0u; i < kProbeNeighbourCount; ++i) {
    ivec3 coordinate = probe + probeNeighbourOffset(i);
    Probe neighbour = probes[levelStart + probeSlotIndex(coordinate, probesPerAxis)];
    // Invalid neighbours are not usable, so no thread reads a probe that another one writes.
    if (!probeIsUsable(neighbour, coordinate)) continue;
    sum = sh2Add(sum, probeRadianceSh(neighbour));
    skyVisibilitySum += probeSkyVisibilitySh(neighbour);
    count += 1.0;
  }
  if (count == 0.0) return;  // nothing around to fill from: it keeps what it has until a neighbour is traced
  Sh2Rgb mean = sh2Divide(sum, count);
  probes[probeIndex].radianceRed = packSh2Half(mean.r);
  probes[probeIndex].radianceGreen = packSh2Half(mean.g);
  probes[probeIndex].radianceBlue = packSh2Half(mean.b);
  probes[probeIndex].skyVisibility = packSh2Half(skyVisibilitySum / count);
}
