#include "transfers.h"

#include <cstring>

namespace ssvgi::gpu {

namespace {

// For the uncompressed formats ssvgi uses.
uint32_t bytesPerTexel(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R8_UNORM:
      return 1;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32:
    case VK_FORMAT_R16G16_SFLOAT:
      return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
      return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      return 16;
    default:
      throw GpuError("bytesPerTexel: unsupported format " + std::to_string(format));
  }
}

// Moves a whole image between layouts inside the blocking transfers, where the tracker is not in use.
void transitionForTransfer(VkCommandBuffer commandBuffer, const Image& image, VkImageLayout from,
                           VkImageLayout to, VkAccessFlags srcAccess, VkAccessFlags dstAccess,
                           VkPipelineStageFlags srcStage, VkPipelineStageFlags dstStage) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = dstAccess;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image.handle();
  barrier.subresourceRange = {image.aspect(), 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
  vkCmdPipelineBarrier(commandBuffer, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

VkBufferImageCopy layerCopy(const Image& image, uint32_t layer) {
  VkBufferImageCopy region{};
  region.imageSubresource = {image.aspect(), 0, layer, 1};
  region.imageExtent = {image.desc().width, image.desc().height, 1};
  return region;
}

}  // namespace

void uploadBuffer(OwnedDevice& device, const Buffer& buffer, std::span<const std::byte> data, VkDeviceSize offset) {
  if (data.empty()) return;
  if (offset + data.size() > buffer.size()) throw GpuError("upload past the end of buffer '" + buffer.name() + "'");
  Buffer staging(device, "staging upload", data.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::HostUpload);
  std::memcpy(staging.mapped(), data.data(), data.size());
  device.submitAndWait([&](VkCommandBuffer commandBuffer) {
    const VkBufferCopy region{0, offset, data.size()};
    vkCmdCopyBuffer(commandBuffer, staging.handle(), buffer.handle(), 1, &region);
    // Make the upload visible to every later use; the tracker starts from "written by a transfer".
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1,
                         &barrier, 0, nullptr, 0, nullptr);
  });
  buffer.state() = {};
}

std::vector<std::byte> readBuffer(OwnedDevice& device, const Buffer& buffer) {
  Buffer staging(device, "staging readback", buffer.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::HostReadback);
  device.submitAndWait([&](VkCommandBuffer commandBuffer) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                         &barrier, 0, nullptr, 0, nullptr);
    const VkBufferCopy region{0, 0, buffer.size()};
    vkCmdCopyBuffer(commandBuffer, buffer.handle(), staging.handle(), 1, &region);
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
  });
  std::vector<std::byte> bytes(buffer.size());
  std::memcpy(bytes.data(), staging.mapped(), bytes.size());
  return bytes;
}

void uploadImage(OwnedDevice& device, const Image& image, std::span<const std::byte> texels, uint32_t layer) {
  const ImageDesc& desc = image.desc();
  const VkDeviceSize expected = VkDeviceSize(desc.width) * desc.height * bytesPerTexel(desc.format);
  if (texels.size() != expected) throw GpuError("upload to image '" + desc.name + "' has the wrong size");
  Buffer staging(device, "staging upload", texels.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::HostUpload);
  std::memcpy(staging.mapped(), texels.data(), texels.size());
  const VkImageLayout current = image.state().layout;
  device.submitAndWait([&](VkCommandBuffer commandBuffer) {
    transitionForTransfer(commandBuffer, image, current, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                          VK_ACCESS_MEMORY_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                          VK_PIPELINE_STAGE_TRANSFER_BIT);
    const VkBufferImageCopy region = layerCopy(image, layer);
    vkCmdCopyBufferToImage(commandBuffer, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &region);
    transitionForTransfer(commandBuffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                          VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
  });
  image.state() = {};
  image.state().layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
}

std::vector<std::byte> readImage(OwnedDevice& device, const Image& image, uint32_t layer) {
  const ImageDesc& desc = image.desc();
  const VkDeviceSize size = VkDeviceSize(desc.width) * desc.height * bytesPerTexel(desc.format);
  Buffer staging(device, "staging readback", size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::HostReadback);
  const VkImageLayout current = image.state().layout;
  if (current == VK_IMAGE_LAYOUT_UNDEFINED) throw GpuError("reading image '" + desc.name + "' that was never written");
  device.submitAndWait([&](VkCommandBuffer commandBuffer) {
    transitionForTransfer(commandBuffer, image, current, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                          VK_ACCESS_MEMORY_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                          VK_PIPELINE_STAGE_TRANSFER_BIT);
    const VkBufferImageCopy region = layerCopy(image, layer);
    vkCmdCopyImageToBuffer(commandBuffer, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1,
                           &region);
    transitionForTransfer(commandBuffer, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, current, 0, 0,
                          VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
  });
  std::vector<std::byte> bytes(size);
  std::memcpy(bytes.data(), staging.mapped(), size);
  return bytes;
}

}  // namespace ssvgi::gpu
