#include "trace_benchmark.h"

#include "camera.h"
#include "gi/context_internals.h"
#include "gpu/command_list.h"
#include "gpu/profiler.h"
#include "gpu_host/transfers.h"
#include "ssvgi/pixel_coordinates.h"
#include "trace_rays.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace ssvgi::bench {

namespace {

// Rays that leave visible surfaces of a view, as the GI's bounces do: from a surface pixel's point, offset along its
// normal by `offset` metres, in a cosine-distributed direction around the normal.
class SurfaceRays {
 public:
  SurfaceRays(const renderer::Camera& camera, const renderer::FloatImage& viewDistance,
              const renderer::FloatImage& normal, float offset)
      : camera_(camera), viewDistance_(viewDistance), normal_(normal), offset_(offset) {
    const uint32_t width = viewDistance.width, height = viewDistance.height;
    inverseViewProjection_ = glm::inverse(
        renderer::reversedZInfiniteProjection(camera.verticalFov, float(width) / float(height), camera.nearPlane) *
        renderer::viewMatrix(camera));
    for (uint32_t i = 0; i < width * height; ++i)
      if (viewDistance.pixels[i] > 0.0f) surfacePixels_.push_back(i);
    if (surfacePixels_.empty()) throw std::runtime_error("the benchmark view shows no surface to trace from");
  }

  const std::vector<uint32_t>& surfacePixels() const { return surfacePixels_; }

  // The ray from `pixel` whose direction is the cosine-distributed image of `unitSquare` (Malley's method).
  shader::VoxelTraceRay ray(uint32_t pixel, glm::vec2 unitSquare, float maxDistance) const {
    const uint32_t width = viewDistance_.width, height = viewDistance_.height;
    const glm::vec2 ndc = shader::ssvgiPixelToNdc(glm::vec2(pixel % width, pixel / width), glm::vec2(width, height));
    const glm::vec4 onPlane = inverseViewProjection_ * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 view = glm::normalize(glm::vec3(onPlane) / onPlane.w - camera_.position);
    const glm::vec3 n = glm::normalize(glm::vec3(normal_.pixels[pixel * 3], normal_.pixels[pixel * 3 + 1],
                                                 normal_.pixels[pixel * 3 + 2]));
    const float r = std::sqrt(unitSquare.x), phi = glm::two_pi<float>() * unitSquare.y;
    const glm::vec3 tangent =
        glm::normalize(glm::cross(std::abs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0), n));
    const glm::vec3 bitangent = glm::cross(n, tangent);
    const glm::vec3 direction = glm::normalize(tangent * (r * std::cos(phi)) + bitangent * (r * std::sin(phi)) +
                                               n * std::sqrt(std::max(0.0f, 1.0f - r * r)));
    const glm::vec3 origin = camera_.position + view * viewDistance_.pixels[pixel] + n * offset_;
    return {origin, maxDistance, direction, 0u};
  }

 private:
  const renderer::Camera& camera_;
  const renderer::FloatImage& viewDistance_;
  const renderer::FloatImage& normal_;
  float offset_;
  glm::mat4 inverseViewProjection_{1.0f};
  std::vector<uint32_t> surfacePixels_;
};

struct TimedTrace {
  double milliseconds = 0.0;  // median of the repetitions
  std::vector<shader::VoxelTraceHit> hits;
};

// Traces `rays` through the context's voxels with `method`, `repetitions` times.
TimedTrace traceTimed(gpu::OwnedDevice& device, const Context& context, gi::TraceMethod method,
                      const std::vector<shader::VoxelTraceRay>& rays, uint32_t repetitions) {
  const gi::VoxelScene& scene = gi::voxelSceneOf(context);
  gpu::Buffer rayBuffer(device, "benchmark rays", rays.size() * sizeof(shader::VoxelTraceRay),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device, rayBuffer, std::as_bytes(std::span(rays)));
  gpu::Buffer hitBuffer(device, "benchmark hits", rays.size() * sizeof(shader::VoxelTraceHit),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::DescriptorArena descriptors(device);
  gpu::Profiler profiler(device);
  if (!profiler.supported()) throw std::runtime_error("the device has no timestamps: cannot time the traces");
  gi::TraceRays trace(device, method);
  std::vector<double> times;
  for (uint32_t repetition = 0; repetition < repetitions; ++repetition) {
    descriptors.reset();
    device.submitAndWait([&](VkCommandBuffer commandBuffer) {
      gpu::CommandList commands(device, commandBuffer, descriptors, &profiler);
      profiler.begin(commandBuffer);
      trace.record(commands, scene, rayBuffer, hitBuffer, uint32_t(rays.size()));
    });
    for (const auto& timing : profiler.resolve()) times.push_back(timing.milliseconds);
  }
  // The median: lavapipe's timestamps are taken on its CPU threads and an occasional one is meaningless.
  std::sort(times.begin(), times.end());
  return {times[times.size() / 2], gpu::readBufferAs<shader::VoxelTraceHit>(device, hitBuffer)};
}

float luminance(glm::vec3 rgb) { return glm::dot(rgb, glm::vec3(0.2126f, 0.7152f, 0.0722f)); }

// The side of the per-pixel baseline's jittered grid of `count` rays; 0 unless `count` is an even square.
uint32_t gridSide(uint32_t count) {
  const uint32_t side = uint32_t(std::lround(std::sqrt(double(count))));
  return side * side == count && side % 2 == 0 ? side : 0u;
}

}  // namespace

void checkPixelTraceRayCounts(const std::vector<uint32_t>& raysPerPixel) {
  for (const uint32_t count : raysPerPixel)
    if (gridSide(count) == 0)
      throw std::runtime_error("--pixel-rays " + std::to_string(count) +
                               ": rays per pixel must be even squares (4, 16, 36, 64, …: a jittered grid in two "
                               "checkerboard halves)");
}

TraceBenchmarkResult benchmarkVoxelTrace(gpu::OwnedDevice& device, const Context& context,
                                         const renderer::Camera& camera, const renderer::FloatImage& viewDistance,
                                         const renderer::FloatImage& normal, uint32_t rayCount, uint32_t repetitions,
                                         float maxDistance) {
  const SurfaceRays surface(camera, viewDistance, normal, 0.3f);  // out of the surface's voxel at any tier's size
  std::mt19937 random(1234);  // fixed: every run traces the same rays
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<shader::VoxelTraceRay> rays(rayCount);
  for (auto& ray : rays) {
    const uint32_t pixel = surface.surfacePixels()[random() % surface.surfacePixels().size()];
    const float u = uniform(random);
    ray = surface.ray(pixel, {u, uniform(random)}, maxDistance);
  }

  TraceBenchmarkResult result;
  result.rays = rayCount;
  std::vector<shader::VoxelTraceHit> hits[2];
  for (const gi::TraceMethod method : {gi::TraceMethod::Hierarchical, gi::TraceMethod::Flat}) {
    TimedTrace traced = traceTimed(device, context, method, rays, repetitions);
    TraceMethodResult& measured = method == gi::TraceMethod::Hierarchical ? result.hierarchical : result.flat;
    measured.milliseconds = traced.milliseconds;
    measured.raysPerSecond = double(rayCount) / (measured.milliseconds * 1e-3);
    double reads = 0.0, hitCount = 0.0;
    for (const auto& hit : traced.hits) {
      reads += hit.reads;
      hitCount += hit.brick != shader::kInvalidBrick;
    }
    measured.readsPerRay = reads / rayCount;
    measured.hitFraction = hitCount / rayCount;
    hits[method == gi::TraceMethod::Hierarchical ? 0 : 1] = std::move(traced.hits);
  }
  uint32_t identical = 0;
  for (uint32_t i = 0; i < rayCount; ++i)
    identical += hits[0][i].brick == hits[1][i].brick && hits[0][i].voxelBit == hits[1][i].voxelBit;
  result.identicalHits = double(identical) / rayCount;
  return result;
}

PixelTraceBaselineResult benchmarkPixelTrace(gpu::OwnedDevice& device, const Context& context,
                                             const renderer::Camera& camera, const renderer::FloatImage& viewDistance,
                                             const renderer::FloatImage& normal,
                                             const renderer::FloatImage& ssvgiIrradiance,
                                             const shader::Sh2Rgb& skyRadiance, uint32_t pixelStride,
                                             const std::vector<uint32_t>& raysPerPixel, uint32_t repetitions,
                                             float maxDistance) {
  // Out of the surface's own voxel, wherever in it the surface lies, as little as that: near geometry counts here.
  const float voxelSize = gi::voxelSceneOf(context).current().voxelSize;
  checkPixelTraceRayCounts(raysPerPixel);
  const SurfaceRays surface(camera, viewDistance, normal, std::sqrt(3.0f) * voxelSize);
  std::vector<uint32_t> traced;
  for (const uint32_t pixel : surface.surfacePixels())
    if ((pixel % viewDistance.width) % pixelStride == 0 && (pixel / viewDistance.width) % pixelStride == 0)
      traced.push_back(pixel);
  if (traced.empty()) throw std::runtime_error("--pixel-stride leaves no surface pixel to trace");

  PixelTraceBaselineResult result;
  result.tracedPixels = uint32_t(traced.size());
  result.surfacePixels = uint32_t(surface.surfacePixels().size());
  std::mt19937 random(1234);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (const uint32_t count : raysPerPixel) {
    const uint32_t side = gridSide(count);
    // Per pixel, one ray in each cell of a jittered side × side grid of the unit square: the grid's two checkerboard
    // halves are then independent estimates of the same hemisphere, which measures the estimate's own noise.
    std::vector<shader::VoxelTraceRay> rays;
    rays.reserve(size_t(traced.size()) * count);
    for (const uint32_t pixel : traced)
      for (uint32_t cell = 0; cell < count; ++cell) {
        const float x = (float(cell % side) + uniform(random)) / float(side);
        const float y = (float(cell / side) + uniform(random)) / float(side);
        rays.push_back(surface.ray(pixel, {x, y}, maxDistance));
      }
    const TimedTrace timed = traceTimed(device, context, gi::TraceMethod::Hierarchical, rays, repetitions);

    double differenceSum = 0.0, noiseSum = 0.0, ssvgiSum = 0.0, estimateSum = 0.0;
    for (size_t p = 0; p < traced.size(); ++p) {
      glm::vec3 halves[2]{glm::vec3(0.0f), glm::vec3(0.0f)};
      for (uint32_t cell = 0; cell < count; ++cell) {
        const shader::VoxelTraceHit& hit = timed.hits[p * count + cell];
        const glm::vec3 direction(rays[p * count + cell].direction);
        const glm::vec4 basis = shader::sh2Basis(direction);
        const glm::vec3 radiance =
            hit.brick != shader::kInvalidBrick
                ? hit.radiance
                : glm::max(glm::vec3(glm::dot(skyRadiance.r, basis), glm::dot(skyRadiance.g, basis),
                                     glm::dot(skyRadiance.b, basis)),
                           glm::vec3(0.0f));
        halves[(cell % side + cell / side) % 2] += radiance;
      }
      // Cosine-weighted sampling: E = π/K·Σ L, and each half of the checkerboard has K/2 rays.
      const float halfWeight = glm::pi<float>() / (0.5f * float(count));
      const float a = luminance(halves[0]) * halfWeight, b = luminance(halves[1]) * halfWeight;
      const float estimate = 0.5f * (a + b);
      const uint32_t pixel = traced[p];
      const float ssvgi = luminance({ssvgiIrradiance.pixels[pixel * 3], ssvgiIrradiance.pixels[pixel * 3 + 1],
                                     ssvgiIrradiance.pixels[pixel * 3 + 2]});
      differenceSum += std::abs(estimate - ssvgi);
      noiseSum += 0.5 * std::abs(a - b);
      ssvgiSum += ssvgi;
      estimateSum += estimate;
    }
    PixelTraceResult measured;
    measured.raysPerPixel = count;
    measured.milliseconds = timed.milliseconds;
    measured.fullFrameMilliseconds = timed.milliseconds * double(result.surfacePixels) / double(result.tracedPixels);
    measured.differenceFromSsvgi = ssvgiSum > 0.0 ? differenceSum / ssvgiSum : 0.0;
    measured.noise = estimateSum > 0.0 ? noiseSum / estimateSum : 0.0;
    result.results.push_back(measured);
  }
  return result;
}

}  // namespace ssvgi::bench
