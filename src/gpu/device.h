#pragma once
#include "vulkan_check.h"
#include "vulkan_functions.h"

#include <cstdint>
#include <map>
#include <string>

namespace ssvgi::gpu {

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

// The GPU layer's view of a device the host created: the functions every call goes through, debug names and labels,
// memory types, and the memory each named resource holds. It records into command buffers it is given and never
// creates, submits to or destroys the device; host tooling that owns its device derives from it
// (gpu_host/owned_device.h).
class Device {
 public:
  explicit Device(const ExternalDevice& external);
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_; }
  const VulkanFunctions& vk() const { return vk_; }  // every call on the device goes through these
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memoryProperties_; }

  // VK_EXT_debug_utils: names show in RenderDoc / Nsight and in validation messages. No-ops without the extension.
  void setName(VkObjectType type, uint64_t handle, const std::string& name) const;
  template <typename Handle>
  void setName(Handle handle, VkObjectType type, const std::string& name) const {
    setName(type, reinterpret_cast<uint64_t>(handle), name);
  }
  void beginLabel(VkCommandBuffer commandBuffer, const char* label) const;
  void endLabel(VkCommandBuffer commandBuffer) const;

  // Memory type for a resource: the first type allowed by `typeBits` with all of `required` flags.
  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;

  // Bytes of device memory held by each named resource, for Stats and memory budgets.
  void trackAllocation(const std::string& name, VkDeviceSize bytes);
  void untrackAllocation(const std::string& name, VkDeviceSize bytes);
  const std::map<std::string, VkDeviceSize>& allocations() const { return allocations_; }

 private:
  VulkanFunctions vk_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memoryProperties_{};

  PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT endLabel_ = nullptr;

  std::map<std::string, VkDeviceSize> allocations_;
};

}  // namespace ssvgi::gpu
