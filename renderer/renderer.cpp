#include "renderer.h"

#include "camera.h"
#include "gpu_host/transfers.h"
#include "sky.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cstring>

namespace ssvgi::renderer {

namespace {

VkSamplerCreateInfo pointSamplerInfo() {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = VK_FILTER_NEAREST;
  info.minFilter = VK_FILTER_NEAREST;
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
  gpuLight.cosInnerCone = std::cos(light.innerConeAngle);
  gpuLight.cosOuterCone = std::cos(light.outerConeAngle);
  return gpuLight;
}

shader::FrameConstants makeFrameConstants(const Scene& scene, const AnimatedState& state, uint32_t width,
                                          uint32_t height, float exposure) {
  shader::FrameConstants frame{};
  setFrameView(frame, state.camera, width, height);
  frame.sunDirectionAndEnabled = glm::vec4(glm::normalize(state.sun.direction), state.sun.enabled ? 1.0f : 0.0f);
  frame.sunIlluminance = state.sun.illuminance;
  frame.localLightCount = uint32_t(scene.lights.size());
  frame.exposure = exposure;
  frame.sky = makeSkyParameters(scene.sky, state.sun);
  return frame;
}

Renderer::Renderer(gpu::OwnedDevice& device, const Scene& scene, const RendererSettings& settings)
    : device_(device),
      scene_(scene),
      settings_(settings),
      bounds_(worldBounds(scene)),
      gpuScene_(device, scene),
      pointSampler_(device, pointSamplerInfo(), "point sampler"),
      descriptors_(device),
      profiler_(device),
      shadows_(device, settings.shadows),
      gbufferPass_(device),
      directLighting_(device),
      composite_(device),
      tonemap_(device),
      gbuffers_{GBuffer(device, settings.width, settings.height), GBuffer(device, settings.width, settings.height)},
      frameConstants_(device, "frame constants", sizeof(shader::FrameConstants), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      gpu::MemoryUsage::HostUpload),
      compositeFallback_(device, "composite fallback", sizeof(shader::CompositeFallback),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload),
      lights_(device, "local lights", std::max<size_t>(1, scene.lights.size()) * sizeof(shader::GpuLight),
              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload),
      directIrradiance_(storageImage(device, "direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height)),
      viewDistance_(storageImage(device, "view distance", VK_FORMAT_R32_SFLOAT, settings.width, settings.height)),
      indirectIrradiance_(storageImage(device, "indirect irradiance", VK_FORMAT_R16G16B16A16_SFLOAT,
                                       (settings.width + 1) / 2, (settings.height + 1) / 2)),
      indirectUsed_(storageImage(device, "indirect irradiance used", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height)),
      finalRadiance_{storageImage(device, "final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height),
                     storageImage(device, "final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings.width, settings.height)},
      directRadiance_{storageImage(device, "direct radiance", VK_FORMAT_R16G16B16A16_SFLOAT, settings.width, settings.height),
                      storageImage(device, "direct radiance", VK_FORMAT_R16G16B16A16_SFLOAT, settings.width, settings.height)},
      tonemapped_(storageImage(device, "tonemapped", VK_FORMAT_R8G8B8A8_UNORM, settings.width, settings.height)) {
  if (settings.width == 0 || settings.height == 0) throw gpu::GpuError("render size must be at least 1×1");
  setShownLight(settings.shownLight);
  if (settings.gi) {
    ssvgi::ContextDesc desc;
    desc.instance = device.instance();
    desc.physicalDevice = device.physicalDevice();
    desc.device = device.device();
    desc.debugUtilsEnabled = true;
    desc.settings = *settings.gi;
    desc.maxWidth = settings.width;
    desc.maxHeight = settings.height;
    desc.framesInFlight = 1;  // the renderer waits for every frame
    desc.memoryBudgetBytes = settings.giMemoryBudgetBytes;
    extraViews_.emplace(device, scene, settings.extraViews, *settings.gi, bounds_);
    if (settings.extraViews.skyMap) skyMap_.emplace(device);
    desc.maxExtraViewSize = extraViews_->maxViewSize();
    auto context = ssvgi::Context::create(desc);
    if (!context.ok()) throw gpu::GpuError("ssvgi: " + context.error().message);
    gi_ = std::move(context.value());
    // The views cover the voxel volume: the one the memory budget left, if it shrank it (their sizes stay).
    if (gi_->settings().volumeBricks != settings.gi->volumeBricks)
      extraViews_.emplace(device, scene, settings.extraViews, gi_->settings(), bounds_);
  }
}

void Renderer::setShownLight(ShownLight shown) {
  if (shown != ShownLight::All && !settings_.litFrameDirectOnly)
    throw gpu::GpuError("showing part of the light needs the direct lit frame (--lit-frame direct): with the final "
                        "radiance as ssvgi's lit frame, ssvgi would be given the part shown");
  settings_.shownLight = shown;
}

namespace {
ssvgi::View toView(const glm::mat4& viewProjection, glm::vec3 position, uint32_t width, uint32_t height) {
  ssvgi::View view;
  std::memcpy(view.viewProjection.data(), &viewProjection[0][0], sizeof(float) * 16);
  view.position = {position.x, position.y, position.z};
  view.width = width;
  view.height = height;
  return view;
}
}  // namespace

void Renderer::recordGi(gpu::CommandList& commands, const shader::FrameConstants& frame,
                        const shader::Sh2Rgb& skyRadiance) {
  // ssvgi samples the host's images: they must be shader-readable, their writes visible, before it records.
  const GBuffer& gbuffer = currentGBuffer();
  const uint32_t litSet = (frameIndex_ + 1) & 1u;
  const GBuffer& litGBuffer = gbuffers_[litSet];
  const gpu::Image& litColor = settings_.litFrameDirectOnly ? directRadiance_[litSet] : finalRadiance_[litSet];
  const bool hasLitFrame = frameIndex_ > 0;
  commands.use(gbuffer.depth, gpu::Usage::ComputeSampled);
  commands.use(gbuffer.normal, gpu::Usage::ComputeSampled);
  if (hasLitFrame) {
    commands.use(litColor, gpu::Usage::ComputeSampled);
    commands.use(litGBuffer.depth, gpu::Usage::ComputeSampled);
    commands.use(litGBuffer.normal, gpu::Usage::ComputeSampled);
    if (settings_.litFrameDirectOnly) commands.use(litGBuffer.albedo, gpu::Usage::ComputeSampled);
  }
  commands.flushBarriers();

  ssvgi::FrameDesc desc;
  desc.frameIndex = frameIndex_;
  desc.camera = toView(frame.viewProjection, glm::vec3(frame.cameraPosition), settings_.width, settings_.height);
  desc.depth.view = gbuffer.depth.view();
  desc.normal.view = gbuffer.normal.view();
  desc.hasLitFrame = hasLitFrame;
  desc.litCamera = giView_;
  desc.litColor.view = litColor.view();
  desc.litDepth.view = litGBuffer.depth.view();
  desc.litNormal.view = litGBuffer.normal.view();
  if (settings_.litFrameDirectOnly) desc.litAlbedo.view = litGBuffer.albedo.view();
  // What probe rays that leave the voxel volume see (the map), and the sky the gather reads their openings with.
  std::memcpy(desc.skyRadianceSh.data(), &skyRadiance, sizeof(skyRadiance));
  if (skyMap_) desc.skyRadianceMap.view = skyMap_->image().view();
  desc.extraViews = lastExtraViews_;
  desc.countWork = settings_.countGiWork;
  if (const ssvgi::Error error = gi_->dispatch(desc, commands.handle())) throw gpu::GpuError("ssvgi: " + error.message);
  giView_ = desc.camera;
}

void Renderer::writeCompositeFallback(const std::optional<ssvgi::WorldBox>& voxelVolume,
                                      const shader::Sh2Rgb& skyRadiance) {
  shader::CompositeFallback fallback{};
  if (voxelVolume) {
    fallback.knownVolumeMinimum = glm::vec3(voxelVolume->min[0], voxelVolume->min[1], voxelVolume->min[2]);
    fallback.knownVolumeMaximum = glm::vec3(voxelVolume->max[0], voxelVolume->max[1], voxelVolume->max[2]);
    fallback.blendsToFallback = 1u;
    fallback.skyRadiance = skyRadiance;
  }
  std::memcpy(compositeFallback_.mapped(), &fallback, sizeof(fallback));
}

void Renderer::render(const AnimatedState& state) {
  const bool firstFrame = frameIndex_ == 0;
  descriptors_.reset();
  gpuScene_.updateInstances(scene_, state);

  shader::FrameConstants frame = makeFrameConstants(scene_, state, settings_.width, settings_.height, settings_.exposure);
  if (!firstFrame) frame.previousViewProjection = previousViewProjection_;
  const bool giLighting = gi_ && settings_.giLighting;
  if (giLighting) frame.addsIndirectLight = 1u;  // the composite adds ssvgi's indirect irradiance
  frame.shownLight = uint32_t(settings_.shownLight);

  std::vector<shader::GpuLight> lights;
  for (const LocalLight& light : scene_.lights) lights.push_back(toGpuLight(light));
  shadows_.prepare(scene_, bounds_, state.sun, frame, lights);
  std::memcpy(frameConstants_.mapped(), &frame, sizeof(frame));
  if (!lights.empty()) std::memcpy(lights_.mapped(), lights.data(), lights.size() * sizeof(shader::GpuLight));

  device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::HostCommandList commands(device_, commandBuffer, descriptors_, &profiler_);
    profiler_.begin(commandBuffer);
    if (firstFrame) commands.clearImage(indirectIrradiance_, VkClearColorValue{});
    const GBuffer& gbuffer = currentGBuffer();
    const gpu::Image& finalRadiance = finalRadiance_[frameIndex_ & 1u];
    shadows_.record(commands, gpuScene_);
    gbufferPass_.record(commands, gpuScene_, frameConstants_, gbuffer);
    directLighting_.record(commands, frameConstants_, lights_, shadows_, gbuffer, pointSampler_.handle(),
                           directIrradiance_, viewDistance_);
    std::optional<ssvgi::WorldBox> voxelVolume;  // none without the GI's light: no fallback either
    shader::Sh2Rgb skyRadiance{};
    if (gi_) {
      lastExtraViews_ = extraViews_->record(commands, frame, gpuScene_, lights_, shadows_, pointSampler_.handle());
      if (skyMap_) skyMap_->record(commands, frameConstants_);
      skyRadiance = projectSkyToSh2(frame.sky);
      recordGi(commands, frame, skyRadiance);
      if (giLighting) voxelVolume = gi_->voxelVolume();
    }
    writeCompositeFallback(voxelVolume, skyRadiance);
    // Without the GI's light the composite binds the black image for both, and reads neither.
    VkImageView indirect = indirectIrradiance_.view(), confidence = indirectIrradiance_.view();
    if (giLighting) {
      indirect = gi_->output().view;  // left by dispatch() ready for compute reads (ssvgi::OutputImage)
      confidence = gi_->confidence().view;
    } else {
      commands.use(indirectIrradiance_, gpu::Usage::ComputeSampled);
    }
    composite_.record(commands, frameConstants_, compositeFallback_, gbuffer, pointSampler_.handle(),
                      directIrradiance_, indirect, confidence, finalRadiance, indirectUsed_,
                      directRadiance_[frameIndex_ & 1u]);
    tonemap_.record(commands, frameConstants_, finalRadiance, tonemapped_);
  });
  timings_ = profiler_.resolve();
  if (gi_)
    for (const ssvgi::PassTime& pass : gi_->stats().passes) timings_.push_back({pass.name, pass.milliseconds});
  previousViewProjection_ = frame.viewProjection;
  ++frameIndex_;
}

std::optional<ssvgi::Stats> Renderer::giStats() {
  if (!gi_) return std::nullopt;
  return gi_->stats();
}

Renderer::DebugImage Renderer::giDebugView(ssvgi::DebugView view, const std::optional<Camera>& camera) {
  drawGiDebugView(view, camera);
  return {readFloatImage(device_, debugRadiance_, 3), tonemapped()};
}

void Renderer::drawGiDebugView(ssvgi::DebugView view, const std::optional<Camera>& camera) {
  if (!gi_) throw gpu::GpuError("debug views need the GI library to run");
  if (!debugRadiance_)
    debugRadiance_ = storageImage(device_, "ssvgi debug view", VK_FORMAT_R32G32B32A32_SFLOAT, settings_.width,
                                  settings_.height);
  device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList commands(device_, commandBuffer, descriptors_);
    ssvgi::View debugCamera = giView_;
    if (camera) {
      shader::FrameConstants frame{};
      setFrameView(frame, *camera, settings_.width, settings_.height);
      debugCamera = toView(frame.viewProjection, camera->position, settings_.width, settings_.height);
    }
    if (const ssvgi::Error error = gi_->debugView(view, debugCamera, debugRadiance_.handle(), debugRadiance_.view(),
                                                  commandBuffer))
      throw gpu::GpuError("ssvgi: " + error.message);
    // ssvgi left the image in GENERAL, written by a compute shader: tell the tracker before the tonemap reads it.
    debugRadiance_.state() = {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, 0, 0,
                              VK_IMAGE_LAYOUT_GENERAL};
    tonemap_.record(commands, frameConstants_, debugRadiance_, tonemapped_);
  });
}

ssvgi::Settings giSettingsFor(ssvgi::QualityTier tier, const Scene& scene) {
  ssvgi::Settings settings = ssvgi::settingsForTier(tier);
  settings.voxelSize *= scene.giDetailScale;
  settings.probeSpacing *= scene.giDetailScale;
  settings.skyOnlyThroughObservedSpace = true;
  return settings;
}

FloatImage readFloatImage(gpu::OwnedDevice& device, const gpu::Image& image, uint32_t channels) {
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

// Read after render(): the last frame is frameIndex_ - 1.
FloatImage Renderer::finalRadiance() { return readFloatImage(device_, finalRadiance_[(frameIndex_ + 1) & 1u], 3); }
FloatImage Renderer::directIrradiance() { return readFloatImage(device_, directIrradiance_, 3); }
FloatImage Renderer::indirectIrradiance() { return readFloatImage(device_, indirectUsed_, 3); }
FloatImage Renderer::skyMap() {
  if (!skyMap_) throw gpu::GpuError("the renderer gives ssvgi no sky map (GI off, or ExtraViewSettings::skyMap off)");
  return readFloatImage(device_, skyMap_->image(), 3);
}
FloatImage Renderer::confidence() {
  const FloatImage used = readFloatImage(device_, indirectUsed_, 4);
  FloatImage result{used.width, used.height, 1, std::vector<float>(size_t(used.width) * used.height)};
  for (size_t i = 0; i < result.pixels.size(); ++i) result.pixels[i] = used.pixels[i * 4 + 3];
  return result;
}
FloatImage Renderer::albedo() { return readFloatImage(device_, gbuffers_[(frameIndex_ + 1) & 1u].albedo, 3); }
FloatImage Renderer::normal() { return readFloatImage(device_, gbuffers_[(frameIndex_ + 1) & 1u].normal, 3); }
FloatImage Renderer::viewDistance() { return readFloatImage(device_, viewDistance_, 1); }
FloatImage Renderer::depthBuffer() { return readFloatImage(device_, gbuffers_[(frameIndex_ + 1) & 1u].depth, 1); }

std::vector<uint8_t> Renderer::tonemapped() {
  const auto bytes = gpu::readImage(device_, tonemapped_);
  std::vector<uint8_t> rgba(bytes.size());
  std::memcpy(rgba.data(), bytes.data(), bytes.size());
  return rgba;
}

}  // namespace ssvgi::renderer
