#pragma once
#include "gpu/command_list.h"
#include "graphics_pipeline.h"

#include <vector>

namespace ssvgi::gpu {

// A CommandList with what only a host records: drawing with graphics pipelines, and blits (a window's image).
class HostCommandList : public CommandList {
 public:
  using CommandList::CommandList;

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

  // Copies a colour image's mip 0, layer 0 into another's, scaled to its size (nearest texel: exact at equal sizes)
  // and converted to its format (vkCmdBlitImage).
  void blitImage(const Image& source, const Image& destination);
  // The same into a colour image someone else owns (a swapchain's), in `currentLayout` before and left in
  // `finalLayout` for its owner, all of this command list's earlier work on it done.
  void blitToExternalImage(const Image& source, VkImage destination, VkExtent2D destinationSize,
                           VkImageLayout currentLayout, VkImageLayout finalLayout);

 private:
  bool rendering_ = false;
};

}  // namespace ssvgi::gpu
