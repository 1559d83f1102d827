#include "view_window.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>

namespace ssvgi::cli {

namespace {

// GLFW reports why a call failed through a callback; the last description becomes the error's line.
std::string& lastGlfwError() {
  static std::string error;
  return error;
}

void onGlfwError(int, const char* description) { lastGlfwError() = description; }

bool environmentSet(const char* name) {
  const char* value = std::getenv(name);
  return value && *value;
}

}  // namespace

ViewerWindow::ViewerWindow(const std::string& title, uint32_t width, uint32_t height) {
  glfwSetErrorCallback(onGlfwError);
  if (!environmentSet("DISPLAY") && !environmentSet("WAYLAND_DISPLAY"))
    throw WindowError("view: no display to open a window on (DISPLAY and WAYLAND_DISPLAY are unset); "
                      "use ssvgi render to render without a window, or run under xvfb-run");
  if (!glfwInit())
    throw WindowError("view: cannot open a window (" + lastGlfwError() +
                      "); use ssvgi render to render without a window, or run under xvfb-run");
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw WindowError("view: GLFW finds no Vulkan loader to present with (" + lastGlfwError() + ")");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw WindowError("view: cannot create a " + std::to_string(width) + "x" + std::to_string(height) + " window (" +
                      lastGlfwError() + ")");
  }
  // A key or button pressed and released between two frames still reads as pressed once: a slow frame (lavapipe)
  // must not lose a screenshot key or a click.
  glfwSetInputMode(window_, GLFW_STICKY_KEYS, GLFW_TRUE);
  glfwSetInputMode(window_, GLFW_STICKY_MOUSE_BUTTONS, GLFW_TRUE);
  glfwSetWindowUserPointer(window_, this);
  // Installed before ImGui's, which calls it after its own.
  glfwSetScrollCallback(window_, [](GLFWwindow* window, double, double y) {
    static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window))->scroll_ += y;
  });
}

ViewerWindow::~ViewerWindow() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

std::vector<std::string> ViewerWindow::requiredInstanceExtensions() {
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  return std::vector<std::string>(names, names + count);
}

VkSurfaceKHR ViewerWindow::createSurface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  if (glfwCreateWindowSurface(instance, window_, nullptr, &surface) != VK_SUCCESS)
    throw WindowError("view: cannot create a Vulkan surface for the window (" + lastGlfwError() + ")");
  return surface;
}

bool ViewerWindow::canPresent(VkInstance instance, VkPhysicalDevice physicalDevice, uint32_t queueFamily) const {
  return glfwGetPhysicalDevicePresentationSupport(instance, physicalDevice, queueFamily) == GLFW_TRUE;
}

bool ViewerWindow::closeRequested() const { return glfwWindowShouldClose(window_); }
void ViewerWindow::requestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

VkExtent2D ViewerWindow::framebufferSize() const {
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  return {uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0))};
}

void ViewerWindow::pollEvents() { glfwPollEvents(); }
void ViewerWindow::waitEvents() { glfwWaitEvents(); }

bool ViewerWindow::keyDown(int key) const { return glfwGetKey(window_, key) == GLFW_PRESS; }

bool ViewerWindow::keyPressed(int key) {
  const bool down = keyDown(key);
  const auto seen = std::find(keysDown_.begin(), keysDown_.end(), key);
  if (!down) {
    if (seen != keysDown_.end()) keysDown_.erase(seen);
    return false;
  }
  if (seen != keysDown_.end()) return false;
  keysDown_.push_back(key);
  return true;
}

bool ViewerWindow::mouseButtonDown(int button) const { return glfwGetMouseButton(window_, button) == GLFW_PRESS; }

glm::dvec2 ViewerWindow::cursorPosition() const {
  glm::dvec2 position{0.0};
  glfwGetCursorPos(window_, &position.x, &position.y);
  return position;
}

double ViewerWindow::takeScroll() {
  const double scroll = scroll_;
  scroll_ = 0.0;
  return scroll;
}

}  // namespace ssvgi::cli
