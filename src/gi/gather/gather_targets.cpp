#include "gather_targets.h"

#include <cstring>

namespace ssvgi::gi {

namespace {

uint32_t divideRoundingUp(uint32_t value, uint32_t divisor) { return (value + divisor - 1) / divisor; }

gpu::Image storageImage(gpu::Device& device, const char* name, VkFormat format, uint32_t width, uint32_t height,
                        VkImageUsageFlags extraUsage = 0) {
  return gpu::Image(device, {name, format, width, height, 1, 1, VK_IMAGE_USAGE_STORAGE_BIT | extraUsage});
}

}  // namespace

// The tile images are sampled-capable so that the library's tests can upload them (uploadImage leaves an image ready
// to be sampled).
GatherTargets::GatherTargets(gpu::Device& device, uint32_t maxWidth, uint32_t maxHeight, uint32_t framesInFlight)
    : tileIrradiance_(storageImage(device, "ssvgi gather tile irradiance", VK_FORMAT_R16G16B16A16_SFLOAT,
                                   divideRoundingUp(maxWidth, shader::kGatherTileSize),
                                   divideRoundingUp(maxHeight, shader::kGatherTileSize), VK_IMAGE_USAGE_SAMPLED_BIT)),
      tileProbeBlend_(storageImage(device, "ssvgi gather tile probe blend", VK_FORMAT_R8_UNORM,
                                   divideRoundingUp(maxWidth, shader::kGatherTileSize),
                                   divideRoundingUp(maxHeight, shader::kGatherTileSize), VK_IMAGE_USAGE_SAMPLED_BIT)),
      // The host samples the output (Context::output()); each alternates as the other's history.
      outputs_{storageImage(device, "ssvgi gather output", VK_FORMAT_R16G16B16A16_SFLOAT, divideRoundingUp(maxWidth, 2),
                            divideRoundingUp(maxHeight, 2), VK_IMAGE_USAGE_SAMPLED_BIT),
               storageImage(device, "ssvgi gather output", VK_FORMAT_R16G16B16A16_SFLOAT, divideRoundingUp(maxWidth, 2),
                            divideRoundingUp(maxHeight, 2), VK_IMAGE_USAGE_SAMPLED_BIT)},
      // The host samples it too (Context::confidence()). R8, a storage format of Vulkan's extended set: every format
      // all devices can store takes 4 bytes a texel, and 2 MB more would break SPEC §5's 10 MB (ARCHITECTURE.md).
      confidence_(storageImage(device, "ssvgi gather confidence", VK_FORMAT_R8_UNORM, divideRoundingUp(maxWidth, 2),
                               divideRoundingUp(maxHeight, 2), VK_IMAGE_USAGE_SAMPLED_BIT)) {
  for (uint32_t i = 0; i < framesInFlight; ++i)
    constants_.emplace_back(device, "ssvgi gather constants", sizeof(shader::GatherConstants),
                            VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::HostUpload);
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
