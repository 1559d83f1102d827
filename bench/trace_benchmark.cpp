#include "trace_benchmark.h"

#include "camera.h"
#include "gi/context_internals.h"
#include "gi/voxels/trace_rays.h"
#include "gpu/command_list.h"
#include "gpu/profiler.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <random>
#include <stdexcept>

namespace ssvgi::bench {

namespace {

std::vector<shader::VoxelTraceRay> surfaceRays(const renderer::Camera& camera, const renderer::FloatImage& viewDistance,
                                               const renderer::FloatImage& normal, uint32_t rayCount,
                                               float maxDistance) {
  const uint32_t width = viewDistance.width, height = viewDistance.height;
  const glm::mat4 inverse = glm::inverse(
      renderer::reversedZInfiniteProjection(camera.verticalFov, float(width) / float(height), camera.nearPlane) *
      renderer::viewMatrix(camera));
  std::vector<uint32_t> surfacePixels;
  for (uint32_t i = 0; i < width * height; ++i)
    if (viewDistance.pixels[i] > 0.0f) surfacePixels.push_back(i);
  if (surfacePixels.empty()) throw std::runtime_error("the benchmark view shows no surface to trace from");

  std::mt19937 random(1234);  // fixed: every run traces the same rays
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<shader::VoxelTraceRay> rays(rayCount);
  for (auto& ray : rays) {
    const uint32_t pixel = surfacePixels[random() % surfacePixels.size()];
    const glm::vec2 ndc((float(pixel % width) + 0.5f) / float(width) * 2.0f - 1.0f,
                        1.0f - (float(pixel / width) + 0.5f) / float(height) * 2.0f);
    const glm::vec4 onPlane = inverse * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 view = glm::normalize(glm::vec3(onPlane) / onPlane.w - camera.position);
    const glm::vec3 n = glm::normalize(glm::vec3(normal.pixels[pixel * 3], normal.pixels[pixel * 3 + 1],
                                                 normal.pixels[pixel * 3 + 2]));
    // Cosine-distributed around the normal (Malley's method), leaving the surface's own voxel.
    const float r = std::sqrt(uniform(random)), phi = glm::two_pi<float>() * uniform(random);
    const glm::vec3 tangent = glm::normalize(glm::cross(std::abs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0), n));
    const glm::vec3 bitangent = glm::cross(n, tangent);
    const glm::vec3 direction = glm::normalize(tangent * (r * std::cos(phi)) + bitangent * (r * std::sin(phi)) +
                                               n * std::sqrt(std::max(0.0f, 1.0f - r * r)));
    const glm::vec3 origin = camera.position + view * viewDistance.pixels[pixel] + n * 0.3f;
    ray.originAndMaxDistance = glm::vec4(origin, maxDistance);
    ray.direction = glm::vec4(direction, 0.0f);
  }
  return rays;
}

}  // namespace

TraceBenchmarkResult benchmarkVoxelTrace(gpu::Device& device, const Context& context, const renderer::Camera& camera,
                                         const renderer::FloatImage& viewDistance, const renderer::FloatImage& normal,
                                         uint32_t rayCount, uint32_t repetitions, float maxDistance) {
  const gi::VoxelScene& scene = gi::voxelSceneOf(context);
  const auto rays = surfaceRays(camera, viewDistance, normal, rayCount, maxDistance);
  gpu::Buffer rayBuffer(device, "benchmark rays", rays.size() * sizeof(shader::VoxelTraceRay),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device, rayBuffer, std::as_bytes(std::span(rays)));
  gpu::Buffer hitBuffer(device, "benchmark hits", rays.size() * sizeof(shader::VoxelTraceHit),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::DescriptorArena descriptors(device);
  gpu::Profiler profiler(device);
  if (!profiler.supported()) throw std::runtime_error("the device has no timestamps: cannot time the traces");

  TraceBenchmarkResult result;
  result.rays = rayCount;
  std::vector<shader::VoxelTraceHit> hits[2];
  for (const gi::TraceMethod method : {gi::TraceMethod::Hierarchical, gi::TraceMethod::Flat}) {
    gi::TraceRays trace(device, method);
    TraceMethodResult& measured = method == gi::TraceMethod::Hierarchical ? result.hierarchical : result.flat;
    std::vector<double> times;
    for (uint32_t repetition = 0; repetition < repetitions; ++repetition) {
      descriptors.reset();
      device.submitAndWait([&](VkCommandBuffer commandBuffer) {
        gpu::CommandList commands(device, commandBuffer, descriptors, &profiler);
        profiler.begin(commandBuffer);
        trace.record(commands, scene, rayBuffer, hitBuffer, rayCount);
      });
      for (const auto& timing : profiler.resolve()) times.push_back(timing.milliseconds);
    }
    // The median: lavapipe's timestamps are taken on its CPU threads and an occasional one is meaningless.
    std::sort(times.begin(), times.end());
    measured.milliseconds = times[times.size() / 2];
    measured.raysPerSecond = double(rayCount) / (measured.milliseconds * 1e-3);
    auto& methodHits = hits[method == gi::TraceMethod::Hierarchical ? 0 : 1];
    methodHits = gpu::readBufferAs<shader::VoxelTraceHit>(device, hitBuffer);
    double reads = 0.0, hitCount = 0.0;
    for (const auto& hit : methodHits) {
      reads += hit.voxel.z;
      hitCount += hit.voxel.x != shader::kInvalidBrick;
    }
    measured.readsPerRay = reads / rayCount;
    measured.hitFraction = hitCount / rayCount;
  }
  uint32_t identical = 0;
  for (uint32_t i = 0; i < rayCount; ++i)
    identical += hits[0][i].voxel.x == hits[1][i].voxel.x && hits[0][i].voxel.y == hits[1][i].voxel.y;
  result.identicalHits = double(identical) / rayCount;
  return result;
}

}  // namespace ssvgi::bench
