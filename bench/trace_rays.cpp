#include "trace_rays.h"

#include "ssvgi_bench_shaders.h"

#include <cassert>

namespace ssvgi::gi {

TraceRays::TraceRays(gpu::Device& device, TraceMethod method)
    : method_(method), pipeline_(device, bench::shaders::trace_rays_comp, {static_cast<uint32_t>(method)}) {}

void TraceRays::record(gpu::CommandList& commands, const VoxelScene& scene, const gpu::Buffer& rays,
                       const gpu::Buffer& hits, uint32_t rayCount) {
  assert(rays.size() >= VkDeviceSize(rayCount) * sizeof(shader::VoxelTraceRay));
  assert(hits.size() >= VkDeviceSize(rayCount) * sizeof(shader::VoxelTraceHit));
  auto scope = commands.scope("ssvgi: TraceRays");
  // Cleared first, so that no hit can come from an earlier trace into the same memory. The barrier between the clear
  // and the trace also times it on lavapipe, whose timestamps are taken when it next flushes: with no barrier in the
  // scope both would fall after the dispatch (docs/PERFORMANCE.md, "Voxel trace: hierarchical against flat").
  commands.fillBuffer(hits, 0u);
  commands.dispatch(pipeline_,
                    scene.bindings().buffer(shader::kBindTraceRaysRays, rays).buffer(shader::kBindTraceRaysHits, hits),
                    {rayCount, 1, 1}, rayCount);
}

}  // namespace ssvgi::gi
