#pragma once
#include "barriers.h"
#include "pipelines.h"
#include "profiler.h"

#include <glm/vec3.hpp>

#include <string>

namespace ssvgi::gpu {

// Records GPU work into a command buffer someone else owns (the host's, for the GI library): labelled and timed
// scopes, dispatches and draws whose barriers are derived from their bindings, and the few transfers we need.
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

  // Dynamic rendering into whole images (or one layer of each). Declares the attachment usages, flushes barriers,
  // sets a viewport with negative height so that NDC +y is up (as in our projection matrices) and a full scissor.
  struct Attachment {
    const Image* image = nullptr;
    uint32_t layer = 0;
    VkClearValue clear{};
  };
  void beginRendering(const std::vector<Attachment>& colors, const Attachment& depth);
  void endRendering();

  // Binds a graphics pipeline and its set 0. Inside rendering no barrier can be recorded, so every resource the
  // bindings use must already be in its usage: declare them with use() before beginRendering.
  void bindGraphics(const GraphicsPipeline& pipeline, const Bindings& bindings);
  void pushConstants(const PipelineLayout& layout, const void* data, size_t bytes);

  void fillBuffer(const Buffer& buffer, uint32_t value);
  // Small inline writes (≤ 64 KiB, a multiple of 4 bytes), recorded into the command buffer.
  void updateBuffer(const Buffer& buffer, VkDeviceSize offset, const void* data, VkDeviceSize bytes);
  void copyBuffer(const Buffer& source, const Buffer& destination, VkDeviceSize bytes);
  void clearImage(const Image& image, const VkClearColorValue& value);
  // Copies a colour image's mip 0, layer 0 into another's, scaled to its size (nearest texel: exact at equal sizes)
  // and converted to its format (vkCmdBlitImage).
  void blitImage(const Image& source, const Image& destination);
  // The same into a colour image someone else owns (a swapchain's), in `currentLayout` before and left in
  // `finalLayout` for its owner, all of this command list's earlier work on it done.
  void blitToExternalImage(const Image& source, VkImage destination, VkExtent2D destinationSize,
                           VkImageLayout currentLayout, VkImageLayout finalLayout);

 private:
  VkDescriptorSet writeDescriptors(const PipelineLayout& layout, const std::string& name, const Bindings& bindings,
                                   bool compute);
  void bindCompute(const ComputePipeline& pipeline, const Bindings& bindings, const void* push, size_t pushBytes);

  Device& device_;
  VkCommandBuffer commandBuffer_;
  DescriptorArena& descriptors_;
  Profiler* profiler_;
  BarrierBatch barriers_;
  bool rendering_ = false;
};

}  // namespace ssvgi::gpu
