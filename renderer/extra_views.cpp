#include "extra_views.h"

#include "camera.h"
#include "shared/sampling.h"
#include "shared/voxel_interface.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace ssvgi::renderer {

namespace {

constexpr float kNearPlane = 0.02f;        // metres: the perspective views start this close to their eye
constexpr float kMaxSpotFov = 2.0943951f;  // 120°: a wider spot cone is seen through its central part
constexpr float kSunViewDepthMargin = 1.0f;  // metres beyond the scene's bounds before and behind, as its shadow map

const std::array<glm::vec3, 6> kCubeFaces{glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0),
                                          glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)};

glm::vec3 upFor(glm::vec3 forward) {
  return std::abs(forward.y) > 0.99f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
}

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
    camera.up = upFor(light.direction);
    return {camera};
  }
  camera.verticalFov = glm::half_pi<float>();
  std::vector<Camera> faces;
  for (const glm::vec3& axis : kCubeFaces) {
    camera.target = light.position + axis;
    camera.up = upFor(axis);
    faces.push_back(camera);
  }
  return faces;
}

bool sunAboveHorizon(const shader::FrameConstants& frame) {
  return frame.sunDirectionAndEnabled.w > 0.0f && frame.sunDirectionAndEnabled.y > 0.0f;
}

ssvgi::View toView(const shader::FrameConstants& frame, uint32_t size) {
  ssvgi::View view;
  std::memcpy(view.viewProjection.data(), &frame.viewProjection[0][0], sizeof(float) * 16);
  view.position = {frame.cameraPosition.x, frame.cameraPosition.y, frame.cameraPosition.z};
  view.width = view.height = size;
  return view;
}

}  // namespace

ExtraViews::Target::Target(Kind viewKind, gpu::Device& device, uint32_t viewSize)
    : kind(viewKind),
      size(viewSize),
      frameConstants(device, "extra view constants", sizeof(shader::FrameConstants), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                     gpu::MemoryUsage::HostUpload),
      gbuffer(device, viewSize, viewSize),
      radiance(storageImage(device, "extra view radiance", VK_FORMAT_R16G16B16A16_SFLOAT,
                            viewKind == Kind::Overhead ? 1 : viewSize)) {}

ExtraViews::ExtraViews(gpu::Device& device, const Scene& scene, const ExtraViewSettings& settings,
                       const ssvgi::Settings& gi, const Bounds& sceneBounds)
    : settings_(settings),
      sceneEmits_(std::any_of(scene.materials.begin(), scene.materials.end(),
                              [](const Material& material) { return material.emission != glm::vec3(0.0f); })),
      voxelSize_(gi.voxelSize),
      volumeHalfExtent_(0.5f * float(shader::kBrickSizeVoxels) * gi.voxelSize *
                        glm::vec3(gi.volumeBricks[0], gi.volumeBricks[1], gi.volumeBricks[2])),
      sceneBounds_(sceneBounds),
      gbufferPass_(device),
      directLighting_(device),
      composite_(device),
      directIrradiance_(storageImage(device, "extra view direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, 1)),
      viewDistance_(storageImage(device, "extra view distance", VK_FORMAT_R32_SFLOAT, 1)),
      noIndirect_(storageImage(device, "extra view no indirect", VK_FORMAT_R16G16B16A16_SFLOAT, 1)),
      noFallback_(device, "extra view no fallback", sizeof(shader::CompositeFallback),
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload),
      indirectUsed_(storageImage(device, "extra view indirect used", VK_FORMAT_R32G32B32A32_SFLOAT, 1)),
      finalRadiance_(storageImage(device, "extra view final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, 1)) {
  if (settings.viewsPerFrame == 0 || settings.viewsPerFrame > ssvgi::kMaxExtraViews)
    throw gpu::GpuError("extra views: viewsPerFrame must be in 1.." + std::to_string(ssvgi::kMaxExtraViews));
  const shader::CompositeFallback noFallback{};
  std::memcpy(noFallback_.mapped(), &noFallback, sizeof(noFallback));
  if (settings.sunViewSize > 0) sources_.push_back({Kind::Sun, 0});
  if (settings.overheadViewSize > 0) sources_.push_back({Kind::Overhead, 0});
  if (settings.surroundViewSize > 0)
    for (uint32_t face = 0; face < kCubeFaces.size(); ++face) sources_.push_back({Kind::Surround, face});
  if (settings.lightViewSize > 0)
    for (const LocalLight& light : scene.lights)
      for (const Camera& camera : lightCameras(light)) {
        sources_.push_back({Kind::Light, uint32_t(lightCameras_.size())});
        lightCameras_.push_back(camera);
      }
  // As many targets of each kind as one frame can render.
  for (Kind kind : {Kind::Sun, Kind::Overhead, Kind::Surround, Kind::Light}) {
    const auto count = uint32_t(std::count_if(sources_.begin(), sources_.end(),
                                              [kind](const Source& source) { return source.kind == kind; }));
    for (uint32_t i = 0; i < std::min(count, settings.viewsPerFrame); ++i)
      targets_.emplace_back(kind, device, sizeOf(kind));
  }
  if (const uint32_t size = maxViewSize(); size > 0) {
    directIrradiance_ = storageImage(device, "extra view direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, size);
    viewDistance_ = storageImage(device, "extra view distance", VK_FORMAT_R32_SFLOAT, size);
    indirectUsed_ = storageImage(device, "extra view indirect used", VK_FORMAT_R32G32B32A32_SFLOAT, size);
    finalRadiance_ = storageImage(device, "extra view final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, size);
  }
}

uint32_t ExtraViews::sizeOf(Kind kind) const {
  switch (kind) {
    case Kind::Sun: return settings_.sunViewSize;
    case Kind::Overhead: return settings_.overheadViewSize;
    case Kind::Surround: return settings_.surroundViewSize;
    case Kind::Light: return settings_.lightViewSize;
  }
  return 0;
}

bool ExtraViews::isReflectiveShadowMap(const Source& source, const shader::FrameConstants& frame) const {
  const bool sunEnabled = frame.sunDirectionAndEnabled.w > 0.0f;
  if (!settings_.reflectiveShadowMaps || sceneEmits_) return false;
  if (source.kind == Kind::Sun) return sunAboveHorizon(frame) && frame.localLightCount == 0;
  return source.kind == Kind::Light && !sunEnabled && frame.localLightCount == 1;
}

uint32_t ExtraViews::maxViewSize() const {
  uint32_t size = 0;
  for (const Source& source : sources_) size = std::max(size, sizeOf(source.kind));
  return size;
}

void ExtraViews::viewOf(const Source& source, const shader::FrameConstants& frame, glm::mat4& view,
                        glm::mat4& projection) const {
  if (source.kind != Kind::Sun && source.kind != Kind::Overhead) {
    Camera camera;
    if (source.kind == Kind::Light) {
      camera = lightCameras_[source.index];
    } else {
      const glm::vec3 axis = kCubeFaces[source.index];
      camera.position = glm::vec3(frame.cameraPosition);
      camera.target = camera.position + axis;
      camera.up = upFor(axis);
      camera.verticalFov = glm::half_pi<float>();
      camera.nearPlane = kNearPlane;
    }
    view = viewMatrix(camera);
    projection = reversedZInfiniteProjection(camera.verticalFov, 1.0f, camera.nearPlane);
    return;
  }
  // Along the sun, over the voxel volume around the camera, its texels a voxel wide (or narrower where the volume's
  // footprint is smaller than the view). Without a sun (none, or below the horizon) the view looks straight down: it
  // still observes the open space above roofs and yards that the probes' rays cross to the sky (SPEC §6.4), and the
  // surfaces under the sky. The overhead view looks straight down over the whole volume, whatever its texels.
  const glm::vec3 cameraPosition(frame.cameraPosition);
  if (source.kind == Kind::Overhead) {
    orthographicOverVolume(glm::vec3(0.0f, 1.0f, 0.0f), cameraPosition, settings_.overheadViewSize,
                           std::numeric_limits<float>::infinity(), view, projection);
    return;
  }
  const glm::vec3 toSun =
      sunAboveHorizon(frame) ? glm::normalize(glm::vec3(frame.sunDirectionAndEnabled)) : glm::vec3(0.0f, 1.0f, 0.0f);
  orthographicOverVolume(toSun, cameraPosition, settings_.sunViewSize, voxelSize_, view, projection);
}

void ExtraViews::orthographicOverVolume(glm::vec3 toward, glm::vec3 cameraPosition, uint32_t size, float maxTexel,
                                        glm::mat4& view, glm::mat4& projection) const {
  // In the view's frame (rotation only) the volume's footprint is its box's extent across the view; the texels depend
  // only on the direction: snapping the view's centre to whole texels keeps the texel grid fixed in the world as the
  // camera moves, so that the view does not shimmer.
  const glm::mat4 rotation = glm::lookAtRH(glm::vec3(0.0f), -toward, upFor(toward));
  // The volume re-centres in steps of kScrollStepBricks bricks: across, it reaches that much further from the camera
  // (up and down it may stand further off, where it holds what the camera sees: ssvgi::Stats::voxelVolume; these views
  // stay on the camera, QUALITY.md "The volume stands where the camera looks").
  const glm::vec3 halfExtent =
      volumeHalfExtent_ + float(shader::kScrollStepBricks * shader::kBrickSizeVoxels) * voxelSize_;
  const glm::mat3 rows = glm::transpose(glm::mat3(rotation));  // rows[0], rows[1]: the view frame's x and y axes
  const glm::vec2 footprint(glm::dot(glm::abs(rows[0]), halfExtent), glm::dot(glm::abs(rows[1]), halfExtent));
  const float texel = std::min(maxTexel, 2.0f * std::max(footprint.x, footprint.y) / float(size));
  const glm::vec3 cameraInViewFrame = glm::vec3(rotation * glm::vec4(cameraPosition, 1.0f));
  const glm::vec2 centre = glm::round(glm::vec2(cameraInViewFrame) / texel) * texel;
  // Depth: the whole scene, so that whatever shades a surface from the sun lies inside the view, and — in front of
  // it — the whole voxel volume, so that the view observes all the open space its rays cross there (SPEC §6.4).
  float nearest = 1e30f, farthest = -1e30f;
  const glm::vec3 volumeMin = cameraPosition - halfExtent;
  const glm::vec3 volumeMax = cameraPosition + halfExtent;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 point((corner & 1) ? sceneBounds_.max.x : sceneBounds_.min.x,
                          (corner & 2) ? sceneBounds_.max.y : sceneBounds_.min.y,
                          (corner & 4) ? sceneBounds_.max.z : sceneBounds_.min.z);
    const glm::vec3 volumeCorner((corner & 1) ? volumeMax.x : volumeMin.x, (corner & 2) ? volumeMax.y : volumeMin.y,
                                 (corner & 4) ? volumeMax.z : volumeMin.z);
    const float distance = -(rotation * glm::vec4(point, 1.0f)).z;
    nearest = std::min({nearest, distance - kSunViewDepthMargin, -(rotation * glm::vec4(volumeCorner, 1.0f)).z});
    farthest = std::max(farthest, distance + kSunViewDepthMargin);
  }
  // The eye at the centre of the near plane.
  const glm::vec3 eye = glm::vec3(glm::inverse(rotation) * glm::vec4(centre, -nearest, 1.0f));
  view = glm::lookAtRH(eye, eye - toward, upFor(toward));
  const float half = 0.5f * float(size) * texel;
  projection = reversedZOrthographicProjection(-half, half, -half, half, 0.0f, farthest - nearest);
}

std::vector<ssvgi::ExtraView> ExtraViews::record(gpu::HostCommandList& commands, const shader::FrameConstants& frame,
                                                 const GpuScene& scene, const gpu::Buffer& lights,
                                                 const ShadowPass& shadows, VkSampler pointSampler) {
  std::vector<ssvgi::ExtraView> views;
  if (sources_.empty()) return views;
  auto scope = commands.scope("renderer: ExtraViews");
  if (!cleared_) {
    commands.clearImage(noIndirect_, VkClearColorValue{});
    cleared_ = true;
  }
  commands.use(noIndirect_, gpu::Usage::ComputeSampled);
  const auto count = uint32_t(std::min<size_t>(settings_.viewsPerFrame, sources_.size()));
  std::vector<Target*> unused;
  for (Target& target : targets_) unused.push_back(&target);
  for (uint32_t i = 0; i < count; ++i) {
    Source& source = sources_[(nextSource_ + i) % sources_.size()];
    const auto slot =
        std::find_if(unused.begin(), unused.end(), [&](const Target* target) { return target->kind == source.kind; });
    Target& target = **slot;
    unused.erase(slot);

    glm::mat4 view, projection;
    viewOf(source, frame, view, projection);
    const glm::vec2 jitter = shader::halton23(++source.renders) - glm::vec2(0.5f);
    shader::FrameConstants viewFrame = frame;
    setFrameView(viewFrame, view, jitteredProjection(projection, jitter, target.size, target.size), target.size,
                 target.size);
    viewFrame.addsIndirectLight = 0u;  // direct and emitted light only: ssvgi adds the rest
    std::memcpy(target.frameConstants.mapped(), &viewFrame, sizeof(viewFrame));
    gbufferPass_.record(commands, scene, target.frameConstants, target.gbuffer);
    if (source.kind == Kind::Overhead) {  // observes space only: its depth
      commands.use(target.gbuffer.depth, gpu::Usage::ComputeSampled);
      ssvgi::ExtraView overhead;
      overhead.camera = toView(viewFrame, target.size);
      overhead.depth.view = target.gbuffer.depth.view();
      views.push_back(overhead);
      continue;
    }
    directLighting_.record(commands, target.frameConstants, lights, shadows, target.gbuffer, pointSampler,
                           directIrradiance_, viewDistance_);
    composite_.record(commands, target.frameConstants, noFallback_, target.gbuffer, pointSampler, directIrradiance_,
                      noIndirect_.view(), noIndirect_.view(), finalRadiance_, indirectUsed_, target.radiance);
    for (const gpu::Image* image :
         {&target.radiance, &target.gbuffer.depth, &target.gbuffer.normal, &target.gbuffer.albedo})
      commands.use(*image, gpu::Usage::ComputeSampled);
    ssvgi::ExtraView lit;
    lit.camera = toView(viewFrame, target.size);
    lit.depth.view = target.gbuffer.depth.view();
    lit.color.view = target.radiance.view();
    lit.normal.view = target.gbuffer.normal.view();
    lit.albedo.view = target.gbuffer.albedo.view();
    lit.isReflectiveShadowMap = isReflectiveShadowMap(source, frame);
    views.push_back(lit);
  }
  nextSource_ = (nextSource_ + count) % uint32_t(sources_.size());
  return views;
}

}  // namespace ssvgi::renderer
