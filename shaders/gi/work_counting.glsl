// The counters of the passes' work (shared/work_counters.h), for a pass that counts it. A pass counts only where
// countsWork(), a branch on a uniform.
#ifndef SSVGI_WORK_COUNTING_GLSL
#define SSVGI_WORK_COUNTING_GLSL

#include "gi/voxels/voxel_access.glsl"
#include "shared/work_counters.h"

layout(binding = kBindWorkCounters) buffer WorkCountersBlock { WorkCounters work; };

bool countsWork() { return volume.countsWork != 0u; }

#endif
