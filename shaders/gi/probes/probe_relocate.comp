#version 450
// ProbeRelocate (SPEC §4.5; the talk's "Virtual Offset"): after ProbeTrace, each listed probe whose normal-dot is
// negative in some direction sees back faces — it is inside geometry, which shows as dark blotches ("the probe is in
// the voxels", the talk). It moves along its minimum-distance direction, past that surface, by less than half a
// spacing; a probe that cannot get out so is marked invalid (ProbeDilate fills it; gathers leave it out).
//
// The per-direction minimum normal-dot and distance are the probe's SH2 of them (kept by ProbeTrace: no extra memory)
// evaluated along the 26 neighbour directions: a smooth estimate over all 1024 directions, which is what we want —
// a back face must cover a good part of the sphere to turn the SH negative, so a few grazing rays do not move a probe.
// The direction is the nearest back face: the least distance among the directions with a negative normal-dot, ties
// (a probe inside an occupied voxel sees everything at distance 0) to the most negative normal-dot, which for a probe
// inside a voxel points out through the voxel's front.
//
// How far: a ray traced back towards the probe from the farthest point the offset may reach along that direction
// meets the far side of the surface; the probe goes halfway between that side and the farthest point, as far from the
// surface as the bound allows. None (the surface extends past the bound) or too little room: invalid. A moved or
// invalidated probe starts afresh (m = 0), so that its next trace alone — from its new position — decides again:
// seeing no back faces it stays; an invalid probe seeing none (the geometry went) becomes active again.
#include "gi/voxels/voxel_trace.glsl"
#include "gi/work_counting.glsl"
#include "shared/probe_interface.h"

layout(local_size_x = kProbeListGroupSize) in;  // one thread per listed probe

layout(binding = kBindProbeUpdate, std140) readonly buffer ProbeUpdateBlock { ProbeUpdate update; };
layout(binding = kBindProbes) buffer Probes { Probe probes[]; };
layout(binding = kBindProbeList) readonly buffer ProbeList {
  IndirectList list;
  uint listedProbes[];
};

// The neighbour direction of the nearest back face, or -1 when the probe sees none.
int nearestBackFace(Probe probe, float spacing) {
  vec4 normalDotSh = probeNormalDotSh(probe);
  vec4 distanceSh = probeDistanceSh(probe, spacing);
  int nearest = -1;
  float nearestNormalDot = 0.0, nearestDistance = 0.0;
  for (int i = 0; i < int(kProbeNeighbourCount); ++i) {
    vec4 basis = sh2Basis(normalize(vec3(probeNeighbourOffset(uint(i)))));
    float normalDot = dot(normalDotSh, basis);
    float distance = dot(distanceSh, basis);
    if (normalDot >= 0.0) continue;
    if (nearest < 0 || distance < nearestDistance || (distance == nearestDistance && normalDot < nearestNormalDot)) {
      nearest = i;
      nearestNormalDot = normalDot;
      nearestDistance = distance;
    }
  }
  return nearest;
}

void main() {
  if (gl_GlobalInvocationID.x >= list.count) return;
  uint probeIndex = listedProbes[gl_GlobalInvocationID.x];
  Probe probe = probes[probeIndex];
  uint state = probe.state;
  uint nextDirection = probeNextDirection(state);
  int nearest = nearestBackFace(probe, update.spacing);
  if (nearest < 0) {
    if (probePlacement(state) == kProbeStateInvalid)
      probes[probeIndex].state = packProbeState(probeHistoryCount(state), nextDirection, kProbeStateActive);
    return;
  }

  float spacing = update.spacing;
  float offsetStep = spacing / kProbeOffsetStepsPerSpacing;
  ivec3 coordinate = probeWorldCoordinate(probeIndex % uint(update.probesPerLevel), update.originProbe,
                                          update.probesPerAxis);
  vec3 offset = vec3(unpackProbeOffset(probeOffsetCode(state))) * offsetStep;  // zero for an invalid probe
  vec3 direction = normalize(vec3(probeNeighbourOffset(uint(nearest))));
  // How far the offset can go along the direction before one of its components reaches the bound.
  float reach = 1.0e30;  // every neighbour direction has a non-zero component
  for (int axis = 0; axis < 3; ++axis)
    if (direction[axis] != 0.0)
      reach = min(reach, (sign(direction[axis]) * float(kProbeMaxOffsetSteps) * offsetStep - offset[axis]) /
                             direction[axis]);
  vec3 farthest = vec3(coordinate) * spacing + offset + direction * reach;
  // Traced a voxel past the probe: a probe inside a voxel has that voxel's far side at (or, rounded, just past) its
  // own position.
  VoxelHit surface = traceVoxelsHierarchical(farthest, -direction, max(reach, 0.0) + volume.voxelSize,
                                             kIgnoreObservedSpace);
  if (countsWork()) {
    atomicAdd(work.relocateRays, 1u);
    atomicAdd(work.relocateReads, surface.reads);
  }
  // Halfway into the room behind the surface must stay clear of it after rounding each component to a step.
  float room = surface.distance;
  bool escapes = reach > 0.0 && surface.hit && room >= sqrt(3.0) * offsetStep;
  uint moved = kProbeStateInvalid, offsetCode = 0u;
  if (escapes) {
    ivec3 steps = ivec3(round((offset + direction * (reach - 0.5 * room)) / offsetStep));
    offsetCode = packProbeOffset(clamp(steps, ivec3(-kProbeMaxOffsetSteps), ivec3(kProbeMaxOffsetSteps)));
    moved = kProbeStateActive;
  }
  probes[probeIndex].state = packProbeState(0u, nextDirection, moved, offsetCode);
}
