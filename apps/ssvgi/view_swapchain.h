#pragma once
// The window's swapchain: images the size of the window's framebuffer, written by a blit (the viewer draws into an
// image of its own and copies it here), recreated when the window's size changes or the surface says it is stale.
#include "gpu_host/owned_device.h"

#include <optional>
#include <vector>

namespace ssvgi::cli {

class Swapchain {
 public:
  // Takes ownership of `surface` (created on the device's instance). Throws gpu::GpuError naming what the surface
  // lacks.
  Swapchain(gpu::OwnedDevice& device, VkSurfaceKHR surface, VkExtent2D size);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  void recreate(VkExtent2D size);
  VkExtent2D size() const { return size_; }

  // The next image to draw into, ready for the GPU (waited for on the CPU: the viewer's frames run one at a time), or
  // nothing when the swapchain no longer matches its surface (recreate it).
  std::optional<uint32_t> acquire();
  VkImage image(uint32_t index) const { return images_[index]; }
  // Shows the image, drawn and left in PRESENT_SRC_KHR by work that has finished. False: recreate the swapchain.
  bool present(uint32_t index);

 private:
  void create(VkExtent2D size, VkSwapchainKHR previous);

  gpu::OwnedDevice& device_;
  VkSurfaceKHR surface_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFence acquired_ = VK_NULL_HANDLE;
  VkExtent2D size_{};
  std::vector<VkImage> images_;
};

}  // namespace ssvgi::cli
