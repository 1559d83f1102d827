#pragma once
#include "device.h"

#include <string>
#include <vector>

namespace ssvgi::gpu {

struct PassTiming {
  std::string name;
  double milliseconds = 0.0;  // summed over the frame's scopes of that name
};

// GPU timestamps around labelled passes. One frame at a time: begin() in the command buffer, scopes, then resolve()
// after the submission has completed. Only outermost scopes are timed: a scope opened inside another (the passes of an
// extra view inside "ssvgi: ExtraViews") counts towards the outer one alone, so that the timings add up to the frame
// without counting any work twice.
class Profiler {
 public:
  explicit Profiler(Device& device, uint32_t maxScopes = 256);
  ~Profiler();
  Profiler(const Profiler&) = delete;
  Profiler& operator=(const Profiler&) = delete;

  bool supported() const { return supported_; }
  void begin(VkCommandBuffer commandBuffer);
  // Returns the scope's handle for endScope().
  uint32_t beginScope(VkCommandBuffer commandBuffer, const std::string& name);
  void endScope(VkCommandBuffer commandBuffer, uint32_t scope);
  // The passes of the last frame in the order they first began. Empty when timestamps are unsupported.
  std::vector<PassTiming> resolve();

 private:
  Device& device_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t maxScopes_ = 0;
  bool supported_ = false;
  std::vector<std::string> names_;
  uint32_t openScopes_ = 0;
};

}  // namespace ssvgi::gpu
