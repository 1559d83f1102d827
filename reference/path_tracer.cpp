#include "path_tracer.h"

#include "gpu_host/transfers.h"
#include "renderer.h"
#include "ssvgi_reference_shaders.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace ssvgi::reference {

namespace {

gpu::Image storageImage(gpu::Device& device, const char* name, VkFormat format, const PathTracerSettings& settings) {
  return gpu::Image(device, {name, format, settings.width, settings.height, 1, 1, VK_IMAGE_USAGE_STORAGE_BIT});
}

glm::uvec3 pixels(const PathTracerSettings& settings) { return {settings.width, settings.height, 1}; }

}  // namespace

PathTracer::PathTracer(gpu::OwnedDevice& device, const renderer::Scene& scene, const renderer::AnimatedState& state,
                       const PathTracerSettings& settings)
    : device_(device),
      settings_(settings),
      descriptors_(device),
      profiler_(device),
      primaryHitsPipeline_(device, shaders::primary_hits_comp, sceneTracingConstants(scene)),
      pathTracePipeline_(device, shaders::path_trace_comp, sceneTracingConstants(scene)),
      tonemap_(device),
      scene_(device, scene, state, settings.width, settings.height, settings.exposure),
      pacer_(settings.secondsPerDispatch),
      rayOrigins_(storageImage(device, "reference ray origins", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      normals_(storageImage(device, "reference normal", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      albedos_(storageImage(device, "reference albedo", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      primaryRadiance_(storageImage(device, "reference primary radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      directIrradiance_(storageImage(device, "reference direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      viewDistances_(storageImage(device, "reference view distance", VK_FORMAT_R32_SFLOAT, settings)),
      indirectSums_(storageImage(device, "reference indirect sums", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      indirectIrradiance_(storageImage(device, "reference indirect irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      finalRadiance_(storageImage(device, "reference final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      tonemapped_(storageImage(device, "reference tonemapped", VK_FORMAT_R8G8B8A8_UNORM, settings)) {
  if (settings.width == 0 || settings.height == 0) throw gpu::GpuError("reference size must be at least 1×1");
  submit([&](gpu::CommandList& commands) {
    commands.clearImage(indirectSums_, VkClearColorValue{});
    commands.clearImage(indirectIrradiance_, VkClearColorValue{});
    commands.clearImage(finalRadiance_, VkClearColorValue{});
    commands.clearImage(tonemapped_, VkClearColorValue{});
    auto scope = commands.scope("reference: PrimaryHits");
    commands.dispatch(primaryHitsPipeline_,
                      primaryHitBindings()
                          .image(shader::kBindPrimaryDistance, viewDistances_),
                      pixels(settings_));
  });
}

gpu::Bindings PathTracer::primaryHitBindings() const {
  return scene_.bindings()
      .image(shader::kBindPrimaryRayOrigin, rayOrigins_)
      .image(shader::kBindPrimaryNormal, normals_)
      .image(shader::kBindPrimaryAlbedo, albedos_)
      .image(shader::kBindPrimaryRadiance, primaryRadiance_)
      .image(shader::kBindPrimaryDirect, directIrradiance_);
}

void PathTracer::submit(const std::function<void(gpu::CommandList&)>& record) {
  descriptors_.reset();
  device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList commands(device_, commandBuffer, descriptors_, &profiler_);
    profiler_.begin(commandBuffer);
    record(commands);
  });
  for (const gpu::PassTiming& timing : profiler_.resolve()) {
    auto total = std::find_if(timings_.begin(), timings_.end(),
                              [&](const gpu::PassTiming& pass) { return pass.name == timing.name; });
    if (total == timings_.end()) {
      timings_.push_back(timing);
    } else {
      total->milliseconds += timing.milliseconds;
    }
  }
}

void PathTracer::trace(uint32_t samples, const std::function<void(uint32_t samplesPerPixel)>& progress) {
  if (samples == 0) throw gpu::GpuError("the path tracer needs at least one sample per pixel");
  const uint32_t target = samplesPerPixel_ + samples;
  while (samplesPerPixel_ < target) {
    const shader::PathTracePush push{.firstSample = samplesPerPixel_,
                                     .sampleCount = pacer_.nextUnits(target - samplesPerPixel_),
                                     .seed = settings_.seed,
                                     .maxBounces = settings_.maxBounces,
                                     .emitterCount = settings_.sampleEmitters ? scene_.emitterCount() : 0u,
                                     .emittedPower = scene_.emittedPower()};
    const auto start = std::chrono::steady_clock::now();
    submit([&](gpu::CommandList& commands) {
      {
        auto scope = commands.scope("reference: PathTrace");
        commands.dispatch(pathTracePipeline_,
                          primaryHitBindings()
                              .image(shader::kBindTraceIndirectSum, indirectSums_)
                              .image(shader::kBindTraceIndirect, indirectIrradiance_)
                              .image(shader::kBindTraceFinal, finalRadiance_),
                          pixels(settings_), push);
      }
      tonemap_.record(commands, scene_.frameConstants(), finalRadiance_, tonemapped_);
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    samplesPerPixel_ += push.sampleCount;
    pacer_.measured(push.sampleCount, seconds);
    if (progress) progress(samplesPerPixel_);
  }
}

renderer::FloatImage PathTracer::finalRadiance() { return renderer::readFloatImage(device_, finalRadiance_, 3); }
renderer::FloatImage PathTracer::directIrradiance() { return renderer::readFloatImage(device_, directIrradiance_, 3); }
renderer::FloatImage PathTracer::indirectIrradiance() {
  return renderer::readFloatImage(device_, indirectIrradiance_, 3);
}
renderer::FloatImage PathTracer::albedo() { return renderer::readFloatImage(device_, albedos_, 3); }
renderer::FloatImage PathTracer::normal() { return renderer::readFloatImage(device_, normals_, 3); }
renderer::FloatImage PathTracer::viewDistance() { return renderer::readFloatImage(device_, viewDistances_, 1); }

std::vector<uint8_t> PathTracer::tonemapped() {
  const auto bytes = gpu::readImage(device_, tonemapped_);
  std::vector<uint8_t> rgba(bytes.size());
  std::memcpy(rgba.data(), bytes.data(), bytes.size());
  return rgba;
}

}  // namespace ssvgi::reference
