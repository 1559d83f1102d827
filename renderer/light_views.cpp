#include "light_views.h"

#include "camera.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cstring>

namespace ssvgi::renderer {

namespace {

constexpr float kNearPlane = 0.02f;          // metres: the views start this close to the light
constexpr float kMaxSpotFov = 2.0943951f;    // 120°: a wider spot cone is seen through its central part

gpu::Image storageImage(gpu::Device& device, const char* name, VkFormat format, uint32_t size) {
  return gpu::Image(device, {name, format, size, size, 1, 1, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT});
}

// The cameras a light sees its surroundings through: the six faces of a cube around a point light, the cone of a
// spot light.
std::vector<Camera> lightCameras(const LocalLight& light) {
  Camera camera;
  camera.position = light.position;
  camera.nearPlane = kNearPlane;
  if (light.type == LightType::Spot) {
    camera.verticalFov = std::min(2.0f * light.outerConeAngle, kMaxSpotFov);
    camera.target = light.position + light.direction;
    camera.up = std::abs(light.direction.y) > 0.99f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    return {camera};
  }
  camera.verticalFov = glm::half_pi<float>();
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Camera> faces;
  for (const glm::vec3& axis : axes) {
    camera.target = light.position + axis;
    camera.up = axis.y != 0.0f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    faces.push_back(camera);
  }
  return faces;
}

ssvgi::View toView(const shader::FrameConstants& frame, uint32_t size) {
  ssvgi::View view;
  std::memcpy(view.viewProjection.data(), &frame.viewProjection[0][0], sizeof(float) * 16);
  view.position = {frame.cameraPositionAndNear.x, frame.cameraPositionAndNear.y, frame.cameraPositionAndNear.z};
  view.width = view.height = size;
  return view;
}

}  // namespace

LightViews::Slot::Slot(gpu::Device& device, uint32_t size)
    : frameConstants(device, "light view constants", sizeof(shader::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                     gpu::MemoryUsage::HostUpload),
      gbuffer(device, size, size),
      radiance(storageImage(device, "light view radiance", VK_FORMAT_R32G32B32A32_SFLOAT, size)) {}

LightViews::LightViews(gpu::Device& device, const Scene& scene, uint32_t size)
    : size_(size),
      gbufferPass_(device),
      directLighting_(device),
      composite_(device),
      directIrradiance_(storageImage(device, "light view direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, size)),
      viewDistance_(storageImage(device, "light view distance", VK_FORMAT_R32_SFLOAT, size)),
      noIndirect_(storageImage(device, "light view no indirect", VK_FORMAT_R16G16B16A16_SFLOAT, 1)),
      indirectUsed_(storageImage(device, "light view indirect used", VK_FORMAT_R32G32B32A32_SFLOAT, size)) {
  for (const LocalLight& light : scene.lights)
    for (const Camera& camera : lightCameras(light)) cameras_.push_back(camera);
  const size_t slots = std::min<size_t>(cameras_.size(), ssvgi::kMaxExtraViews);
  slots_.reserve(slots);
  for (size_t i = 0; i < slots; ++i) slots_.emplace_back(device, size);
}

std::vector<ssvgi::ExtraView> LightViews::record(gpu::CommandList& commands, uint32_t frameIndex,
                                                 const shader::FrameConstants& frame, const GpuScene& scene,
                                                 const gpu::Buffer& lights, const ShadowPass& shadows,
                                                 VkSampler pointSampler) {
  auto scope = commands.scope("renderer: LightViews");
  if (frameIndex == 0) commands.clearImage(noIndirect_, VkClearColorValue{});
  commands.use(noIndirect_, gpu::Usage::ComputeSampled);
  std::vector<ssvgi::ExtraView> views;
  const size_t first = size_t(frameIndex) * slots_.size();
  for (size_t i = 0; i < slots_.size(); ++i) {
    Slot& slot = slots_[i];
    shader::FrameConstants viewFrame = frame;
    setFrameView(viewFrame, cameras_[(first + i) % cameras_.size()], size_, size_);
    viewFrame.lightCountAndExposure.z = 0.0f;  // direct and emitted light only: ssvgi adds the rest
    std::memcpy(slot.frameConstants.mapped(), &viewFrame, sizeof(viewFrame));
    gbufferPass_.record(commands, scene, slot.frameConstants, slot.gbuffer);
    directLighting_.record(commands, slot.frameConstants, lights, shadows, slot.gbuffer, pointSampler,
                           directIrradiance_, viewDistance_);
    composite_.record(commands, slot.frameConstants, slot.gbuffer, pointSampler, directIrradiance_, noIndirect_.view(),
                      slot.radiance, indirectUsed_);
    for (const gpu::Image* image : {&slot.radiance, &slot.gbuffer.depth, &slot.gbuffer.normal, &slot.gbuffer.albedo})
      commands.use(*image, gpu::Usage::ComputeSampled);
    views.push_back({toView(viewFrame, size_), {slot.radiance.view()}, {slot.gbuffer.depth.view()},
                     {slot.gbuffer.normal.view()}, {slot.gbuffer.albedo.view()}});
  }
  return views;
}

}  // namespace ssvgi::renderer
