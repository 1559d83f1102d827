#include "vulkan_functions.h"

#include "vulkan_check.h"

#include <string>

namespace ssvgi::gpu {

VulkanFunctions loadVulkanFunctions(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance,
                                    PFN_vkGetDeviceProcAddr getDeviceProcAddr, VkDevice device) {
  if (!getDeviceProcAddr)
    getDeviceProcAddr =
        reinterpret_cast<PFN_vkGetDeviceProcAddr>(getInstanceProcAddr(instance, "vkGetDeviceProcAddr"));
  if (!getDeviceProcAddr) throw GpuError("vkGetInstanceProcAddr found no vkGetDeviceProcAddr");
  VulkanFunctions functions;
#define SSVGI_LOAD_REQUIRED(name, lookup, handle)                                             \
  functions.name = reinterpret_cast<PFN_##name>(lookup(handle, #name));                       \
  if (!functions.name) throw GpuError(std::string(#lookup) + " found no " #name);
#define SSVGI_LOAD_INSTANCE(name) SSVGI_LOAD_REQUIRED(name, getInstanceProcAddr, instance)
#define SSVGI_LOAD_DEVICE(name) SSVGI_LOAD_REQUIRED(name, getDeviceProcAddr, device)
  SSVGI_VULKAN_INSTANCE_FUNCTIONS(SSVGI_LOAD_INSTANCE)
  SSVGI_VULKAN_DEVICE_FUNCTIONS(SSVGI_LOAD_DEVICE)
#undef SSVGI_LOAD_DEVICE
#undef SSVGI_LOAD_INSTANCE
#undef SSVGI_LOAD_REQUIRED
  return functions;
}

}  // namespace ssvgi::gpu
