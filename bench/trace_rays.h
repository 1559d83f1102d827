#pragma once
// TraceRays: a buffer of rays traced through the voxel scene with the hierarchical or the flat voxel DDA
// (shaders/gi/voxels/voxel_trace.glsl), for the tests and for the benchmark that compares the two on the same rays
// (SPEC §7 baselines): hit voxels, distances, radiance and the buffer reads each ray made. Not a pass of the library's:
// it is built into the benchmarks, which the tests link too, and stays in ssvgi::gi beside the voxel scene it reads.
#include "gpu/command_list.h"
#include "shared/voxel_trace_interface.h"
#include "gi/voxels/voxel_scene.h"

namespace ssvgi::gi {

enum class TraceMethod : uint32_t {
  Hierarchical = shader::kTraceMethodHierarchical,  // over the occupancy hierarchy (SPEC §4.4)
  Flat = shader::kTraceMethodFlat,                  // voxel by voxel: the baseline
  NearSurfaces = shader::kTraceMethodNearSurfaces,  // hierarchical from the brick level (the probes' rays)
};

class TraceRays {
 public:
  TraceRays(gpu::Device& device, TraceMethod method);
  // Traces rays[i] (shader::VoxelTraceRay) into hits[i] (shader::VoxelTraceHit) for i < rayCount, as the scope
  // "ssvgi: TraceRays" (the profiler sums scopes of one name in a frame: time the two methods in separate frames).
  void record(gpu::CommandList& commands, const VoxelScene& scene, const gpu::Buffer& rays, const gpu::Buffer& hits,
              uint32_t rayCount);
  TraceMethod method() const { return method_; }

 private:
  TraceMethod method_;
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
