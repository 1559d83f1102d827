#include "gather_targets.h"

#include <cstring>

namespace ssvgi::gi {

namespace {

uint32_t divideRoundingUp(uint32_t value, uint32_t divisor) { return (value + divisor - 1) / divisor; }

// The images of frames up to maxWidth × maxHeight and the bytes of a frame's constants: what the constructor allocates
// and bytes() counts.
struct Resources {
  gpu::ImageDesc tileIrradiance, tileProbeBlend, output, confidence;
  VkDeviceSize constants;  // per frame in flight
};

// The tile images are sampled-capable so that the library's tests can upload them (uploadImage leaves an image ready
// to be sampled). The host samples the output (Context::output()); two alternate, each the other's history. The host samples
// the confidence too (Context::confidence()): R8, a storage format of Vulkan's extended set, since every format all
// devices can store takes 4 bytes a texel, and 2 MB more would break SPEC §5's 10 MB (ARCHITECTURE.md).
Resources resources(uint32_t maxWidth, uint32_t maxHeight) {
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  const uint32_t halfWidth = divideRoundingUp(maxWidth, 2), halfHeight = divideRoundingUp(maxHeight, 2);
  return {{"ssvgi gather tile irradiance", VK_FORMAT_R16G16B16A16_SFLOAT,
           divideRoundingUp(maxWidth, shader::kGatherTileSize), divideRoundingUp(maxHeight, shader::kGatherTileSize), 1,
           1, usage},
          {"ssvgi gather tile probe blend", VK_FORMAT_R8_UNORM, divideRoundingUp(maxWidth, shader::kGatherTileSize),
           divideRoundingUp(maxHeight, shader::kGatherTileSize), 1, 1, usage},
          {"ssvgi gather output", VK_FORMAT_R16G16B16A16_SFLOAT, halfWidth, halfHeight, 1, 1, usage},
          {"ssvgi gather confidence", VK_FORMAT_R8_UNORM, halfWidth, halfHeight, 1, 1, usage},
          sizeof(shader::GatherConstants)};
}

}  // namespace

GatherTargets::GatherTargets(gpu::Device& device, uint32_t maxWidth, uint32_t maxHeight, uint32_t framesInFlight) {
  const Resources sizes = resources(maxWidth, maxHeight);
  tileIrradiance_ = gpu::Image(device, sizes.tileIrradiance);
  tileProbeBlend_ = gpu::Image(device, sizes.tileProbeBlend);
  for (gpu::Image& output : outputs_) output = gpu::Image(device, sizes.output);
  confidence_ = gpu::Image(device, sizes.confidence);
  for (uint32_t i = 0; i < framesInFlight; ++i)
    constants_.emplace_back(device, "ssvgi gather constants", sizes.constants, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                            gpu::MemoryUsage::HostUpload);
}

VkDeviceSize GatherTargets::bytes(gpu::Device& device, uint32_t maxWidth, uint32_t maxHeight, uint32_t framesInFlight) {
  const Resources sizes = resources(maxWidth, maxHeight);
  return gpu::imageMemoryBytes(device, sizes.tileIrradiance) + gpu::imageMemoryBytes(device, sizes.tileProbeBlend) +
         kOutputs * gpu::imageMemoryBytes(device, sizes.output) + gpu::imageMemoryBytes(device, sizes.confidence) +
         framesInFlight * sizes.constants;
}

void GatherTargets::prepare(uint32_t frameIndex, const glm::mat4& viewProjection, uint32_t width, uint32_t height,
                            const ProbeLevels& probes) {
  const glm::uvec2 tiles(divideRoundingUp(width, shader::kGatherTileSize),
                         divideRoundingUp(height, shader::kGatherTileSize));
  const glm::uvec2 halfSize(divideRoundingUp(width, 2), divideRoundingUp(height, 2));
  const bool historyUsable = prepared_ && tiles == current_.tiles && halfSize == current_.halfSize;
  // The history is the last frame's output, seen through the last frame's camera.
  current_.historyViewProjection = prepared_ ? previousViewProjection_ : viewProjection;
  current_.historyInverseViewProjection = glm::inverse(current_.historyViewProjection);
  for (uint32_t level = 0; level < shader::kProbeLevels; ++level)
    current_.probeLevels[level] = {probes.origins[level], probes.spacings[level]};
  current_.probesPerAxis = probes.dimensions;
  current_.skyRadiance = probes.skyRadiance;
  current_.probesPerLevel = probes.dimensions.x * probes.dimensions.y * probes.dimensions.z;
  current_.tiles = tiles;
  current_.halfSize = halfSize;
  current_.frameIndex = frameIndex;
  current_.historyUsable = historyUsable ? 1u : 0u;
  currentFrame_ = frameIndex % constants_.size();
  std::memcpy(constants_[currentFrame_].mapped(), &current_, sizeof(current_));
  if (prepared_) currentOutput_ = 1 - currentOutput_;
  previousViewProjection_ = viewProjection;
  prepared_ = true;
}

}  // namespace ssvgi::gi
