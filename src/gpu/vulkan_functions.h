#pragma once
#include <vulkan/vulkan.h>

namespace ssvgi::gpu {

// The Vulkan functions the GPU layer calls on a device — those and no others — looked up through the entry points a
// host gives (ContextDesc::vkGetInstanceProcAddr/vkGetDeviceProcAddr) or the loader's, so that a host that loads
// Vulkan itself has every call of ssvgi's go where its own go. Device-level functions come from vkGetDeviceProcAddr:
// they skip the loader's trampoline. Host tooling, which creates its own device, calls the loader directly.
#define SSVGI_VULKAN_INSTANCE_FUNCTIONS(X) \
  X(vkGetPhysicalDeviceProperties)         \
  X(vkGetPhysicalDeviceMemoryProperties)   \
  X(vkGetPhysicalDeviceFormatProperties)

#define SSVGI_VULKAN_DEVICE_FUNCTIONS(X) \
  X(vkAllocateDescriptorSets)            \
  X(vkAllocateMemory)                    \
  X(vkBindBufferMemory)                  \
  X(vkBindImageMemory)                   \
  X(vkCmdBindDescriptorSets)             \
  X(vkCmdBindPipeline)                   \
  X(vkCmdClearColorImage)                \
  X(vkCmdCopyBuffer)                     \
  X(vkCmdDispatch)                       \
  X(vkCmdDispatchIndirect)               \
  X(vkCmdFillBuffer)                     \
  X(vkCmdPipelineBarrier)                \
  X(vkCmdPushConstants)                  \
  X(vkCmdResetQueryPool)                 \
  X(vkCmdUpdateBuffer)                   \
  X(vkCmdWriteTimestamp)                 \
  X(vkCreateBuffer)                      \
  X(vkCreateComputePipelines)            \
  X(vkCreateDescriptorPool)              \
  X(vkCreateDescriptorSetLayout)         \
  X(vkCreateImage)                       \
  X(vkCreateImageView)                   \
  X(vkCreatePipelineLayout)              \
  X(vkCreateQueryPool)                   \
  X(vkCreateSampler)                     \
  X(vkCreateShaderModule)                \
  X(vkDestroyBuffer)                     \
  X(vkDestroyDescriptorPool)             \
  X(vkDestroyDescriptorSetLayout)        \
  X(vkDestroyImage)                      \
  X(vkDestroyImageView)                  \
  X(vkDestroyPipeline)                   \
  X(vkDestroyPipelineLayout)             \
  X(vkDestroyQueryPool)                  \
  X(vkDestroySampler)                    \
  X(vkDestroyShaderModule)               \
  X(vkFreeMemory)                        \
  X(vkGetBufferMemoryRequirements)       \
  X(vkGetImageMemoryRequirements)        \
  X(vkGetQueryPoolResults)               \
  X(vkMapMemory)                         \
  X(vkResetDescriptorPool)               \
  X(vkUpdateDescriptorSets)

struct VulkanFunctions {
#define SSVGI_VULKAN_FUNCTION_MEMBER(name) PFN_##name name = nullptr;
  SSVGI_VULKAN_INSTANCE_FUNCTIONS(SSVGI_VULKAN_FUNCTION_MEMBER)
  SSVGI_VULKAN_DEVICE_FUNCTIONS(SSVGI_VULKAN_FUNCTION_MEMBER)
#undef SSVGI_VULKAN_FUNCTION_MEMBER
};

// Looks up every function; a null getDeviceProcAddr is looked up through getInstanceProcAddr. Throws GpuError naming
// a function that is not found.
VulkanFunctions loadVulkanFunctions(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance,
                                    PFN_vkGetDeviceProcAddr getDeviceProcAddr, VkDevice device);

}  // namespace ssvgi::gpu
