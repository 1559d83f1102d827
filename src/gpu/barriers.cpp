#include "barriers.h"

namespace ssvgi::gpu {

namespace {

struct UsageInfo {
  VkPipelineStageFlags stages;
  VkAccessFlags access;
  VkImageLayout layout;
  bool writes;
};

UsageInfo describe(Usage usage) {
  constexpr VkPipelineStageFlags kGraphicsShaders =
      VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
  switch (usage) {
    case Usage::ComputeRead:
      return {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT, VK_IMAGE_LAYOUT_GENERAL, false};
    case Usage::ComputeWrite:
      return {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
              VK_IMAGE_LAYOUT_GENERAL, true};
    case Usage::ComputeSampled:
      return {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
              false};
    case Usage::GraphicsRead:
      return {kGraphicsShaders, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_UNIFORM_READ_BIT, VK_IMAGE_LAYOUT_GENERAL, false};
    case Usage::FragmentSampled:
      return {VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
              false};
    case Usage::VertexInput:
      return {VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT,
              VK_IMAGE_LAYOUT_UNDEFINED, false};
    case Usage::IndirectArgument:
      return {VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, VK_ACCESS_INDIRECT_COMMAND_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED, false};
    case Usage::ColorAttachment:
      return {VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
              VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
              VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, true};
    case Usage::DepthAttachment:
      return {VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
              VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, true};
    case Usage::TransferSource:
      return {VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, false};
    case Usage::TransferDestination:
      return {VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, true};
    case Usage::HostRead:
      return {VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT, VK_IMAGE_LAYOUT_GENERAL, false};
  }
  return {};
}

// Decides the barrier for one resource and updates its state. Returns false when no barrier is needed.
bool transition(ResourceState& state, const UsageInfo& next, bool isImage, VkPipelineStageFlags& srcStages,
                VkAccessFlags& srcAccess) {
  const bool layoutChange = isImage && state.layout != next.layout;
  bool needed = false;
  srcStages = 0;
  srcAccess = 0;
  if (next.writes || layoutChange) {
    // A write (or a layout change, which is one) waits for the last write and for every read since.
    srcStages = state.writeStages | state.readStages;
    srcAccess = state.writeAccess;
    needed = srcStages != 0 || layoutChange;
    state.writeStages = next.writes ? next.stages : 0;
    state.writeAccess = next.writes ? (next.access & (VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                                      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                                      VK_ACCESS_TRANSFER_WRITE_BIT))
                                     : 0;
    if (layoutChange && !next.writes) {
      // A layout transition is a write: readers after it wait for it through this barrier, the later ones through
      // the recorded transition stage.
      state.writeStages = next.stages;
      state.writeAccess = 0;
    }
    state.readStages = next.writes ? 0 : next.stages;
    state.readAccess = next.writes ? 0 : next.access;
  } else {
    // A read waits only for the last write, once per reading stage/access.
    const bool alreadyVisible = (state.readStages & next.stages) == next.stages &&
                                (state.readAccess & next.access) == next.access;
    if (state.writeStages != 0 && !alreadyVisible) {
      srcStages = state.writeStages;
      srcAccess = state.writeAccess;
      needed = true;
    }
    state.readStages |= next.stages;
    state.readAccess |= next.access;
  }
  if (isImage) state.layout = next.layout;
  return needed;
}

}  // namespace

void BarrierBatch::use(const Buffer& buffer, Usage usage) {
  const UsageInfo next = describe(usage);
  VkPipelineStageFlags srcStages = 0;
  VkAccessFlags srcAccess = 0;
  if (!transition(buffer.state(), next, false, srcStages, srcAccess)) return;
  VkBufferMemoryBarrier barrier{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = next.access;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.buffer = buffer.handle();
  barrier.size = VK_WHOLE_SIZE;
  bufferBarriers_.push_back(barrier);
  srcStages_ |= srcStages;
  dstStages_ |= next.stages;
}

void BarrierBatch::use(const Image& image, Usage usage) {
  const UsageInfo next = describe(usage);
  const VkImageLayout oldLayout = image.state().layout;
  VkPipelineStageFlags srcStages = 0;
  VkAccessFlags srcAccess = 0;
  if (!transition(image.state(), next, true, srcStages, srcAccess)) return;
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = next.access;
  barrier.oldLayout = oldLayout;
  barrier.newLayout = next.layout;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image.handle();
  barrier.subresourceRange = {image.aspect(), 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
  imageBarriers_.push_back(barrier);
  srcStages_ |= srcStages;
  dstStages_ |= next.stages;
}

void BarrierBatch::flush(const Device& device, VkCommandBuffer commandBuffer) {
  if (bufferBarriers_.empty() && imageBarriers_.empty()) return;
  const VkPipelineStageFlags src = srcStages_ != 0 ? srcStages_ : VkPipelineStageFlags(VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT);
  device.vk().vkCmdPipelineBarrier(commandBuffer, src, dstStages_, 0, 0, nullptr,
                                   static_cast<uint32_t>(bufferBarriers_.size()), bufferBarriers_.data(),
                                   static_cast<uint32_t>(imageBarriers_.size()), imageBarriers_.data());
  bufferBarriers_.clear();
  imageBarriers_.clear();
  srcStages_ = 0;
  dstStages_ = 0;
}

}  // namespace ssvgi::gpu
