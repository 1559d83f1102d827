#include "host_command_list.h"

namespace ssvgi::gpu {

void HostCommandList::beginRendering(const std::vector<Attachment>& colors, const Attachment& depth) {
  const Image* any = depth.image ? depth.image : colors.at(0).image;
  const uint32_t width = any->desc().width;
  const uint32_t height = any->desc().height;
  std::vector<VkRenderingAttachmentInfo> colorInfos;
  for (const Attachment& color : colors) {
    use(*color.image, Usage::ColorAttachment);
    VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    info.imageView = color.image->layerView(color.layer);
    info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    info.clearValue = color.clear;
    colorInfos.push_back(info);
  }
  VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  if (depth.image) {
    use(*depth.image, Usage::DepthAttachment);
    depthInfo.imageView = depth.image->layerView(depth.layer);
    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depthInfo.clearValue = depth.clear;
  }
  flushBarriers();
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, {width, height}};
  info.layerCount = 1;
  info.colorAttachmentCount = static_cast<uint32_t>(colorInfos.size());
  info.pColorAttachments = colorInfos.data();
  info.pDepthAttachment = depth.image ? &depthInfo : nullptr;
  vkCmdBeginRendering(handle(), &info);
  rendering_ = true;
  const VkViewport viewport{0.0f, float(height), float(width), -float(height), 0.0f, 1.0f};
  vkCmdSetViewport(handle(), 0, 1, &viewport);
  const VkRect2D scissor{{0, 0}, {width, height}};
  vkCmdSetScissor(handle(), 0, 1, &scissor);
}

void HostCommandList::endRendering() {
  vkCmdEndRendering(handle());
  rendering_ = false;
}

void HostCommandList::bindGraphics(const GraphicsPipeline& pipeline, const Bindings& bindings) {
  const VkDescriptorSet set = writeDescriptors(pipeline.layout(), pipeline.name(), bindings, false);
  if (rendering_ && barriersPending())
    throw GpuError(pipeline.name() + ": a binding needs a barrier inside rendering; declare its usage before beginRendering");
  flushBarriers();
  vkCmdBindPipeline(handle(), VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  if (set) {
    vkCmdBindDescriptorSets(handle(), VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout().handle(), 0, 1, &set, 0,
                            nullptr);
  }
}

namespace {

VkImageBlit wholeImageBlit(VkExtent2D sourceSize, VkExtent2D destinationSize) {
  VkImageBlit region{};
  region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.srcOffsets[1] = {int32_t(sourceSize.width), int32_t(sourceSize.height), 1};
  region.dstOffsets[1] = {int32_t(destinationSize.width), int32_t(destinationSize.height), 1};
  return region;
}

VkExtent2D sizeOf(const Image& image) { return {image.desc().width, image.desc().height}; }

}  // namespace

void HostCommandList::blitImage(const Image& source, const Image& destination) {
  use(source, Usage::TransferSource);
  use(destination, Usage::TransferDestination);
  flushBarriers();
  const VkImageBlit region = wholeImageBlit(sizeOf(source), sizeOf(destination));
  vkCmdBlitImage(handle(), source.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, destination.handle(),
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_NEAREST);
}

void HostCommandList::blitToExternalImage(const Image& source, VkImage destination, VkExtent2D destinationSize,
                                      VkImageLayout currentLayout, VkImageLayout finalLayout) {
  use(source, Usage::TransferSource);
  flushBarriers();
  // The owner's earlier use is unknown: wait for all of it, and let all later work wait for the blit.
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.oldLayout = currentLayout;
  barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = destination;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(handle(), VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &barrier);
  const VkImageBlit region = wholeImageBlit(sizeOf(source), destinationSize);
  vkCmdBlitImage(handle(), source.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, destination,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_NEAREST);
  barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT;
  barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  barrier.newLayout = finalLayout;
  vkCmdPipelineBarrier(handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &barrier);
}

}  // namespace ssvgi::gpu
