#include "view_swapchain.h"

#include <algorithm>

namespace ssvgi::cli {

namespace {

// The renderer's image is already sRGB-encoded 8-bit: a UNORM swapchain takes its bytes as they are.
VkSurfaceFormatKHR chooseFormat(VkPhysicalDevice physicalDevice, VkSurfaceKHR surface) {
  uint32_t count = 0;
  VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physicalDevice, surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physicalDevice, surface, &count, formats.data()));
  for (const VkSurfaceFormatKHR& format : formats)
    if (format.format == VK_FORMAT_B8G8R8A8_UNORM || format.format == VK_FORMAT_R8G8B8A8_UNORM) return format;
  if (formats.empty()) throw gpu::GpuError("view: the window's surface offers no image format");
  return formats.front();
}

}  // namespace

Swapchain::Swapchain(gpu::OwnedDevice& device, VkSurfaceKHR surface, VkExtent2D size)
    : device_(device), surface_(surface) {
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_CHECK(vkCreateFence(device.device(), &fenceInfo, nullptr, &acquired_));
  create(size, VK_NULL_HANDLE);
}

Swapchain::~Swapchain() {
  vkDeviceWaitIdle(device_.device());
  vkDestroySwapchainKHR(device_.device(), swapchain_, nullptr);
  vkDestroyFence(device_.device(), acquired_, nullptr);
  vkDestroySurfaceKHR(device_.instance(), surface_, nullptr);
}

void Swapchain::recreate(VkExtent2D size) {
  vkDeviceWaitIdle(device_.device());
  const VkSwapchainKHR previous = swapchain_;
  create(size, previous);
  vkDestroySwapchainKHR(device_.device(), previous, nullptr);
}

void Swapchain::create(VkExtent2D size, VkSwapchainKHR previous) {
  VkSurfaceCapabilitiesKHR capabilities{};
  VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_.physicalDevice(), surface_, &capabilities));
  if (!(capabilities.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
    throw gpu::GpuError("view: the window's surface does not accept copies into its images (TRANSFER_DST)");
  // The surface's own size where it has one (0xFFFFFFFF: the swapchain decides).
  if (capabilities.currentExtent.width != 0xFFFFFFFFu) size = capabilities.currentExtent;
  size.width = std::clamp(size.width, capabilities.minImageExtent.width, capabilities.maxImageExtent.width);
  size.height = std::clamp(size.height, capabilities.minImageExtent.height, capabilities.maxImageExtent.height);
  const VkSurfaceFormatKHR format = chooseFormat(device_.physicalDevice(), surface_);

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface_;
  info.minImageCount = capabilities.maxImageCount == 0 ? capabilities.minImageCount + 1
                                                       : std::min(capabilities.minImageCount + 1, capabilities.maxImageCount);
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = size;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = capabilities.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  if (!(capabilities.supportedCompositeAlpha & info.compositeAlpha))
    info.compositeAlpha = VkCompositeAlphaFlagBitsKHR(capabilities.supportedCompositeAlpha &
                                                      ~(capabilities.supportedCompositeAlpha - 1));  // lowest bit
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // the one mode every surface has
  info.clipped = VK_TRUE;
  info.oldSwapchain = previous;
  VK_CHECK(vkCreateSwapchainKHR(device_.device(), &info, nullptr, &swapchain_));
  size_ = size;

  uint32_t count = 0;
  VK_CHECK(vkGetSwapchainImagesKHR(device_.device(), swapchain_, &count, nullptr));
  images_.resize(count);
  VK_CHECK(vkGetSwapchainImagesKHR(device_.device(), swapchain_, &count, images_.data()));
}

std::optional<uint32_t> Swapchain::acquire() {
  uint32_t index = 0;
  const VkResult result =
      vkAcquireNextImageKHR(device_.device(), swapchain_, UINT64_MAX, VK_NULL_HANDLE, acquired_, &index);
  if (result == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
  if (result != VK_SUBOPTIMAL_KHR) VK_CHECK(result);
  VK_CHECK(vkWaitForFences(device_.device(), 1, &acquired_, VK_TRUE, UINT64_MAX));
  VK_CHECK(vkResetFences(device_.device(), 1, &acquired_));
  return index;
}

bool Swapchain::present(uint32_t index) {
  VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain_;
  info.pImageIndices = &index;
  const VkResult result = vkQueuePresentKHR(device_.queue(), &info);
  if (result == VK_ERROR_OUT_OF_DATE_KHR || result == VK_SUBOPTIMAL_KHR) return false;
  VK_CHECK(result);
  return true;
}

}  // namespace ssvgi::cli
