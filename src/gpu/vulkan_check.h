#pragma once
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace ssvgi::gpu {

// A Vulkan failure or a misuse of the GPU layer. Thrown inside the library's C++ code; the public API converts it to a
// status (Error, with result() as its VkResult); host tooling lets it reach its caller.
class GpuError : public std::runtime_error {
 public:
  explicit GpuError(const std::string& message, VkResult result = VK_SUCCESS)
      : std::runtime_error(message), result_(result) {}
  VkResult result() const { return result_; }  // the failed call's; VK_SUCCESS for a misuse or a missing feature

 private:
  VkResult result_;
};

const char* toString(VkResult result);

[[noreturn]] void throwVulkanError(VkResult result, const char* call, const char* file, int line);

}  // namespace ssvgi::gpu

#define VK_CHECK(call)                                                                        \
  do {                                                                                        \
    const VkResult vkCheckResult = (call);                                                    \
    if (vkCheckResult != VK_SUCCESS) ::ssvgi::gpu::throwVulkanError(vkCheckResult, #call, __FILE__, __LINE__); \
  } while (false)
