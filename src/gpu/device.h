#pragma once
#include "vulkan_check.h"
#include "vulkan_functions.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
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
  // Extensions beyond the ones the layer enables itself: a window's surface and swapchain (`ssvgi view`). The
  // swapchain's device functions are then in vk() (VulkanFunctions' window list).
  std::vector<std::string> instanceExtensions;
  std::vector<std::string> deviceExtensions;
};

// What `ssvgi info` prints: a device and each capability ssvgi needs, present or missing.
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

// A device someone else created (the host of the GI library): used, never destroyed.
struct ExternalDevice {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  bool debugUtils = false;  // the instance has VK_EXT_debug_utils enabled: name objects and label passes
  // The host's entry points (null: the loader's); every call on this device goes through them.
  PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr;
  PFN_vkGetDeviceProcAddr getDeviceProcAddr = nullptr;
};

// One Vulkan instance + logical device + its single graphics/compute queue. Shared by the GI library, the host renderer
// and the reference; tests share one for the whole run.
class Device {
 public:
  // Throws GpuError naming the problem: no Vulkan loader, no device, no device matching the selector, a missing feature.
  explicit Device(const DeviceDesc& desc);
  // Wraps the host's device for recording only: no queue, so submitAndWait() and the blocking transfers throw.
  explicit Device(const ExternalDevice& external);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_; }
  const VulkanFunctions& vk() const { return vk_; }  // every call on the device goes through these
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memoryProperties_; }
  std::string description() const;  // "NVIDIA H100 (discrete GPU, Vulkan 1.3.x, driver …)"
  bool isCpuDevice() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }

  // Records `record` into the device's command buffer, submits it and waits for it to finish. Not reentrant.
  void submitAndWait(const std::function<void(VkCommandBuffer)>& record);

  // VK_EXT_debug_utils: names show in RenderDoc / Nsight and in validation messages. No-ops without the extension.
  void setName(VkObjectType type, uint64_t handle, const std::string& name) const;
  template <typename Handle>
  void setName(Handle handle, VkObjectType type, const std::string& name) const {
    setName(type, reinterpret_cast<uint64_t>(handle), name);
  }
  void beginLabel(VkCommandBuffer commandBuffer, const char* label) const;
  void endLabel(VkCommandBuffer commandBuffer) const;

  // Validation messages of severity error seen so far (only with DeviceDesc::validation).
  uint32_t validationErrorCount() const { return validationErrors_.load(); }
  const std::string& lastValidationError() const { return lastValidationError_; }

  // Memory type for a resource: the first type allowed by `typeBits` with all of `required` flags.
  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;

  // Bytes of device memory held by each named resource, for Stats and memory budgets.
  void trackAllocation(const std::string& name, VkDeviceSize bytes);
  void untrackAllocation(const std::string& name, VkDeviceSize bytes);
  const std::map<std::string, VkDeviceSize>& allocations() const { return allocations_; }

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                            VkDebugUtilsMessageTypeFlagsEXT types,
                                                            const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                            void* user);

  void loadDebugUtils();

  bool owned_ = true;
  PFN_vkGetInstanceProcAddr getInstanceProcAddr_ = vkGetInstanceProcAddr;
  VulkanFunctions vk_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  VkCommandBuffer commandBuffer_ = VK_NULL_HANDLE;  // freed with the pool
  VkFence fence_ = VK_NULL_HANDLE;
  bool recording_ = false;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memoryProperties_{};
  std::string driverInfo_;

  PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT endLabel_ = nullptr;

  std::atomic<uint32_t> validationErrors_{0};
  std::string lastValidationError_;
  std::map<std::string, VkDeviceSize> allocations_;
};

}  // namespace ssvgi::gpu
