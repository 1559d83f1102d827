#include "point_radiance.h"

#include "gpu_host/transfers.h"
#include "ssvgi_reference_shaders.h"

#include <chrono>

namespace ssvgi::reference {

namespace {

std::vector<glm::vec4> pointPositions(std::span<const glm::vec3> points) {
  if (points.empty()) throw gpu::GpuError("point radiance needs at least one point");
  std::vector<glm::vec4> positions;
  for (const glm::vec3& point : points) positions.emplace_back(point, 1.0f);
  return positions;
}

}  // namespace

PointRadianceTracer::PointRadianceTracer(gpu::OwnedDevice& device, const renderer::Scene& scene,
                                         const renderer::AnimatedState& state, std::span<const glm::vec3> points,
                                         const PointRadianceSettings& settings)
    : device_(device),
      settings_(settings),
      descriptors_(device),
      pipeline_(device, shaders::point_radiance_comp, sceneTracingConstants(scene)),
      // The view size only sets the camera's frame constants, which no ray from a point uses.
      scene_(device, scene, state, 1, 1, 1.0f),
      pacer_(settings.secondsPerDispatch),
      pointCount_(static_cast<uint32_t>(points.size())) {
  const std::vector<glm::vec4> positions = pointPositions(points);
  points_ = gpu::Buffer(device, "reference points", positions.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device, points_, std::as_bytes(std::span(positions)));
  sums_ = gpu::Buffer(device, "reference point radiance sums",
                      VkDeviceSize(pointCount_) * sizeof(shader::PointRadianceSums), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  device.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList commands(device, commandBuffer, descriptors_);
    commands.fillBuffer(sums_, 0);  // 0.0f
  });
}

void PointRadianceTracer::trace(uint32_t directions) {
  const uint32_t target =
      rounds_ + (directions + shader::kPointRadianceDirectionsPerRound - 1) / shader::kPointRadianceDirectionsPerRound;
  while (rounds_ < target) {
    const shader::PointRadiancePush push{.firstRound = rounds_,
                                         .roundCount = pacer_.nextUnits(target - rounds_),
                                         .seed = settings_.seed,
                                         .maxBounces = settings_.maxBounces,
                                         .emitterCount = settings_.sampleEmitters ? scene_.emitterCount() : 0u,
                                         .emittedPower = scene_.emittedPower()};
    const auto start = std::chrono::steady_clock::now();
    descriptors_.reset();
    device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
      gpu::CommandList commands(device_, commandBuffer, descriptors_);
      auto scope = commands.scope("reference: PointRadiance");
      commands.dispatch(pipeline_,
                        scene_.bindings()
                            .buffer(shader::kBindPointPositions, points_)
                            .buffer(shader::kBindPointRadianceSums, sums_),
                        {pointCount_ * shader::kPointRadianceLanes, 1, 1}, push);
    });
    rounds_ += push.roundCount;
    pacer_.measured(push.roundCount, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}

std::vector<shader::PointRadianceSums> PointRadianceTracer::measurements() {
  std::vector<shader::PointRadianceSums> points = gpu::readBufferAs<shader::PointRadianceSums>(device_, sums_);
  const float weight = rounds_ > 0 ? 4.0f * shader::kPi / float(directionsPerPoint()) : 0.0f;
  for (shader::PointRadianceSums& point : points) {
    point.radiance = shader::sh2Scale(point.radiance, weight);
    for (glm::vec4& irradiance : point.axisIrradiance) irradiance *= weight;
  }
  return points;
}

std::vector<shader::Sh2Rgb> PointRadianceTracer::radiance() {
  std::vector<shader::Sh2Rgb> radiance;
  for (const shader::PointRadianceSums& point : measurements()) radiance.push_back(point.radiance);
  return radiance;
}

}  // namespace ssvgi::reference
