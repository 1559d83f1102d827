#ifndef SSVGI_PROBE_IRRADIANCE_GLSL
#define SSVGI_PROBE_IRRADIANCE_GLSL
// Irradiance at a surface point from the probe volume (SPEC §4.6; the talk's "Probe Volume sampling with custom
// weights"): the level choice with noise at level boundaries, and the 8-probe weights with the talk's three leak
// remedies and a voxel visibility test. FinalGather samples it for the screen, VoxelRelight for the voxels its views
// lit with direct light only (SPEC §6.1), ConfidenceDebugView for the voxels the camera looks at.
#include "gi/voxels/voxel_trace.glsl"
#include "shared/gather_interface.h"

layout(binding = kBindGatherConstants, std140) readonly buffer GatherConstantsBlock { GatherConstants gather; };
layout(binding = kBindGatherProbes) readonly buffer Probes { Probe probes[]; };

// What the gather reads of the frame's constants, read once for an invocation rather than for each point it lights,
// each level it tries or each probe it traces from (gi/voxels/voxel_access.glsl's VolumeLayout says why).
struct GatherFrame {
  GatherProbeLevel levels[kProbeLevels];
  ivec3 probesPerAxis;    // of every level
  uint probesPerLevel;
  Sh2Rgb skyRadiance;     // for the sky part of the probes' light (readProbeIrradiance)
  VoxelTraceFrame trace;  // for the visibility tests, and the voxel size
};

GatherFrame gatherFrame() {
  return GatherFrame(gather.probeLevels, gather.probesPerAxis, uint(gather.probesPerLevel), gather.skyRadiance,
                     voxelTraceFrame());
}

// How far a point lies inside the cells of a level, in spacings; negative when some of its 8 probes are outside it.
float insideMargin(GatherFrame constants, uint level, vec3 position) {
  vec3 probeUnits = position / constants.levels[level].spacing - vec3(constants.levels[level].origin);
  vec3 margins = min(probeUnits, vec3(constants.probesPerAxis - 1) - probeUnits);
  return min(margins.x, min(margins.y, margins.z));
}

// The finest level holding the point, or near its boundary — with a probability growing toward it — the next coarser
// one (the talk's "Probe Volume Interpolation: Noise + Light Gather Temporal Filter"). kProbeLevels: none holds it.
uint chooseLevel(GatherFrame constants, vec3 position, float noise) {
  for (uint level = 0u; level < kProbeLevels; ++level) {
    float margin = insideMargin(constants, level, position);
    if (margin < 0.0) continue;
    bool coarserHoldsIt = level + 1u < kProbeLevels && insideMargin(constants, level + 1u, position) >= 0.0;
    if (coarserHoldsIt && noise * kGatherLevelBlendSpacings > margin) continue;
    return level;
  }
  return kProbeLevels;
}

// What the probes around a surface point give it.
struct GatheredLight {
  vec3 irradiance;   // E(n), W/m²
  float confidence;  // the probes' known fraction (SPEC §6.4), weighted as their light is; 0 when none contributed
  // The weight their next updates give new light, 1/(m+1) for history count m, weighted as their light is: high
  // while they follow a change (a new probe, or change detection cut m), 1/(historyCap+1) once they are settled.
  float probeBlend;
  bool found;        // some probe contributed
};

// One of the 8 probes around a point, as the gather reads it.
struct CornerProbe {
  Probe stored;
  vec3 position;    // with its virtual offset
  float trilinear;  // its trilinear weight; 0 where it is outside the level or knows nothing
};

// A level's constants as the gather's loops over the probes read them.
struct GatherLevel {
  ivec3 origin;         // GatherProbeLevel
  float spacing;
  ivec3 probesPerAxis;  // GatherConstants
  uint firstProbe;      // the level's first probe in the probe buffer
};

GatherLevel gatherLevelConstants(GatherFrame constants, uint level) {
  GatherProbeLevel levelConstants = constants.levels[level];
  return GatherLevel(levelConstants.origin, levelConstants.spacing, constants.probesPerAxis,
                     level * constants.probesPerLevel);
}

CornerProbe cornerProbe(GatherLevel level, ivec3 cell, vec3 fraction, int corner) {
  ProbeCellCorner around = probeCellCorner(cell, fraction, corner);
  ivec3 probe = around.probe;
  CornerProbe result;
  result.trilinear = 0.0;
  if (any(lessThan(probe, level.origin)) || any(greaterThanEqual(probe, level.origin + level.probesPerAxis)))
    return result;
  result.stored = probes[level.firstProbe + probeSlotIndex(probe, level.probesPerAxis)];
  // A probe never traced, inside geometry, just moved, or a slot that still holds a probe the level scrolled away
  // from, knows nothing here.
  if (!probeIsUsable(result.stored, probe)) return result;
  result.position = probeWorldPosition(probe, level.spacing, result.stored.state);
  result.trilinear = around.weight;
  return result;
}

// The talk's weights of a corner probe (trilinear × normal × distance), before the visibility test.
float cornerWeight(CornerProbe probe, float spacing, vec3 position, vec3 normal, vec3 biased) {
  if (probe.trilinear <= 0.0) return 0.0;
  // "Normal Weight": probes behind the surface count less (from the true point, as DDGI does).
  vec3 toProbe = probe.position - position;
  float facing = 0.5 * (dot(toProbe, normal) / max(length(toProbe), 1e-4) + 1.0);
  float weight = probe.trilinear * (facing * facing + kGatherBackfacingProbeWeight);
  // "Distance Weight": the probe's traced distance toward the point against the point's distance.
  vec3 fromProbe = biased - probe.position;
  float pointDistance = length(fromProbe);
  if (pointDistance > 1e-4) {
    float traced = dot(probeDistanceSh(probe.stored, spacing), sh2Basis(fromProbe / pointDistance));
    float visible = clamp(traced / pointDistance, 0.0, 1.0);
    weight *= max(visible * visible * visible, kGatherOccludedProbeWeight);
  }
  return weight;
}

// Beyond the talk's weights, which it says only ease leaks: a probe with a voxel between it and the point does not light
// it. The SH2 distance is far too coarse to see a wall a probe stands a few centimetres behind (the virtual offset may
// put it on either side), and through a closed door the lit room's probes would light the dark one (`ssvgi scenario
// leak`). A voxel within half a voxel of the biased point is the point's own surface. With
// `watchesObservedSpace` (FinalGather's, where the probes' rays watch observed space, SPEC §6.4) space between them
// that no view has observed stops it too, and a hole in a wall's voxels that no view has seen through stops it as the
// wall would (voxel_trace.glsl). Unknown is not open air either: the walls of a sealed room have holes at first, and a
// probe outside it, lit by the sky, lit them through the holes (docs/QUALITY.md, "A sealed room").
bool probeSeesPoint(GatherFrame constants, vec3 probePosition, vec3 biased, bool watchesObservedSpace) {
  vec3 fromProbe = biased - probePosition;
  float pointDistance = length(fromProbe);
  if (pointDistance <= 1e-4) return true;
  VoxelHit blocker = traceVoxelsNearSurfaces(constants.trace, probePosition, fromProbe / pointDistance, pointDistance,
                                             watchesObservedSpace);
  float reached = min(blocker.unobservedDistance, blocker.distance);
  return !(blocker.hit || blocker.unobserved) || reached >= pointDistance - 0.5 * constants.trace.voxelSize;
}

// Irradiance at a surface point from the 8 probes of a level around it, and their confidence, leaving out a probe with
// a voxel between it and the point (a voxel trace per probe). Only a pass that does not write the voxels may trace
// them.
GatheredLight gatherLevel(GatherFrame constants, uint levelIndex, vec3 position, vec3 normal,
                          bool watchesObservedSpace) {
  GatherLevel level = gatherLevelConstants(constants, levelIndex);
  float spacing = level.spacing;
  Sh2Rgb skyRadiance = constants.skyRadiance;
  // "Normal Bias" (the talk): interpolate and test visibility from a point off the surface, so that the probes just
  // behind a wall do not see the point on its front as unoccluded.
  vec3 biased = position + normal * (kGatherNormalBiasSpacings * spacing);
  vec3 grid = biased / spacing;
  ivec3 cell = ivec3(floor(grid));
  vec3 fraction = grid - vec3(cell);
  float weights[kProbeCellCorners];
  float weightBeforeVisibility = 0.0;
  for (int corner = 0; corner < kProbeCellCorners; ++corner) {
    weights[corner] = cornerWeight(cornerProbe(level, cell, fraction, corner), spacing, position, normal, biased);
    weightBeforeVisibility += weights[corner];
  }
  // The traces are most of the gather's cost: a probe whose weight is a negligible share of the 8 probes' is left out
  // rather than traced, which changes E by less than that share.
  float negligibleWeight = kGatherNegligibleProbeShare * weightBeforeVisibility;
  uint kept = 0u;  // bit per corner
  for (int corner = 0; corner < kProbeCellCorners; ++corner)
    if (weights[corner] > negligibleWeight) kept |= 1u << uint(corner);
  // Each kept probe's own reading: where the probes see a small bright source from different sides, one reading of
  // their mean SH is darker than the mean of their readings (QUALITY.md, "Cheaper passes").
  vec3 readings[kProbeCellCorners];
  vec3 positions[kProbeCellCorners];
  float knownFractions[kProbeCellCorners];
  float blends[kProbeCellCorners];
  vec3 meanReading = vec3(0.0);
  float keptWeight = 0.0;
  // Over the kept corners only: invocations run in lock-step groups, and a loop over all eight would make each group
  // wait for a trace at every corner some invocation keeps.
  for (uint left = kept; left != 0u; left &= left - 1u) {
    int corner = findLSB(left);
    CornerProbe probe = cornerProbe(level, cell, fraction, corner);
    Probe stored = probe.stored;
    positions[corner] = probe.position;
    readings[corner] = readProbeIrradiance(stored, normal, skyRadiance);
    knownFractions[corner] = probeKnownFraction(stored);
    blends[corner] = 1.0 / float(probeHistoryCount(stored.state) + 1u);
    meanReading += weights[corner] * readings[corner];
    keptWeight += weights[corner];
  }
  // The visibility test only chooses which of these probes light the point. Where their readings agree to within
  // kGatherAgreement of their mean, any choice but none gives E within that share of it: one trace, from the heaviest,
  // shows that some probe sees the point, and the others are not traced. One loop of traces, because lavapipe pays for
  // every copy of the trace in a shader, taken or not.
  uint visible = kept;  // bit per corner
  if (keptWeight > 0.0) {
    meanReading /= keptWeight;
    float tolerance = kGatherAgreement * max(meanReading.r, max(meanReading.g, meanReading.b));
    bool agree = true;
    int heaviest = findLSB(kept);
    for (uint left = kept; left != 0u; left &= left - 1u) {
      int corner = findLSB(left);
      agree = agree && all(lessThanEqual(abs(readings[corner] - meanReading), vec3(tolerance)));
      if (weights[corner] > weights[heaviest]) heaviest = corner;
    }
    uint heaviestBit = 1u << uint(heaviest);
    uint toTrace = agree ? heaviestBit : kept;
    visible = 0u;
    while (toTrace != 0u) {
      int corner = findLSB(toTrace);
      toTrace &= toTrace - 1u;
      if (probeSeesPoint(constants, positions[corner], biased, watchesObservedSpace))
        visible |= 1u << uint(corner);
      if (toTrace == 0u && agree) {  // the heaviest traced: all seen, or none yet and the rest to trace
        agree = false;
        if (visible != 0u)
          visible = kept;
        else
          toTrace = kept & ~heaviestBit;
      }
    }
  }
  vec3 irradiance = vec3(0.0);
  float known = 0.0;
  float blend = 0.0;
  float totalWeight = 0.0;
  for (; visible != 0u; visible &= visible - 1u) {
    int corner = findLSB(visible);
    float weight = weights[corner];
    irradiance += weight * readings[corner];
    // The same probes with the same weights: the confidence says how much of this E rests on observed space.
    known += weight * knownFractions[corner];
    blend += weight * blends[corner];
    totalWeight += weight;
  }
  if (totalWeight <= 0.0) return GatheredLight(vec3(0.0), 0.0, 1.0, false);
  return GatheredLight(irradiance / totalWeight, known / totalWeight, blend / totalWeight, true);
}

// Irradiance and confidence at a surface point from the finest level that holds it (near a level's boundary, by
// `noise` in [0, 1), the next coarser one); where a level's probes are stale or untraced, a coarser level (seeded
// earlier, SPEC §4.5) answers. `watchesObservedSpace`: the visibility tests watch observed space (probeSeesPoint).
GatheredLight probeLight(GatherFrame constants, vec3 position, vec3 normal, float noise, bool watchesObservedSpace) {
  GatheredLight light = GatheredLight(vec3(0.0), 0.0, 1.0, false);
  for (uint level = chooseLevel(constants, position, noise); level < kProbeLevels && !light.found; ++level)
    light = gatherLevel(constants, level, position, normal, watchesObservedSpace);
  return light;
}

// The probes' irradiance at a voxel's surface for VoxelRelight: rgb E; a: 1 when some probe contributed. Its
// visibility tests take space no view has observed for open: watching it there too slowed the fall of a light switched
// off below issue 14's target, while what it lets into a sealed room's walls is small (docs/QUALITY.md, "A sealed
// room").
vec4 probeIrradiance(GatherFrame constants, vec3 position, vec3 normal, float noise) {
  GatheredLight light = probeLight(constants, position, normal, noise, kIgnoreObservedSpace);
  return vec4(light.irradiance, light.found ? 1.0 : 0.0);
}

#endif
