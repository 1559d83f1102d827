#pragma once
// The SPEC §7 baseline "flat-DDA trace against the hierarchical trace (same rays, same hits)": both traces over the
// voxel scene a GI context built, on the same rays, timed with GPU timestamps.
#include "gpu/device.h"
#include "image_io.h"
#include "scene.h"
#include "ssvgi/ssvgi.h"

#include <cstdint>

namespace ssvgi::bench {

struct TraceMethodResult {
  double milliseconds = 0.0;  // median of the repetitions
  double raysPerSecond = 0.0;
  double readsPerRay = 0.0;   // buffer loads per ray (lookups, masks, grid words, the hit voxel)
  double hitFraction = 0.0;
};

struct TraceBenchmarkResult {
  uint32_t rays = 0;
  TraceMethodResult hierarchical;
  TraceMethodResult flat;
  double identicalHits = 0.0;  // fraction of rays whose first hit (or miss) is the same voxel in both
};

// Rays leave visible surfaces of the view (a bounce, as the GI traces): from `rayCount` random pixels with a surface,
// offset along the normal, in cosine-distributed directions, up to `maxDistance` metres.
TraceBenchmarkResult benchmarkVoxelTrace(gpu::Device& device, const Context& context, const renderer::Camera& camera,
                                         const renderer::FloatImage& viewDistance, const renderer::FloatImage& normal,
                                         uint32_t rayCount, uint32_t repetitions, float maxDistance = 64.0f);

}  // namespace ssvgi::bench
