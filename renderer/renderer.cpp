#include "renderer.h"

#include "camera.h"
#include "sky.h"

#include <glm/gtc/packing.hpp>

#include <cstring>

namespace ssvgi::renderer {

namespace {

VkSamplerCreateInfo clampSampler(VkFilter filter) {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = filter;
  info.minFilter = filter;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  return info;
}

gpu::Image storageImage(gpu::Device& device, const char* name, VkFormat format, uint32_t width, uint32_t height) {
  return gpu::Image(device, {name, format, width, height, 1, 1, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT});
}

}  // namespace

shader::GpuLight toGpuLight(const LocalLight& light) {
  shader::GpuLight gpuLight{};
  const uint32_t type = light.type == LightType::Point ? shader::kLightPoint : shader::kLightSpot;
  gpuLight.positionAndType = glm::vec4(light.position, float(type));
  gpuLight.directionAndRange = glm::vec4(glm::normalize(light.direction), light.range);
  gpuLight.intensityAndShadow = glm::vec4(light.intensity, 0.0f);
  gpuLight.spotCosines = glm::vec4(std::cos(light.innerConeAngle), std::cos(light.outerConeAngle), 0.0f, 0.0f);
  return gpuLight;
}

shader::FrameConstants makeFrameConstants(const Scene& scene, const AnimatedState& state, uint32_t width,
                                          uint32_t height, float exposure) {
  const float aspect = float(width) / float(height);
  const glm::mat4 viewProjection =
      reversedZInfiniteProjection(state.camera.verticalFov, aspect, state.camera.nearPlane) * viewMatrix(state.camera);
  shader::FrameConstants frame{};
  frame.viewProjection = viewProjection;
  frame.inverseViewProjection = glm::inverse(viewProjection);
  frame.previousViewProjection = viewProjection;
  frame.cameraPositionAndNear = glm::vec4(state.camera.position, state.camera.nearPlane);
  frame.cameraForward = glm::vec4(glm::normalize(state.camera.target - state.camera.position), 0.0f);
  frame.viewportSize = glm::vec4(width, height, 1.0f / float(width), 1.0f / float(height));
  frame.sunDirectionAndEnabled = glm::vec4(glm::normalize(state.sun.direction), state.sun.enabled ? 1.0f : 0.0f);
  frame.sunIlluminance = glm::vec4(state.sun.illuminance, 0.0f);
  frame.lightCountAndExposure = glm::vec4(float(scene.lights.size()), exposure, 0.0f, 0.0f);
  frame.sky = makeSkyParameters(scene.sky, state.sun);
  return frame;
}

Renderer::Renderer(gpu::Device& device, const Scene& scene, const RendererSettings& settings)
    : device_(device),
      scene_(scene),
      settings_(settings),
      bounds_(worldBounds(scene)),
      gpuScene_(device, scene),
      pointSampler_(device, clampSampler(VK_FILTER_NEAREST), "point sampler"),
      linearSampler_(device, clampSampler(VK_FILTER_LINEAR), "linear sampler"),
      descriptors_(device),
      profiler_(device),
      shadows_(device, settings.shadows),
      gbufferPass_(device),
      directLighting_(device),
      composite_(device),
      tonemap_(device),
      gbuffer_(device, settings.width, settings.height),
      frameConstants_(device, "frame constants", sizeof(shader::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                      gpu::MemoryUsage::HostUpload),
      lights_(device, "local lights", std::max<size_t>(1, scene.lights.size()) * sizeof(shader::GpuLight),
              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload),
      directIrradiance_(storageImage(device, "direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height)),
      viewDistance_(storageImage(device, "view distance", VK_FORMAT_R32_SFLOAT, settings.width, settings.height)),
      indirectIrradiance_(storageImage(device, "indirect irradiance", VK_FORMAT_R16G16B16A16_SFLOAT,
                                       (settings.width + 1) / 2, (settings.height + 1) / 2)),
      indirectUsed_(storageImage(device, "indirect irradiance used", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height)),
      finalRadiance_(storageImage(device, "final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height)),
      tonemapped_(storageImage(device, "tonemapped", VK_FORMAT_R8G8B8A8_UNORM, settings.width, settings.height)) {
  if (settings.width == 0 || settings.height == 0) throw gpu::GpuError("render size must be at least 1×1");
}

void Renderer::render(const AnimatedState& state) {
  descriptors_.reset();
  gpuScene_.updateInstances(scene_, state);

  shader::FrameConstants frame = makeFrameConstants(scene_, state, settings_.width, settings_.height, settings_.exposure);
  if (!firstFrame_) frame.previousViewProjection = previousViewProjection_;

  std::vector<shader::GpuLight> lights;
  for (const LocalLight& light : scene_.lights) lights.push_back(toGpuLight(light));
  shadows_.prepare(scene_, bounds_, state.sun, frame, lights);
  std::memcpy(frameConstants_.mapped(), &frame, sizeof(frame));
  std::memcpy(lights_.mapped(), lights.data(), lights.size() * sizeof(shader::GpuLight));

  device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList commands(device_, commandBuffer, descriptors_, &profiler_);
    profiler_.begin(commandBuffer);
    if (firstFrame_) commands.clearImage(indirectIrradiance_, VkClearColorValue{});
    shadows_.record(commands, gpuScene_);
    gbufferPass_.record(commands, gpuScene_, frameConstants_, gbuffer_);
    directLighting_.record(commands, frameConstants_, lights_, shadows_, gbuffer_, pointSampler_.handle(),
                           directIrradiance_, viewDistance_);
    composite_.record(commands, frameConstants_, gbuffer_, pointSampler_.handle(), directIrradiance_,
                      indirectIrradiance_, linearSampler_.handle(), finalRadiance_, indirectUsed_);
    tonemap_.record(commands, frameConstants_, finalRadiance_, tonemapped_);
  });
  timings_ = profiler_.resolve();
  previousViewProjection_ = frame.viewProjection;
  firstFrame_ = false;
}

FloatImage readFloatImage(gpu::Device& device, const gpu::Image& image, uint32_t channels) {
  const auto bytes = gpu::readImage(device, image);
  const gpu::ImageDesc& desc = image.desc();
  const size_t texels = size_t(desc.width) * desc.height;
  FloatImage result{desc.width, desc.height, channels, std::vector<float>(texels * channels)};
  for (size_t i = 0; i < texels; ++i) {
    for (uint32_t c = 0; c < channels; ++c) {
      switch (desc.format) {
        case VK_FORMAT_R32G32B32A32_SFLOAT:
          std::memcpy(&result.pixels[i * channels + c], bytes.data() + (i * 4 + c) * sizeof(float), sizeof(float));
          break;
        case VK_FORMAT_R32_SFLOAT:
        case VK_FORMAT_D32_SFLOAT:
          std::memcpy(&result.pixels[i * channels + c], bytes.data() + i * sizeof(float), sizeof(float));
          break;
        case VK_FORMAT_R16G16B16A16_SFLOAT: {
          uint16_t half = 0;
          std::memcpy(&half, bytes.data() + (i * 4 + c) * sizeof(uint16_t), sizeof(uint16_t));
          result.pixels[i * channels + c] = glm::unpackHalf1x16(half);
          break;
        }
        default:
          throw gpu::GpuError("reading back '" + desc.name + "': unsupported format");
      }
    }
  }
  return result;
}

FloatImage Renderer::finalRadiance() { return readFloatImage(device_, finalRadiance_, 3); }
FloatImage Renderer::directIrradiance() { return readFloatImage(device_, directIrradiance_, 3); }
FloatImage Renderer::indirectIrradiance() { return readFloatImage(device_, indirectUsed_, 3); }
FloatImage Renderer::albedo() { return readFloatImage(device_, gbuffer_.albedo, 3); }
FloatImage Renderer::normal() { return readFloatImage(device_, gbuffer_.normal, 3); }
FloatImage Renderer::viewDistance() { return readFloatImage(device_, viewDistance_, 1); }
FloatImage Renderer::depthBuffer() { return readFloatImage(device_, gbuffer_.depth, 1); }

std::vector<uint8_t> Renderer::tonemapped() {
  const auto bytes = gpu::readImage(device_, tonemapped_);
  std::vector<uint8_t> rgba(bytes.size());
  std::memcpy(rgba.data(), bytes.data(), bytes.size());
  return rgba;
}

}  // namespace ssvgi::renderer
