#pragma once
#include "resources.h"

#include <vector>

namespace ssvgi::gpu {

// Collects the barriers that the next command needs, given how it uses each resource, and emits them as one
// vkCmdPipelineBarrier. Passes never write barriers by hand: they declare usages (or their pipeline does, from the
// shader's declarations) and the batch works out read-after-write, write-after-read and layout changes.
// Vulkan 1.0 barriers (not synchronization2) so that the GI passes run on Vulkan 1.1 devices (SPEC §2).
class BarrierBatch {
 public:
  void use(const Buffer& buffer, Usage usage);
  void use(const Image& image, Usage usage);
  void flush(const Device& device, VkCommandBuffer commandBuffer);
  bool empty() const { return bufferBarriers_.empty() && imageBarriers_.empty(); }

 private:
  VkPipelineStageFlags srcStages_ = 0;
  VkPipelineStageFlags dstStages_ = 0;
  std::vector<VkBufferMemoryBarrier> bufferBarriers_;
  std::vector<VkImageMemoryBarrier> imageBarriers_;
};

}  // namespace ssvgi::gpu
