#pragma once
// The viewer's window (GLFW): opening it, or one line saying why it cannot be opened; its surface; the input the fly
// camera reads.
#include <vulkan/vulkan.h>

#include <glm/vec2.hpp>

#include <stdexcept>
#include <string>
#include <vector>

struct GLFWwindow;

namespace ssvgi::cli {

// The window could not be opened (no display, no Vulkan presentation): what() is one line naming the problem.
class WindowError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ViewerWindow {
 public:
  // Throws WindowError when there is no display to open a window on, or GLFW finds no Vulkan.
  ViewerWindow(const std::string& title, uint32_t width, uint32_t height);
  ~ViewerWindow();
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  GLFWwindow* handle() const { return window_; }
  // What a Vulkan instance needs to present to this window (VK_KHR_surface and the platform's).
  static std::vector<std::string> requiredInstanceExtensions();
  VkSurfaceKHR createSurface(VkInstance instance) const;
  bool canPresent(VkInstance instance, VkPhysicalDevice physicalDevice, uint32_t queueFamily) const;

  bool closeRequested() const;
  void requestClose();
  // The framebuffer's size in pixels; zero while the window is minimised.
  VkExtent2D framebufferSize() const;
  void pollEvents();
  // Sleeps until an event arrives: while minimised there is nothing to draw.
  void waitEvents();

  bool keyDown(int key) const;
  // True once per press (for actions such as a screenshot).
  bool keyPressed(int key);
  bool mouseButtonDown(int button) const;
  glm::dvec2 cursorPosition() const;
  // The wheel's movement since the last call.
  double takeScroll();

 private:
  GLFWwindow* window_ = nullptr;
  double scroll_ = 0.0;
  std::vector<int> keysDown_;  // keys seen down at the last keyPressed() of each
};

}  // namespace ssvgi::cli
