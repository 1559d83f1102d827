#pragma once
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace ssvgi::gpu {

// A Vulkan failure or a misuse of the GPU layer. Thrown inside the host-side code; the public API converts it to a
// status, the CLI prints what() as its one error line.
class GpuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* toString(VkResult result);

[[noreturn]] void throwVulkanError(VkResult result, const char* call, const char* file, int line);

}  // namespace ssvgi::gpu

#define VK_CHECK(call)                                                                        \
  do {                                                                                        \
    const VkResult vkCheckResult = (call);                                                    \
    if (vkCheckResult != VK_SUCCESS) ::ssvgi::gpu::throwVulkanError(vkCheckResult, #call, __FILE__, __LINE__); \
  } while (false)
