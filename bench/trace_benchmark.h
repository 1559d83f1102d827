#pragma once
// The SPEC §7 baselines of the voxel trace, both over the voxel scene a GI context built and timed with GPU
// timestamps: "the flat-DDA trace against the hierarchical trace (same rays, same hits)", and "a per-pixel voxel trace
// at the same quality against the probe pipeline".
#include "gpu_host/owned_device.h"
#include "image_io.h"
#include "scene.h"
#include "shared/sh.h"
#include "ssvgi/ssvgi.h"

#include <cstdint>
#include <vector>

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
TraceBenchmarkResult benchmarkVoxelTrace(gpu::OwnedDevice& device, const Context& context,
                                         const renderer::Camera& camera, const renderer::FloatImage& viewDistance,
                                         const renderer::FloatImage& normal, uint32_t rayCount, uint32_t repetitions,
                                         float maxDistance = 64.0f);

// The per-pixel trace with one number of rays per pixel.
struct PixelTraceResult {
  uint32_t raysPerPixel = 0;
  double milliseconds = 0.0;           // median GPU time of the traced pixels' rays
  double fullFrameMilliseconds = 0.0;  // scaled to every surface pixel of the frame
  double differenceFromSsvgi = 0.0;    // mean |E − E_ssvgi| over mean E_ssvgi, luminance, at the traced pixels
  double noise = 0.0;                  // the estimate's own: mean |E_a − E_b| / 2 of its two halves, over mean E
};

struct PixelTraceBaselineResult {
  uint32_t tracedPixels = 0;   // every `pixelStride`-th surface pixel in x and y
  uint32_t surfacePixels = 0;  // of the whole frame
  std::vector<PixelTraceResult> results;
};

// The per-pixel baseline: each traced surface pixel sends raysPerPixel cosine-distributed rays (a jittered square
// grid, so each count must be an even square) through the voxels with the hierarchical trace, and E = π/K·Σ L — a hit's
// voxel radiance (black from behind), a miss the sky's SH2, as the probes see them. `ssvgiIrradiance` is ssvgi's
// E_indirect of the same frame (rgb), `skyRadiance` the sky the frame gave ssvgi.
// Throws, naming the count, unless every count of rays per pixel is an even square.
void checkPixelTraceRayCounts(const std::vector<uint32_t>& raysPerPixel);

PixelTraceBaselineResult benchmarkPixelTrace(gpu::OwnedDevice& device, const Context& context,
                                             const renderer::Camera& camera, const renderer::FloatImage& viewDistance,
                                             const renderer::FloatImage& normal,
                                             const renderer::FloatImage& ssvgiIrradiance,
                                             const shader::Sh2Rgb& skyRadiance, uint32_t pixelStride,
                                             const std::vector<uint32_t>& raysPerPixel, uint32_t repetitions,
                                             float maxDistance = 64.0f);

}  // namespace ssvgi::bench
