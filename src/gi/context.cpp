// The GI context: owns the passes and their resources and records a frame in the order of SPEC §4.
#include "gather/confidence_debug_view.h"
#include "gather/gather_passes.h"
#include "gpu/command_list.h"
#include "gpu/profiler.h"
#include "probes/probe_debug_view.h"
#include "probes/probe_passes.h"
#include "shared/gi_frame.h"
#include "shared/work_counters.h"
#include "ssvgi/ssvgi.h"
#include "voxels/build_octree.h"
#include "voxels/voxel_debug_view.h"
#include "voxels/voxel_passes.h"
#include "voxels/voxel_scene.h"
#include "context_internals.h"
#include "memory_budget.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <type_traits>
#include <vector>

namespace ssvgi {

namespace {

glm::mat4 toMat4(const Matrix4& matrix) { return glm::make_mat4(matrix.data()); }

// Frustum planes of a view-projection, pointing inwards (Gribb and Hartmann). Reversed-Z: inside is 0 <= z <= w. The
// far plane (z >= 0) bounds an orthographic view; a perspective view's lies at infinity (its row is (0, 0, 0, near))
// and excludes nothing.
void frustumPlanes(const glm::mat4& viewProjection, glm::vec4 planes[6]) {
  const glm::mat4 rows = glm::transpose(viewProjection);
  planes[0] = rows[3] + rows[0];
  planes[1] = rows[3] - rows[0];
  planes[2] = rows[3] + rows[1];
  planes[3] = rows[3] - rows[1];
  planes[4] = rows[3] - rows[2];
  planes[5] = rows[2];
  for (glm::vec4* plane = planes; plane != planes + 6; ++plane) {
    const float length = glm::length(glm::vec3(*plane));
    *plane = length > 0.0f ? *plane / length : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  }
}

Error invalid(const std::string& message) { return {Status::InvalidDescription, message}; }

// View positions beyond this many metres from the origin are refused: there a float no longer resolves a millimetre,
// and the volumes' integer brick and probe coordinates would overflow further out.
constexpr float kMaxViewCoordinate = 1.0e6f;
// The largest extra view side ContextDesc::maxExtraViewSize may ask for (the Hi-Z pyramid is sized for it).
constexpr uint32_t kMaxExtraViewSizeLimit = 16384;

Error toError(const gpu::GpuError& error) {
  const bool outOfMemory = error.result() == VK_ERROR_OUT_OF_DEVICE_MEMORY;
  return {outOfMemory ? Status::OutOfDeviceMemory : Status::VulkanError, error.what(), error.result()};
}

gpu::ExternalDevice externalDevice(const ContextDesc& desc) {
  return {desc.instance,         desc.physicalDevice,        desc.device,
          desc.debugUtilsEnabled, desc.vkGetInstanceProcAddr, desc.vkGetDeviceProcAddr};
}

// Whether a setting's value is one its SettingInfo accepts.
bool accepted(const SettingInfo& info, double value) {
  if (!std::isfinite(value)) return false;
  if (info.zeroTurnsOff && value == 0.0) return true;
  if (info.minimumExcluded ? !(value > info.minimum) : !(value >= info.minimum)) return false;
  if (!(value <= info.maximum)) return false;
  if (info.multipleOf > 1 && std::fmod(value, double(info.multipleOf)) != 0.0) return false;
  return !info.powerOfTwo || (uint64_t(value) & (uint64_t(value) - 1)) == 0;
}

std::string numberText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// What a SettingInfo accepts, in words: "a power of two in 1..32", "a positive multiple of 8", "0 (off) or at least 1".
std::string acceptedValues(const SettingInfo& info, bool isFloat) {
  const bool positive = info.minimumExcluded ? info.minimum == 0.0 : (!isFloat && info.minimum == 1.0);
  std::string range = std::isfinite(info.maximum) ? "in " + numberText(info.minimum) + ".." + numberText(info.maximum)
                      : positive                  ? "positive"
                      : info.minimum == 0.0       ? "0 or more"
                                                  : "at least " + numberText(info.minimum);
  if (info.powerOfTwo) range = "a power of two " + range;
  if (info.multipleOf > 1)
    range = positive && !std::isfinite(info.maximum) ? "a positive multiple of " + std::to_string(info.multipleOf)
                                                     : "a multiple of " + std::to_string(info.multipleOf) + " " + range;
  if (info.zeroTurnsOff) range = "0 (off) or " + range;
  return isFloat ? range + " and finite" : range;
}

Error validateSettings(const ContextDesc& desc) {
  const Settings& settings = desc.settings;
  if (!desc.instance || !desc.physicalDevice || !desc.device)
    return invalid("ContextDesc: instance, physicalDevice and device are required");
  for (const SettingInfo& info : settingInfos()) {
    std::vector<double> values;
    bool isFloat = false;
    std::visit(
        [&](auto member) {
          using Value = std::remove_cvref_t<decltype(settings.*member)>;
          if constexpr (std::is_same_v<Value, std::array<uint32_t, 3>>) {
            for (uint32_t axis : settings.*member) values.push_back(axis);
          } else if constexpr (!std::is_same_v<Value, bool>) {
            values.push_back(double(settings.*member));
            isFloat = std::is_same_v<Value, float>;
          }
        },
        info.member);
    for (double value : values)
      if (!accepted(info, value))
        return invalid(std::string("Settings::") + info.name + " must be " + acceptedValues(info, isFloat) + " (got " +
                       numberText(value) + ")");
  }
  // The volumes follow the views, which stand within ±kMaxViewCoordinate: a volume wider than that span would put its
  // far side (and the views a host makes to cover it, such as a sun's) where floats no longer resolve a voxel.
  const double worldSpan = 2.0 * double(kMaxViewCoordinate);
  const auto widest = [](const std::array<uint32_t, 3>& cells) { return double(*std::ranges::max_element(cells)); };
  const double voxelVolumeSpan = widest(settings.volumeBricks) * shader::kBrickSizeVoxels * settings.voxelSize;
  if (!(voxelVolumeSpan <= worldSpan))
    return invalid("Settings::voxelSize and Settings::volumeBricks make the voxel volume " +
                   numberText(voxelVolumeSpan) + " m across; at most " + numberText(worldSpan) + " m");
  const double probeVolumeSpan =
      widest(settings.probeGrid) * settings.probeSpacing * double(1u << (shader::kProbeLevels - 1u));
  if (!(probeVolumeSpan <= worldSpan))
    return invalid("Settings::probeSpacing and Settings::probeGrid make the coarsest probe level " +
                   numberText(probeVolumeSpan) + " m across; at most " + numberText(worldSpan) + " m");
  if (settings.probeReservoirs && settings.raysPerProbe < 2 * shader::kProbeStrata)
    return invalid("Settings::raysPerProbe must be at least 16 with Settings::probeReservoirs (" +
                   std::to_string(shader::kProbeStrata) + " strata, each a new candidate and its reservoir's ray)");
  if (desc.framesInFlight == 0 || desc.framesInFlight > 8) return invalid("ContextDesc::framesInFlight must be in 1..8");
  if (desc.maxWidth == 0 || desc.maxHeight == 0) return invalid("ContextDesc::maxWidth/maxHeight must be positive");
  if (desc.maxExtraViewSize > kMaxExtraViewSizeLimit)
    return invalid("ContextDesc::maxExtraViewSize must be at most " + std::to_string(kMaxExtraViewSizeLimit));
  return {};
}

// What ssvgi needs of the device beyond Vulkan 1.1 compute. The confidence output is R8_UNORM, written by a shader:
// a storage format of Vulkan's extended set (shaderStorageImageExtendedFormats lists it; its SPIR-V capability needs
// no feature enabled), which desktop and current mobile GPUs store.
Error checkDevice(const ContextDesc& desc) {
  const gpu::Device device(externalDevice(desc));
  VkFormatProperties properties{};
  device.vk().vkGetPhysicalDeviceFormatProperties(desc.physicalDevice, VK_FORMAT_R8_UNORM, &properties);
  const VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
  if ((properties.optimalTilingFeatures & needed) != needed)
    return {Status::UnsupportedDevice,
            "the device cannot write VK_FORMAT_R8_UNORM storage images (the confidence output, Context::confidence())"};
  return {};
}

// A view's matrix must map the world to clip space invertibly and its position lie where float coordinates still
// resolve a voxel: NaN or 1e30 there would send every pass's loops over the volume astray.
Error validateViewGeometry(const View& view, const std::string& name) {
  const glm::mat4 viewProjection = glm::make_mat4(view.viewProjection.data());
  for (float value : view.viewProjection)
    if (!std::isfinite(value)) return invalid(name + ".viewProjection: not finite");
  const glm::mat4 inverse = glm::inverse(viewProjection);
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row)
      if (!std::isfinite(inverse[column][row])) return invalid(name + ".viewProjection: not invertible");
  for (float coordinate : view.position)
    if (!(std::abs(coordinate) <= kMaxViewCoordinate))
      return invalid(name + ".position: each coordinate must be finite and within ±" +
                     std::to_string(int(kMaxViewCoordinate)) + " m");
  return {};
}

Error validateView(const View& view, const std::string& name, uint32_t maxWidth, uint32_t maxHeight,
                   const char* limit) {
  if (view.width == 0 || view.height == 0) return invalid(name + ": width and height must be positive");
  if (view.width > maxWidth || view.height > maxHeight)
    return invalid(name + ": " + std::to_string(view.width) + "×" + std::to_string(view.height) + " exceeds " + limit +
                   " (" + std::to_string(maxWidth) + "×" + std::to_string(maxHeight) + ")");
  return validateViewGeometry(view, name);
}

Error validateFrameView(const View& view, const std::string& name, const ContextDesc& desc) {
  return validateView(view, name, desc.maxWidth, desc.maxHeight, "ContextDesc::maxWidth/maxHeight");
}

class ContextImplementation final : public Context {
 public:
  // `desc` with the settings the memory budget leaves (settingsWithinBudget).
  explicit ContextImplementation(const ContextDesc& desc)
      : desc_(desc),
        bufferBytes_(gi::ContextBufferBytes::of(desc, desc.settings)),
        device_(externalDevice(desc)),
        scene_(device_, desc.settings, desc.framesInFlight),
        probes_(device_, desc.settings, desc.framesInFlight),
        gather_(device_, desc.maxWidth, desc.maxHeight, desc.framesInFlight),
        pointSampler_(device_, pointSamplerInfo(), "ssvgi point sampler"),
        skyMapSampler_(device_, skyMapSamplerInfo(), "ssvgi sky map sampler"),
        hiz_(device_, "ssvgi hi-z pyramid", bufferBytes_.hiz, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
        visibleBricks_(device_, "ssvgi visible bricks", bufferBytes_.visibleBricks,
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT),
        hizBuild_(device_),
        volumeScroll_(device_),
        brickAllocate_(device_),
        observedSpace_(device_),
        brickCulling_(device_),
        sceneVoxelization_(device_),
        buildOctree_(device_),
        voxelRelight_(device_),
        probePlacement_(device_),
        probeTrace_(device_),
        probeRelocate_(device_),
        probeDilate_(device_),
        finalGather_(device_),
        temporalUpsample_(device_),
        voxelDebugView_(device_),
        probeDebugView_(device_),
        confidenceDebugView_(device_) {
    for (uint32_t i = 0; i < desc.framesInFlight; ++i) {
      perFrame_.push_back(std::make_unique<PerFrame>(device_, bufferBytes_));
    }
  }

  Error dispatch(const FrameDesc& desc, VkCommandBuffer commandBuffer) override {
    if (Error error = validateFrame(desc)) return error;
    return guarded([&] { record(desc, commandBuffer); });
  }

  Error debugView(DebugView view, const View& camera, VkImage target, VkImageView targetView,
                  VkCommandBuffer commandBuffer) override {
    if (Error error = validateFrameView(camera, "debugView camera", desc_)) return error;
    if (!target || !targetView) return invalid("debugView: target image and view are required");
    return guarded([&] {
      PerFrame& slot = *perFrame_[lastSlot_];
      gpu::CommandList commands(device_, commandBuffer, slot.descriptors);
      if (view == DebugView::Probes)
        probeDebugView_.record(commands, scene_, probes_, lastCameraPosition_, camera, target, targetView);
      else if (view == DebugView::Confidence)
        confidenceDebugView_.record(commands, scene_, gather_, probes_.probes(), camera, target, targetView);
      else
        voxelDebugView_.record(commands, scene_, view, camera, target, targetView);
    });
  }

  const Settings& settings() const override { return desc_.settings; }
  OutputImage output() const override { return outputImage(gather_.output()); }
  OutputImage confidence() const override { return outputImage(gather_.confidence()); }

  WorldBox voxelVolume() const override {
    if (!dispatched_) return {};
    const shader::VoxelVolume& volume = scene_.current();
    const glm::vec3 lowest = glm::vec3(volume.originBrick) * volume.brickSize;
    const glm::vec3 highest = glm::vec3(volume.originBrick + volume.dimensionsBricks) * volume.brickSize;
    return {{lowest.x, lowest.y, lowest.z}, {highest.x, highest.y, highest.z}};
  }

  const gi::VoxelScene& voxelScene() const { return scene_; }
  const gi::ProbeVolume& probeVolume() const { return probes_; }
  const gi::GatherTargets& gatherTargets() const { return gather_; }

  Stats stats() override {
    Stats stats;
    for (const auto& [name, bytes] : device_.allocations()) {
      stats.memory.push_back({name, bytes});
      stats.totalBytes += bytes;
    }
    stats.memoryBudgetBytes = desc_.memoryBudgetBytes;
    stats.settings = desc_.settings;
    stats.brickPoolCapacity = desc_.settings.brickPoolCapacity;
    if (!dispatched_) return stats;
    PerFrame& slot = *perFrame_[lastSlot_];
    shader::BrickPoolState pool{};
    std::memcpy(&pool, slot.statsReadback.mapped(), sizeof(pool));
    stats.bricksLive = pool.bumpCount - pool.freeCount;
    stats.bricksFree = pool.freeCount;
    stats.bricksNeverUsed = desc_.settings.brickPoolCapacity - pool.bumpCount;
    stats.bricksDroppedLastFrame = pool.droppedThisFrame;
    stats.bricksDroppedTotal = pool.droppedTotal;
    stats.bricksAllocatedLastFrame = pool.allocatedThisFrame;
    stats.bricksReleasedLastFrame = pool.releasedThisFrame;
    stats.bricksVisibleLastFrame = pool.visibleThisFrame;
    stats.voxelsValid = pool.voxelsValid;
    stats.voxelVolume = voxelVolume();
    shader::IndirectList probeList{};
    std::memcpy(&probeList, slot.probeListReadback.mapped(), sizeof(probeList));
    stats.probeLevelUpdatedLastFrame = slot.probeLevel;
    stats.probesUpdatedLastFrame = probeList.count;
    stats.probesWatchedForChange = probes_.lastTally().watchedProbes;
    stats.probesCutByChange = probes_.lastTally().cutProbes;
    stats.sharedChangeRecovery = probes_.current().startsSharedRecovery != 0u;
    stats.probesLeaning = float(probes_.leaning().mean);
    stats.probesLeaningError = float(probes_.leaning().standardError);
    stats.probesLoopGap = float(probes_.leaning().gap());
    stats.sharedDrift = probes_.followsSharedDrift();
    stats.work = workCounts(slot);
    for (const auto& timing : slot.profiler.resolve()) stats.passes.push_back({timing.name, timing.milliseconds});
    return stats;
  }

 private:
  // What a frame in flight owns until the host has finished with it.
  struct PerFrame {
    PerFrame(gpu::Device& device, const gi::ContextBufferBytes& bytes)
        : descriptors(device),
          profiler(device),
          frameConstants(device, "ssvgi frame constants", bytes.viewConstants, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                         gpu::MemoryUsage::HostUpload),
          statsReadback(device, "ssvgi stats readback", bytes.statsReadback, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        gpu::MemoryUsage::HostReadback),
          probeListReadback(device, "ssvgi probe list readback", bytes.probeListReadback,
                            VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::HostReadback),
          workReadback(device, "ssvgi work counters readback", bytes.workReadback, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       gpu::MemoryUsage::HostReadback) {
      for (uint32_t i = 0; i < kMaxExtraViews; ++i)
        extraViewConstants.emplace_back(device, "ssvgi extra view constants", bytes.viewConstants,
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload);
    }
    gpu::DescriptorArena descriptors;
    gpu::Profiler profiler;
    gpu::Buffer frameConstants;
    std::vector<gpu::Buffer> extraViewConstants;  // GiFrame of each extra view (FrameDesc::extraViews)
    gpu::Buffer statsReadback;
    gpu::Buffer probeListReadback;  // the probe list's header: how many probes were traced
    gpu::Buffer workReadback;       // WorkCounters, copied at the end of a frame that counts its work
    uint32_t probeLevel = 0;        // the probe level the frame updated
    // Whether the frame counted its work (FrameDesc::countWork), and what its dispatch sizes tell of it: the camera's
    // Hi-Z texels, the half-resolution pixels of TemporalUpsample.
    bool countsWork = false;
    uint32_t hizTexels = 0;
    uint32_t halfResolutionPixels = 0;
    bool countedHeights = false;  // the slot's last frame counted heights: statsReadback holds them
  };

  // Stats::work of a frame: where it counted its work, the GPU's counters and the figures of the dispatch sizes.
  static WorkCounts workCounts(const PerFrame& slot) {
    WorkCounts work;
    if (!slot.countsWork) return work;
    shader::WorkCounters counted{};
    std::memcpy(&counted, slot.workReadback.mapped(), sizeof(counted));
    work.counted = true;
    work.observedSpace = {counted.observedSpaceRays, counted.observedSpaceCells};
    work.sceneVoxelization = {counted.injectionVoxels, counted.injectionVoxelsInView};
    work.extraViewVoxelization = {counted.extraViewInjectionVoxels, counted.extraViewInjectionVoxelsInView};
    work.voxelRelight = {counted.relightVoxels, {counted.relightRays, counted.relightReads}};
    work.probePlacement = {counted.placementProbes, counted.placementReads};
    work.probeTrace = {counted.probeTraceProbes,
                       {counted.probeTraceRays, counted.probeTraceReads},
                       {counted.probeTraceSeedRays, counted.probeTraceSeedReads}};
    work.probeRelocate = {counted.relocateRays, counted.relocateReads};
    work.finalGather = {counted.gatherTiles, {counted.gatherRays, counted.gatherReads}};
    work.hizBuild.texels = slot.hizTexels;
    work.temporalUpsample.pixels = slot.halfResolutionPixels;
    return work;
  }

  static VkSamplerCreateInfo pointSamplerInfo() {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = VK_FILTER_NEAREST;
    info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    return info;
  }

  // The sky map's: bilinear, round the azimuth, clamped at the poles.
  static VkSamplerCreateInfo skyMapSamplerInfo() {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = VK_FILTER_LINEAR;
    info.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    return info;
  }

  // A gather image as OutputImage describes it to the host: left in SHADER_READ_ONLY_OPTIMAL by record().
  OutputImage outputImage(const gpu::Image& image) const {
    if (!dispatched_) return {};
    return {image.handle(), image.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, image.desc().format,
            gather_.halfSize().x, gather_.halfSize().y};
  }

  template <typename Record>
  Error guarded(Record record) {
    try {
      record();
      return {};
    } catch (const gpu::GpuError& error) {
      return toError(error);
    }
  }

  Error validateFrame(const FrameDesc& frame) const {
    if (Error error = validateFrameView(frame.camera, "FrameDesc::camera", desc_)) return error;
    if (!frame.depth.view) return invalid("FrameDesc::depth: an image view is required");
    if (!frame.normal.view) return invalid("FrameDesc::normal: an image view is required");
    for (float coefficient : frame.skyRadianceSh)
      if (!std::isfinite(coefficient)) return invalid("FrameDesc::skyRadianceSh: not finite");
    if (frame.hasLitFrame) {
      if (Error error = validateFrameView(frame.litCamera, "FrameDesc::litCamera", desc_)) return error;
      if (!frame.litColor.view || !frame.litDepth.view || !frame.litNormal.view)
        return invalid("FrameDesc: hasLitFrame needs litColor, litDepth and litNormal views");
    }
    if (frame.extraViews.size() > kMaxExtraViews)
      return invalid("FrameDesc::extraViews: " + std::to_string(frame.extraViews.size()) + " views, at most " +
                     std::to_string(kMaxExtraViews));
    for (size_t i = 0; i < frame.extraViews.size(); ++i) {
      const ExtraView& view = frame.extraViews[i];
      const std::string name = "FrameDesc::extraViews[" + std::to_string(i) + "]";
      if (Error error = validateView(view.camera, name + ".camera", desc_.maxExtraViewSize, desc_.maxExtraViewSize,
                                     "ContextDesc::maxExtraViewSize"))
        return error;
      if (!view.depth.view) return invalid(name + ": a depth view is required");
      if (view.color.view && !view.normal.view) return invalid(name + ": a view with a color needs its normal view");
      if (view.isReflectiveShadowMap && !view.albedo.view)
        return invalid(name + ": a reflective shadow map needs its albedo view (its color is direct light only)");
    }
    return {};
  }

  // The GiFrame of a view the voxel passes run for: `current` is what BrickAllocate and BrickCulling see, `lit` what
  // SceneVoxelization injects.
  shader::GiFrame viewConstants(const View& current, const View& lit, uint32_t frameIndex, uint32_t kind,
                                uint32_t& hizLevels) const {
    shader::GiFrame frame{};
    frame.viewProjection = toMat4(current.viewProjection);
    frame.inverseViewProjection = glm::inverse(frame.viewProjection);
    frame.cameraPosition = glm::vec3(current.position[0], current.position[1], current.position[2]);
    frame.litViewProjection = toMat4(lit.viewProjection);
    frame.litInverseViewProjection = glm::inverse(frame.litViewProjection);
    frame.size = glm::uvec2(current.width, current.height);
    frame.litSize = glm::uvec2(lit.width, lit.height);
    hizLevels = gi::hizLayout(current.width, current.height, frame.hizLevels);
    frame.frameIndex = frameIndex;
    frame.allocationPixelStride = desc_.settings.allocationPixelStride;
    frame.hizLevelCount = hizLevels;
    frame.viewKind = kind;
    frame.occlusionCulling = desc_.settings.occlusionCulling ? 1u : 0u;
    frustumPlanes(frame.viewProjection, frame.frustumPlanes);
    return frame;
  }

  // A view the voxels are built from: its GiFrame, the depth and normal that allocate and cull bricks, and the images
  // injected (none: the bricks are allocated and culled, nothing is injected).
  struct VoxelView {
    const gpu::Buffer& constants;
    const shader::GiFrame& frame;
    uint32_t hizLevels;
    VkImageView depth;
    VkImageView normal;
    std::optional<gi::LitFrameImages> injected;
    bool countsHeights = false;  // BrickAllocate counts its surface pixels by height (the camera's, some frames)
  };

  // Steps 1 and 3–5 of SPEC §4 for one view: HiZBuild, BrickAllocate, BrickCulling, SceneVoxelization.
  void buildVoxelsFrom(gpu::CommandList& commands, const VoxelView& view) {
    const gi::VoxelFrameInputs inputs{view.constants, pointSampler_.handle(), view.depth, view.normal,
                                      hiz_, visibleBricks_};
    if (desc_.settings.occlusionCulling)  // nothing else reads the Hi-Z
      hizBuild_.record(commands, inputs, view.frame, view.hizLevels);
    brickAllocate_.record(commands, scene_, inputs, view.frame.size, desc_.settings.allocationPixelStride,
                          view.countsHeights);
    if (desc_.settings.skyOnlyThroughObservedSpace)  // nothing else reads it
      observedSpace_.record(commands, scene_, inputs, view.frame);
    const shader::IndirectList empty{0, 1, 1, 0};
    commands.updateBuffer(visibleBricks_, 0, &empty, sizeof(empty));
    brickCulling_.record(commands, scene_, inputs);
    if (view.injected) sceneVoxelization_.record(commands, scene_, inputs, *view.injected, view.frame.viewKind);
  }

  // The camera's kind of view (gi_frame.h): a lit frame given with its albedo holds direct light only, and was lit
  // with the output of the last dispatch (the gather's history from prepare() on) once there was one.
  uint32_t cameraViewKind(const FrameDesc& desc) const {
    if (!desc.litAlbedo.view) return 0u;
    return shader::kViewIsDirectOnly | (dispatched_ ? shader::kViewIsLitWithOutput : 0u);
  }

  void record(const FrameDesc& desc, VkCommandBuffer commandBuffer) {
    const uint32_t slotIndex = desc.frameIndex % desc_.framesInFlight;
    PerFrame& slot = *perFrame_[slotIndex];
    slot.descriptors.reset();
    uint32_t hizLevels = 0;
    const shader::GiFrame frame = viewConstants(desc.camera, desc.hasLitFrame ? desc.litCamera : desc.camera,
                                                desc.frameIndex, cameraViewKind(desc), hizLevels);
    std::memcpy(slot.frameConstants.mapped(), &frame, sizeof(frame));
    bool scrolled = false;
    // The slot's readback holds the pool state its last frame left, done by now (the host's frames in flight).
    shader::BrickPoolState seen{};
    if (slot.countedHeights) std::memcpy(&seen, slot.statsReadback.mapped(), sizeof(seen));
    const shader::VoxelVolume volume = scene_.place(
        glm::vec3(frame.cameraPosition), slot.countedHeights ? &seen : nullptr, desc.frameIndex, desc.countWork,
        scrolled);
    const bool countsHeights = dispatchCount_ % gi::kSurfaceHeightFramePeriod == 0;
    const gi::OfferedProbeBlocks probeBlocks = probes_.prepare(desc.frameIndex, glm::vec3(frame.cameraPosition),
                                                       frame.frustumPlanes, desc.skyRadianceSh,
                                                       desc.skyRadianceMap.view != VK_NULL_HANDLE, volume);
    slot.probeLevel = uint32_t(probes_.current().level);
    slot.countsWork = desc.countWork;
    slot.hizTexels = 0;
    for (uint32_t level = 0; level < hizLevels; ++level)
      slot.hizTexels += frame.hizLevels[level].size.x * frame.hizLevels[level].size.y;
    gi::GatherTargets::ProbeLevels probeLevels{};
    probeLevels.dimensions = probes_.current().probesPerAxis;
    probeLevels.skyRadiance = probes_.current().skyRadiance;
    for (uint32_t level = 0; level < shader::kProbeLevels; ++level) {
      probeLevels.origins[level] = probes_.levelOrigin(level, glm::vec3(frame.cameraPosition));
      probeLevels.spacings[level] = probes_.levelSpacing(level);
    }
    gather_.prepare(desc.frameIndex, frame.viewProjection, desc.camera.width, desc.camera.height, probeLevels);
    slot.halfResolutionPixels = gather_.halfSize().x * gather_.halfSize().y;

    gpu::CommandList commands(device_, commandBuffer, slot.descriptors, &slot.profiler);
    slot.profiler.begin(commandBuffer);
    {
      auto scope = commands.scope("ssvgi: FrameSetup");
      if (!initialised_) {
        commands.fillBuffer(scene_.brickLookup(), shader::kInvalidBrick);
        commands.fillBuffer(scene_.bricks(), 0);
        commands.fillBuffer(scene_.poolState(), 0);
        commands.fillBuffer(scene_.occupancyGrid(), 0);
        commands.fillBuffer(scene_.observedSpace(), 0);  // nothing observed yet
        commands.fillBuffer(probes_.probes(), 0);  // every probe kProbeStateNeverTraced
        commands.fillBuffer(probes_.reservoirs(), 0);  // every reservoir empty
        commands.fillBuffer(probes_.changes(), 0);
        initialised_ = true;
      }
      // This frame's counters (the pool state's from droppedThisFrame on) and the two lists start empty (dispatch
      // arguments {0, 1, 1}).
      constexpr size_t kFrameCountersOffset = offsetof(shader::BrickPoolState, droppedThisFrame);
      const std::array<uint32_t, (sizeof(shader::BrickPoolState) - kFrameCountersOffset) / 4> zeroCounters{};
      commands.updateBuffer(scene_.poolState(), kFrameCountersOffset, zeroCounters.data(), sizeof(zeroCounters));
      if (desc.countWork) {
        // The passes add to the counters untracked (gpu::Bindings::accumulator): all of them after the clear.
        commands.fillBuffer(scene_.workCounters(), 0);
        commands.use(scene_.workCounters(), gpu::Usage::ComputeWrite);
      }
      const shader::IndirectList empty{0, 1, 1, 0};
      commands.updateBuffer(scene_.changedCells(), 0, &empty, sizeof(empty));
      commands.updateBuffer(probes_.list(), 0, &empty, sizeof(empty));
      commands.fillBuffer(probes_.changeTally(), 0);
    }

    if (scrolled)                                                                       // 2. VolumeScroll
      volumeScroll_.record(commands, scene_, {slot.frameConstants, pointSampler_.handle(), desc.depth.view,
                                              desc.normal.view, hiz_, visibleBricks_});
    // 1, 3–5 (HiZBuild, BrickAllocate, BrickCulling, SceneVoxelization) for each extra view (SPEC §6.3), then for the
    // camera, so that the lit frame's light stays where both see a surface.
    // Their passes are timed together, as "ssvgi: ExtraViews" (the profiler times only the outermost scope).
    std::optional<gpu::CommandList::Scope> extraViewsScope;
    if (!desc.extraViews.empty()) extraViewsScope.emplace(commands, "ssvgi: ExtraViews");
    for (size_t i = 0; i < desc.extraViews.size(); ++i) {
      const ExtraView& view = desc.extraViews[i];
      uint32_t viewHizLevels = 0;
      const bool observesOnly = !view.color.view;
      const uint32_t kind = shader::kViewIsExtra | (view.albedo.view ? shader::kViewIsDirectOnly : 0u) |
                            (view.isReflectiveShadowMap ? shader::kViewIsReflectiveShadowMap : 0u);
      const shader::GiFrame viewFrame = viewConstants(view.camera, view.camera, desc.frameIndex, kind, viewHizLevels);
      std::memcpy(slot.extraViewConstants[i].mapped(), &viewFrame, sizeof(viewFrame));
      if (observesOnly) {
        if (desc_.settings.skyOnlyThroughObservedSpace)
          observedSpace_.record(commands, scene_,
                                {slot.extraViewConstants[i], pointSampler_.handle(), view.depth.view, VK_NULL_HANDLE,
                                 hiz_, visibleBricks_},
                                viewFrame);
        continue;
      }
      const VkImageView albedo = view.albedo.view ? view.albedo.view : view.color.view;  // bound, not read
      buildVoxelsFrom(commands,
                      {slot.extraViewConstants[i], viewFrame, viewHizLevels, view.depth.view, view.normal.view,
                       gi::LitFrameImages{view.color.view, view.depth.view, view.normal.view, albedo,
                                          &gather_.history()}});
    }
    extraViewsScope.reset();
    std::optional<gi::LitFrameImages> litFrame;
    if (desc.hasLitFrame)  // without an albedo, its colour is bound in its place and not read
      litFrame = gi::LitFrameImages{desc.litColor.view, desc.litDepth.view, desc.litNormal.view,
                                    desc.litAlbedo.view ? desc.litAlbedo.view : desc.litColor.view,
                                    &gather_.history()};
    buildVoxelsFrom(commands, {slot.frameConstants, frame, hizLevels, desc.depth.view, desc.normal.view, litFrame,
                               countsHeights});
    buildOctree_.record(commands, scene_);                                              // 6. BuildOctree
    voxelRelight_.record(commands, scene_, {gather_.constants(), probes_.probes()},      //    VoxelRelight
                         desc.frameIndex, desc_.settings.voxelRelightPeriod);
    probePlacement_.record(commands, scene_, probes_, slot.frameConstants, probeBlocks);  // 7. ProbePlacement
    // 8. UpdateReservoirs + ProbeTrace; without a sky map any readable image is bound (not read).
    const bool hasSkyMap = desc.skyRadianceMap.view != VK_NULL_HANDLE;
    probeTrace_.record(commands, scene_, probes_, hasSkyMap ? desc.skyRadianceMap.view : desc.depth.view,
                       hasSkyMap ? skyMapSampler_.handle() : pointSampler_.handle());
    probeRelocate_.record(commands, scene_, probes_);                                   // 9. ProbeRelocate
    probeDilate_.record(commands, probes_);                                             //    ProbeDilate
    const gi::GatherInputs gatherInputs{slot.frameConstants, pointSampler_.handle(), desc.depth.view, desc.normal.view};
    finalGather_.record(commands, gatherInputs, gather_, scene_, probes_.probes());    // 10. FinalGather
    temporalUpsample_.record(commands, gatherInputs, gather_);                         // 11.–12. TemporalUpsample
    commands.use(gather_.output(), gpu::Usage::ComputeSampled);  // the outputs' contract (OutputImage)
    commands.use(gather_.confidence(), gpu::Usage::ComputeSampled);

    commands.copyBuffer(scene_.poolState(), slot.statsReadback, sizeof(shader::BrickPoolState));
    commands.use(slot.statsReadback, gpu::Usage::HostRead);
    commands.copyBuffer(probes_.list(), slot.probeListReadback, sizeof(shader::IndirectList));
    commands.use(slot.probeListReadback, gpu::Usage::HostRead);
    commands.copyBuffer(probes_.changeTally(), probes_.changeTallyReadback(), sizeof(shader::ProbeChangeTally));
    commands.use(probes_.changeTallyReadback(), gpu::Usage::HostRead);
    // The tracker last saw the counters written by compute (FrameSetup's use()): the copy waits for every dispatch.
    if (desc.countWork) {
      commands.copyBuffer(scene_.workCounters(), slot.workReadback, sizeof(shader::WorkCounters));
      commands.use(slot.workReadback, gpu::Usage::HostRead);
    }
    commands.flushBarriers();
    lastSlot_ = slotIndex;
    slot.countedHeights = countsHeights;
    ++dispatchCount_;
    lastCameraPosition_ = glm::vec3(frame.cameraPosition);
    dispatched_ = true;
  }

  ContextDesc desc_;
  gi::ContextBufferBytes bufferBytes_;
  gpu::Device device_;
  gi::VoxelScene scene_;
  gi::ProbeVolume probes_;
  gi::GatherTargets gather_;
  gpu::Sampler pointSampler_;
  gpu::Sampler skyMapSampler_;
  gpu::Buffer hiz_;
  gpu::Buffer visibleBricks_;
  std::vector<std::unique_ptr<PerFrame>> perFrame_;
  gi::HiZBuild hizBuild_;
  gi::VolumeScroll volumeScroll_;
  gi::BrickAllocate brickAllocate_;
  gi::ObservedSpace observedSpace_;
  gi::BrickCulling brickCulling_;
  gi::SceneVoxelization sceneVoxelization_;
  gi::BuildOctree buildOctree_;
  gi::VoxelRelight voxelRelight_;
  gi::ProbePlacement probePlacement_;
  gi::ProbeTrace probeTrace_;
  gi::ProbeRelocate probeRelocate_;
  gi::ProbeDilate probeDilate_;
  gi::FinalGather finalGather_;
  gi::TemporalUpsample temporalUpsample_;
  gi::VoxelDebugView voxelDebugView_;
  gi::ProbeDebugView probeDebugView_;
  gi::ConfidenceDebugView confidenceDebugView_;
  glm::vec3 lastCameraPosition_{0.0f};  // where the last dispatch centred the probe volume
  uint32_t lastSlot_ = 0;
  uint64_t dispatchCount_ = 0;
  bool dispatched_ = false;
  bool initialised_ = false;
};

}  // namespace

Result<std::unique_ptr<Context>> Context::create(const ContextDesc& desc) {
  if (Error error = validateSettings(desc)) return error;
  try {
    if (Error error = checkDevice(desc)) return error;
    gpu::Device device(externalDevice(desc));
    Result<Settings> settings = gi::settingsWithinBudget(device, desc);
    if (!settings.ok()) return settings.error();
    ContextDesc budgeted = desc;
    budgeted.settings = settings.value();
    return std::unique_ptr<Context>(std::make_unique<ContextImplementation>(budgeted));
  } catch (const gpu::GpuError& error) {
    return toError(error);
  }
}

}  // namespace ssvgi

namespace ssvgi::gi {

const VoxelScene& voxelSceneOf(const Context& context) {
  return static_cast<const ContextImplementation&>(context).voxelScene();
}

const ProbeVolume& probeVolumeOf(const Context& context) {
  return static_cast<const ContextImplementation&>(context).probeVolume();
}

const GatherTargets& gatherTargetsOf(const Context& context) {
  return static_cast<const ContextImplementation&>(context).gatherTargets();
}

}  // namespace ssvgi::gi
