#include "device.h"

#include <algorithm>
#include <sstream>

namespace ssvgi::gpu {

const char* toString(VkResult result) {
  switch (result) {
#define SSVGI_RESULT_CASE(name) \
  case name:                    \
    return #name;
    SSVGI_RESULT_CASE(VK_SUCCESS)
    SSVGI_RESULT_CASE(VK_NOT_READY)
    SSVGI_RESULT_CASE(VK_TIMEOUT)
    SSVGI_RESULT_CASE(VK_INCOMPLETE)
    SSVGI_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    SSVGI_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    SSVGI_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    SSVGI_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    SSVGI_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    SSVGI_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    SSVGI_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    SSVGI_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    SSVGI_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    SSVGI_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    SSVGI_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    SSVGI_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
#undef SSVGI_RESULT_CASE
    default:
      return "VkResult(unknown)";
  }
}

void throwVulkanError(VkResult result, const char* call, const char* file, int line) {
  std::ostringstream message;
  message << "Vulkan call failed with " << toString(result) << ": " << call << " (" << file << ":" << line << ")";
  throw GpuError(message.str(), result);
}

Device::Device(const ExternalDevice& external)
    : instance_(external.instance), physicalDevice_(external.physicalDevice), device_(external.device) {
  if (!instance_ || !physicalDevice_ || !device_) throw GpuError("an external device needs instance, physical device and device");
  const PFN_vkGetInstanceProcAddr getInstanceProcAddr =
      external.getInstanceProcAddr ? external.getInstanceProcAddr : vkGetInstanceProcAddr;
  vk_ = loadVulkanFunctions(getInstanceProcAddr, instance_, external.getDeviceProcAddr, device_);
  vk_.vkGetPhysicalDeviceProperties(physicalDevice_, &properties_);
  vk_.vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);
  if (external.debugUtils) {
    setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        getInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
    beginLabel_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        getInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
    endLabel_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        getInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
  }
}

void Device::setName(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!setObjectName_) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  setObjectName_(device_, &info);
}

void Device::beginLabel(VkCommandBuffer commandBuffer, const char* label) const {
  if (!beginLabel_) return;
  VkDebugUtilsLabelEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
  info.pLabelName = label;
  beginLabel_(commandBuffer, &info);
}

void Device::endLabel(VkCommandBuffer commandBuffer) const {
  if (endLabel_) endLabel_(commandBuffer);
}

uint32_t Device::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
  for (uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
    if ((typeBits & (1u << i)) && (memoryProperties_.memoryTypes[i].propertyFlags & required) == required) return i;
  }
  throw GpuError("no Vulkan memory type with the required properties");
}

void Device::trackAllocation(const std::string& name, VkDeviceSize bytes) { allocations_[name] += bytes; }

void Device::untrackAllocation(const std::string& name, VkDeviceSize bytes) {
  auto it = allocations_.find(name);
  if (it == allocations_.end()) return;
  it->second -= std::min(it->second, bytes);
  if (it->second == 0) allocations_.erase(it);
}

}  // namespace ssvgi::gpu
