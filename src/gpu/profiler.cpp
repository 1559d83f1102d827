#include "profiler.h"

#include <algorithm>

namespace ssvgi::gpu {

Profiler::Profiler(Device& device, uint32_t maxScopes) : device_(device), maxScopes_(maxScopes) {
  supported_ = device.properties().limits.timestampComputeAndGraphics == VK_TRUE;
  if (!supported_) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = maxScopes * 2;
  VK_CHECK(device.vk().vkCreateQueryPool(device.device(), &info, nullptr, &pool_));
}

Profiler::~Profiler() {
  if (pool_) device_.vk().vkDestroyQueryPool(device_.device(), pool_, nullptr);
}

namespace {
constexpr uint32_t kNestedScope = ~0u;  // a scope inside another: not timed on its own
}  // namespace

void Profiler::begin(VkCommandBuffer commandBuffer) {
  names_.clear();
  openScopes_ = 0;
  if (supported_) device_.vk().vkCmdResetQueryPool(commandBuffer, pool_, 0, maxScopes_ * 2);
}

uint32_t Profiler::beginScope(VkCommandBuffer commandBuffer, const std::string& name) {
  if (openScopes_++ > 0) return kNestedScope;
  const auto scope = static_cast<uint32_t>(names_.size());
  if (scope >= maxScopes_) throw GpuError("profiler: more than " + std::to_string(maxScopes_) + " scopes in a frame");
  names_.push_back(name);
  // Both timestamps at the bottom of the pipe: a scope measures from the completion of the work before it to the
  // completion of its own, so consecutive scopes add up to the frame.
  if (supported_)
    device_.vk().vkCmdWriteTimestamp(commandBuffer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, scope * 2);
  return scope;
}

void Profiler::endScope(VkCommandBuffer commandBuffer, uint32_t scope) {
  --openScopes_;
  if (scope != kNestedScope && supported_)
    device_.vk().vkCmdWriteTimestamp(commandBuffer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, scope * 2 + 1);
}

std::vector<PassTiming> Profiler::resolve() {
  std::vector<PassTiming> timings;
  if (!supported_ || names_.empty()) return timings;
  std::vector<uint64_t> ticks(names_.size() * 2);
  VK_CHECK(device_.vk().vkGetQueryPoolResults(device_.device(), pool_, 0, static_cast<uint32_t>(ticks.size()),
                                 ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const double nanosecondsPerTick = device_.properties().limits.timestampPeriod;
  for (size_t scope = 0; scope < names_.size(); ++scope) {
    const double milliseconds = double(ticks[scope * 2 + 1] - ticks[scope * 2]) * nanosecondsPerTick * 1e-6;
    auto existing = std::find_if(timings.begin(), timings.end(), [&](const auto& t) { return t.name == names_[scope]; });
    if (existing != timings.end()) {
      existing->milliseconds += milliseconds;
    } else {
      timings.push_back({names_[scope], milliseconds});
    }
  }
  return timings;
}

}  // namespace ssvgi::gpu
