#version 450
// ProbePlacement (SPEC §4.5; the talk's "Adaptive Placement"): of the probes in the blocks the CPU found in view, keep
// those whose range reaches into the frustum and holds a voxel, up to the per-frame budget, as the list ProbeTrace
// works through (one workgroup per probe). A second dispatch then offers the blocks beyond the view whose turn it is
// (Settings::probeBlocksBeyondView), for what the budget leaves: the probes that light off-screen voxels (SPEC §6.1).
//
// A probe's range is one spacing on each axis: the 8 grid cells it is a corner of. A surface point is shaded from
// the 8 probes at the corners of its cell, so these are exactly the probes a gather can read; the others would be
// traced for nothing ("only place probes around the scene, to cut the number updated", the talk). The search reads the
// occupancy hierarchy (voxel_access.glsl) at the level whose cells are the spacing (the talk: "probes of each level
// use the voxel octree to speed up the search"): 8 bits for a level whose spacing is 1, 2 or 4 bricks.
#include "gi/gi_frame.glsl"
#include "gi/voxels/voxel_access.glsl"
#include "gi/work_counting.glsl"
#include "shared/probe_interface.h"

layout(local_size_x = 64) in;  // one block of kProbeBlockSize³ probes

layout(binding = kBindProbeUpdate, std140) readonly buffer ProbeUpdateBlock { ProbeUpdate update; };
layout(binding = kBindProbeBlocks) readonly buffer ProbeBlocks { uint offeredBlocks[]; };
layout(binding = kBindProbeList) buffer ProbeList {
  IndirectList list;
  uint listedProbes[];
};
layout(binding = kBindProbes) readonly buffer Probes { Probe probes[]; };
layout(binding = kBindProbeChanges) readonly buffer Changes { uint changes[]; };

// Whether any voxel lies in [lo, hi): the cells of the search level that cover it, each inside the voxel volume
// (a cell of a toroidal grid level — the search level is one — is wholly inside or outside it; outside, its toroidal
// bit belongs to another cell). The cells searched are clipped to the volume first, so that no probe spacing makes
// the loop longer than the volume.
// Counts the grid words it reads in `reads`.
bool voxelsWithin(vec3 lo, vec3 hi, inout uint reads) {
  uint level = update.placementSearchLevel;
  float cellSize = volume.voxelSize * float(1u << level);
  int bricksPerCell = 1 << (level - kFirstGridLevel);
  ivec3 volumeFirst = volume.originBrick / bricksPerCell;  // the volume's origin is a whole number of cells
  ivec3 volumeLast = volumeFirst + volume.dimensionsBricks / bricksPerCell - 1;
  ivec3 first = max(ivec3(floor(max(lo / cellSize, vec3(volumeFirst)))), volumeFirst);
  ivec3 last = min(ivec3(ceil(min(hi / cellSize, vec3(volumeLast + 1)))) - 1, volumeLast);
  for (int z = first.z; z <= last.z; ++z)
    for (int y = first.y; y <= last.y; ++y)
      for (int x = first.x; x <= last.x; ++x) {
        ivec3 cell = ivec3(x, y, z);
        if (!brickInVolume(cell * bricksPerCell, volume)) continue;
        ++reads;
        if (gridOccupied(level, cell)) return true;
      }
  return false;
}

// Whether a probe sits this update out (Settings::settledProbeInterval; SPEC §6.2, "spend more of the ray budget on
// probes that changed"): its history has reached the cap, it follows no change — no recovery under way, and no drift
// summed from its last updates (light still coming round the loop, as in a hall lit through a roof its views have not
// all seen, whose light takes hundreds of frames to settle: QUALITY.md, "Settled probes sit out every other update") —
// and this update of its level is not its turn, which its world coordinate sets so that neighbours take turns. A frame
// that starts a shared recovery traces every probe: it is how a change many probes see reaches those that have not seen
// it yet.
bool sitsOut(ivec3 probe, uint index) {
  int interval = int(update.settledProbeInterval);
  if (interval <= 1 || update.startsSharedRecovery != 0u) return false;
  Probe stored = probes[index];
  ProbeChange change = unpackProbeChange(changes[index]);
  bool settled = probeSlotHolds(stored, probe) && probeHistoryCount(stored.state) >= update.historyCap &&
                 change.recoveryUpdates == 0u && change.drift == 0.0;
  int turnCount = probe.x + probe.y + probe.z + int(update.frameIndex / kProbeLevels);
  int turn = turnCount - interval * int(floor(float(turnCount) / float(interval)));  // ≥ 0 for negative coordinates
  return settled && turn != 0;
}

layout(push_constant) uniform Push { ProbePlacementPush push; };

void main() {
  uvec3 block = unpackProbeBlock(offeredBlocks[push.firstBlock + gl_WorkGroupID.x]);
  uint inBlock = gl_LocalInvocationID.x;
  uvec3 probeInBlock = uvec3(inBlock % kProbeBlockSize, (inBlock / kProbeBlockSize) % kProbeBlockSize,
                             inBlock / (kProbeBlockSize * kProbeBlockSize));
  ivec3 probe = update.originProbe + ivec3(block * kProbeBlockSize + probeInBlock);
  float spacing = update.spacing;
  vec3 lo = vec3(probe - 1) * spacing;
  vec3 hi = vec3(probe + 1) * spacing;
  if (push.inView != 0u && !boxInFrustum(lo, hi, frame.frustumPlanes)) return;
  uint reads = 0u;
  bool holdsVoxels = voxelsWithin(lo, hi, reads);
  if (countsWork()) {
    atomicAdd(work.placementProbes, 1u);
    atomicAdd(work.placementReads, reads);
  }
  if (!holdsVoxels) return;
  uint level = uint(update.level);
  uint index = level * uint(update.probesPerLevel) + probeSlotIndex(probe, update.probesPerAxis);
  if (sitsOut(probe, index)) return;

  uint slot = atomicAdd(list.count, 1u);
  if (slot >= update.probeBudget) {  // over budget: undo, so that count ends as the number listed
    atomicAdd(list.count, uint(-1));
    return;
  }
  atomicAdd(list.groupCountX, 1u);
  listedProbes[slot] = index;
}
