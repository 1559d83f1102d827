#pragma once
#include "gpu/device.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ssvgi::gpu {

struct DeviceDesc {
  // "auto": a discrete GPU, else an integrated one, else any other, else a CPU device (lavapipe).
  // "gpu": a discrete or integrated GPU, an error if there is none. "cpu": a CPU device. "0", "1", …: that index in
  // `listDevices()`.
  std::string selector = "auto";
  bool validation = false;  // enable VK_LAYER_KHRONOS_validation and count its errors (tests always do)
  // Extensions beyond the ones the layer enables itself: a window's surface and swapchain.
  std::vector<std::string> instanceExtensions;
  std::vector<std::string> deviceExtensions;
};

// A device and each capability ssvgi's tools need, present or missing.
struct DeviceCapability {
  std::string name;
  bool present = false;
  bool required = true;
};
struct DeviceReport {
  uint32_t index = 0;
  std::string name;
  std::string type;  // "discrete GPU", "integrated GPU", "CPU", …
  std::string apiVersion;
  std::string driver;
  std::vector<DeviceCapability> capabilities;
  bool usable() const;
};
std::vector<DeviceReport> listDevices();

// A DeviceDesc::selector that picks no usable device. reason() is the message without the selector, for a caller that
// names the selector in its own terms (a command-line option).
class DeviceSelectionError : public GpuError {
 public:
  DeviceSelectionError(const std::string& selector, const std::string& reason)
      : GpuError("device selector '" + selector + "': " + reason), reason_(reason) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// A Vulkan instance + logical device + its single graphics/compute queue that the program creates, owns and submits
// to: the host renderer's, the reference's, the tools' and the tests' (which share one for the whole run). The GI
// library is only ever given the Device part.
class OwnedDevice : public Device {
 public:
  // Throws GpuError naming the problem: no Vulkan loader, no device, a missing feature; DeviceSelectionError when no
  // usable device matches the selector.
  explicit OwnedDevice(const DeviceDesc& desc);
  ~OwnedDevice();

  VkQueue queue() const;
  uint32_t queueFamily() const;
  std::string description() const;  // "NVIDIA H100 (discrete GPU, Vulkan 1.3.x, driver …)"

  // Records `record` into the device's command buffer, submits it and waits for it to finish. Not reentrant.
  void submitAndWait(const std::function<void(VkCommandBuffer)>& record);

  // Validation messages of severity error seen so far (only with DeviceDesc::validation).
  uint32_t validationErrorCount() const;
  const std::string& lastValidationError() const;

 private:
  struct Created;  // the instance, device and queue, destroyed with it
  static std::unique_ptr<Created> create(const DeviceDesc& desc);
  explicit OwnedDevice(std::unique_ptr<Created> created);

  std::unique_ptr<Created> created_;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  VkCommandBuffer commandBuffer_ = VK_NULL_HANDLE;  // freed with the pool
  VkFence fence_ = VK_NULL_HANDLE;
  bool recording_ = false;
};

}  // namespace ssvgi::gpu
