// The work of a frame's passes, counted on the GPU where it depends on the data (ssvgi::Stats::work, `ssvgi bench`):
// what each pass did, which the device's speed does not change, beside the GPU times, which it does. The passes
// count only on a frame the host asks to (FrameDesc::countWork, VoxelVolume::countsWork), into a buffer of the voxel
// scene (kBindWorkCounters) cleared at the start of that frame and copied out at its end. Each thread sums its own
// work and adds it with one atomicAdd per counter (or a workgroup sums its threads' first). Adds commute, so the
// passes need no barrier between them for it (gpu::Bindings::accumulator): a frame that does not count pays for the
// counters with nothing but a uniform branch and a few additions in registers. 32 bits hold a frame's counts.
//
// Rays are voxel traces (traceVoxelsHierarchical, SPEC §4.4); their reads are the buffer words they load (brick
// lookups, occupancy masks and grid words, the voxel they meet: VoxelHit::reads), a trace's cost on any device.
#ifndef SSVGI_SHARED_WORK_COUNTERS_H
#define SSVGI_SHARED_WORK_COUNTERS_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

struct WorkCounters {
  // ObservedSpace, summed over the views: pixels whose ray enters the volume, and the brick cells those rays mark
  // observed (a read each, and an atomic where the cell was not yet).
  uint observedSpaceRays;
  uint observedSpaceCells;
  // SceneVoxelization of the camera's lit frame: the voxels of the blocks it injected (those of the listed bricks that
  // its Hi-Z test kept), and of those the voxels whose random point lies in the view, which read its texels.
  uint injectionVoxels;
  uint injectionVoxelsInView;
  // The same for the extra views (timed as "ssvgi: ExtraViews").
  uint extraViewInjectionVoxels;
  uint extraViewInjectionVoxelsInView;
  // VoxelRelight: the voxels whose light it gathers from the probes, and its visibility rays from those probes.
  uint relightVoxels;
  uint relightRays;
  uint relightReads;
  // ProbePlacement: the probes whose range it searches for voxels (those in the frustum, or offered beyond it), and
  // the occupancy grid words it reads.
  uint placementProbes;
  uint placementReads;
  // ProbeTrace: the probes traced and their rays (raysPerProbe each); and, for the probes that start afresh, the
  // visibility rays to the coarser level's probes they start from (coarserLevelRadiance).
  uint probeTraceProbes;
  uint probeTraceRays;
  uint probeTraceReads;
  uint probeTraceSeedRays;
  uint probeTraceSeedReads;
  // ProbeRelocate: the rays traced back to the surface a probe inside geometry moves past.
  uint relocateRays;
  uint relocateReads;
  // FinalGather: the tiles it gathered whose sample shows a surface (the others gather nothing), and its visibility
  // rays.
  uint gatherTiles;
  uint gatherRays;
  uint gatherReads;
};
SSVGI_CHECK_SIZE(WorkCounters, 84);

SSVGI_SHARED_END

#endif
