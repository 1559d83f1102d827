#pragma once
#include <vulkan/vulkan.h>

namespace ssvgi::gpu {

// The Vulkan functions the GPU layer calls on a device, looked up through the entry points a host gives
// (ContextDesc::vkGetInstanceProcAddr/vkGetDeviceProcAddr) or the loader's, so that a host that loads Vulkan itself has
// every call of ssvgi's go where its own go. Device-level functions come from vkGetDeviceProcAddr: they skip the
// loader's trampoline. Creating and submitting on a device of its own (Device(DeviceDesc)) is host tooling, which
// calls the loader directly.
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
  X(vkCmdBeginRenderPass)                \
  X(vkCmdBindPipeline)                   \
  X(vkCmdBlitImage)                      \
  X(vkCmdClearColorImage)                \
  X(vkCmdCopyBuffer)                     \
  X(vkCmdCopyBufferToImage)              \
  X(vkCmdCopyImageToBuffer)              \
  X(vkCmdDispatch)                       \
  X(vkCmdDispatchIndirect)               \
  X(vkCmdEndRenderPass)                  \
  X(vkCmdFillBuffer)                     \
  X(vkCmdPipelineBarrier)                \
  X(vkCmdPushConstants)                  \
  X(vkCmdResetQueryPool)                 \
  X(vkCmdSetScissor)                     \
  X(vkCmdSetViewport)                    \
  X(vkCmdUpdateBuffer)                   \
  X(vkCmdWriteTimestamp)                 \
  X(vkCreateBuffer)                      \
  X(vkCreateComputePipelines)            \
  X(vkCreateDescriptorPool)              \
  X(vkCreateDescriptorSetLayout)         \
  X(vkCreateFence)                       \
  X(vkCreateFramebuffer)                 \
  X(vkCreateGraphicsPipelines)           \
  X(vkCreateImage)                       \
  X(vkCreateImageView)                   \
  X(vkCreatePipelineLayout)              \
  X(vkCreateQueryPool)                   \
  X(vkCreateRenderPass)                  \
  X(vkCreateSampler)                     \
  X(vkCreateShaderModule)                \
  X(vkDestroyBuffer)                     \
  X(vkDestroyDescriptorPool)             \
  X(vkDestroyDescriptorSetLayout)        \
  X(vkDestroyFence)                      \
  X(vkDestroyFramebuffer)                \
  X(vkDestroyImage)                      \
  X(vkDestroyImageView)                  \
  X(vkDestroyPipeline)                   \
  X(vkDestroyPipelineLayout)             \
  X(vkDestroyQueryPool)                  \
  X(vkDestroyRenderPass)                 \
  X(vkDestroySampler)                    \
  X(vkDestroyShaderModule)               \
  X(vkFreeMemory)                        \
  X(vkGetBufferMemoryRequirements)       \
  X(vkGetImageMemoryRequirements)        \
  X(vkGetQueryPoolResults)               \
  X(vkMapMemory)                         \
  X(vkResetDescriptorPool)               \
  X(vkResetFences)                       \
  X(vkUpdateDescriptorSets)              \
  X(vkWaitForFences)

// Core in Vulkan 1.3, used only by the host renderer's graphics passes: null on a Vulkan 1.1 or 1.2 device, which the
// GI library accepts.
#define SSVGI_VULKAN_DEVICE_FUNCTIONS_1_3(X) \
  X(vkCmdBeginRendering)                     \
  X(vkCmdEndRendering)

// VK_KHR_swapchain, for a window (`ssvgi view`, DeviceDesc::deviceExtensions): null on a device without it.
#define SSVGI_VULKAN_DEVICE_FUNCTIONS_SWAPCHAIN(X) \
  X(vkAcquireNextImageKHR)                         \
  X(vkCreateSwapchainKHR)                          \
  X(vkDestroySwapchainKHR)                         \
  X(vkGetSwapchainImagesKHR)                       \
  X(vkQueuePresentKHR)

struct VulkanFunctions {
#define SSVGI_VULKAN_FUNCTION_MEMBER(name) PFN_##name name = nullptr;
  SSVGI_VULKAN_INSTANCE_FUNCTIONS(SSVGI_VULKAN_FUNCTION_MEMBER)
  SSVGI_VULKAN_DEVICE_FUNCTIONS(SSVGI_VULKAN_FUNCTION_MEMBER)
  SSVGI_VULKAN_DEVICE_FUNCTIONS_1_3(SSVGI_VULKAN_FUNCTION_MEMBER)
  SSVGI_VULKAN_DEVICE_FUNCTIONS_SWAPCHAIN(SSVGI_VULKAN_FUNCTION_MEMBER)
#undef SSVGI_VULKAN_FUNCTION_MEMBER
};

// Looks up every function; a null getDeviceProcAddr is looked up through getInstanceProcAddr. Throws GpuError naming
// a function of the first two lists that is not found.
VulkanFunctions loadVulkanFunctions(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance,
                                    PFN_vkGetDeviceProcAddr getDeviceProcAddr, VkDevice device);

}  // namespace ssvgi::gpu
