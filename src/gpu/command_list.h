#pragma once
#include "barriers.h"
#include "pipelines.h"
#include "profiler.h"

#include <glm/vec3.hpp>

#include <string>

namespace ssvgi::gpu {

// Records compute work into a command buffer someone else owns (the host's, for the GI library): labelled and timed
// scopes, dispatches whose barriers are derived from their bindings, and the few transfers the passes need. Host
// tooling adds drawing and blits (gpu_host/host_command_list.h).
class CommandList {
 public:
  CommandList(Device& device, VkCommandBuffer commandBuffer, DescriptorArena& descriptors, Profiler* profiler = nullptr);

  VkCommandBuffer handle() const { return commandBuffer_; }
  Device& device() const { return device_; }

  // A debug label (VK_EXT_debug_utils) and a profiler scope around the commands recorded while it lives.
  class Scope {
   public:
    Scope(CommandList& list, const std::string& label);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    CommandList& list_;
    uint32_t profilerScope_ = 0;
  };
  Scope scope(const std::string& label) { return Scope(*this, label); }

  void use(const Buffer& buffer, Usage usage) { barriers_.use(buffer, usage); }
  void use(const Image& image, Usage usage) { barriers_.use(image, usage); }
  void flushBarriers() { barriers_.flush(device_, commandBuffer_); }
  // A colour image someone else owns, moved from `currentLayout` to `layout` for this command list's compute work.
  void useExternalImage(VkImage image, VkImageLayout currentLayout, VkImageLayout layout);

  // One thread per element of `threads`; group counts come from the shader's local size.
  void dispatch(const ComputePipeline& pipeline, const Bindings& bindings, glm::uvec3 threads, const void* push = nullptr,
                size_t pushBytes = 0);
  template <typename Push>
  void dispatch(const ComputePipeline& pipeline, const Bindings& bindings, glm::uvec3 threads, const Push& push) {
    dispatch(pipeline, bindings, threads, &push, sizeof(Push));
  }
  // Group counts read from `arguments` (VkDispatchIndirectCommand at `offset`).
  void dispatchIndirect(const ComputePipeline& pipeline, const Bindings& bindings, const Buffer& arguments,
                        VkDeviceSize offset, const void* push = nullptr, size_t pushBytes = 0);

  void pushConstants(const PipelineLayout& layout, const void* data, size_t bytes);

  void fillBuffer(const Buffer& buffer, uint32_t value);
  // Small inline writes (≤ 64 KiB, a multiple of 4 bytes), recorded into the command buffer.
  void updateBuffer(const Buffer& buffer, VkDeviceSize offset, const void* data, VkDeviceSize bytes);
  void copyBuffer(const Buffer& source, const Buffer& destination, VkDeviceSize bytes);
  void clearImage(const Image& image, const VkClearColorValue& value);

 protected:
  // Writes a descriptor set for `bindings` as `layout` reflects them and declares each resource's usage: a compute
  // shader's, or else a vertex or fragment shader's.
  VkDescriptorSet writeDescriptors(const PipelineLayout& layout, const std::string& name, const Bindings& bindings,
                                   bool compute);
  bool barriersPending() const { return !barriers_.empty(); }

 private:
  void bindCompute(const ComputePipeline& pipeline, const Bindings& bindings, const void* push, size_t pushBytes);

  Device& device_;
  VkCommandBuffer commandBuffer_;
  DescriptorArena& descriptors_;
  Profiler* profiler_;
  BarrierBatch barriers_;
};

}  // namespace ssvgi::gpu
