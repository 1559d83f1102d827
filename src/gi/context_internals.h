#pragma once
// White-box access to a context's GPU state, for the library's own tests and benchmarks (not part of the API).
#include "ssvgi/ssvgi.h"
#include "gather/gather_targets.h"
#include "probes/probe_volume.h"
#include "voxels/voxel_scene.h"

namespace ssvgi::gi {

const VoxelScene& voxelSceneOf(const Context& context);
const ProbeVolume& probeVolumeOf(const Context& context);
const GatherTargets& gatherTargetsOf(const Context& context);

}  // namespace ssvgi::gi
