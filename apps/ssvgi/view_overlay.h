#pragma once
// Dear ImGui over an image of the viewer's: its GLFW input, and its Vulkan drawing into a colour image (RGBA8, what
// the window shows and a screenshot saves) through a render pass of its own (ImGui 1.86's Vulkan backend draws only
// inside a render pass).
#include "gpu/command_list.h"
#include "gpu_host/owned_device.h"

#include <vector>

struct GLFWwindow;

namespace ssvgi::cli {

class ImGuiOverlay {
 public:
  static constexpr VkFormat kTargetFormat = VK_FORMAT_R8G8B8A8_UNORM;

  ImGuiOverlay(gpu::OwnedDevice& device, GLFWwindow* window);
  ~ImGuiOverlay();
  ImGuiOverlay(const ImGuiOverlay&) = delete;
  ImGuiOverlay& operator=(const ImGuiOverlay&) = delete;

  // Starts a frame of ImGui calls; its input is what GLFW has seen since the last.
  void newFrame();
  // The image to draw over (kTargetFormat): given again whenever it is made anew (the window's size changed), once
  // the GPU has finished with the last one.
  void setTarget(const gpu::Image& target);
  // Ends the frame and draws it over the target.
  void record(gpu::CommandList& commands);

 private:
  gpu::OwnedDevice& device_;
  VkRenderPass renderPass_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;
  const gpu::Image* target_ = nullptr;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;  // over target_
};

}  // namespace ssvgi::cli
