#include "command_list.h"

#include <algorithm>

namespace ssvgi::gpu {

CommandList::CommandList(Device& device, VkCommandBuffer commandBuffer, DescriptorArena& descriptors, Profiler* profiler)
    : device_(device), commandBuffer_(commandBuffer), descriptors_(descriptors), profiler_(profiler) {}

CommandList::Scope::Scope(CommandList& list, const std::string& label) : list_(list) {
  list.device_.beginLabel(list.commandBuffer_, label.c_str());
  if (list.profiler_) {
    list.flushBarriers();  // the scope's time includes the barriers its own commands need, not the previous pass's
    profilerScope_ = list.profiler_->beginScope(list.commandBuffer_, label);
  }
}

CommandList::Scope::~Scope() {
  if (list_.profiler_) list_.profiler_->endScope(list_.commandBuffer_, profilerScope_);
  list_.device_.endLabel(list_.commandBuffer_);
}

VkDescriptorSet CommandList::writeDescriptors(const PipelineLayout& layout, const std::string& name,
                                              const Bindings& bindings, bool compute) {
  const auto& reflected = layout.bindings();
  if (reflected.empty()) return VK_NULL_HANDLE;
  std::vector<VkDescriptorBufferInfo> bufferInfos;
  std::vector<VkDescriptorImageInfo> imageInfos;
  bufferInfos.reserve(reflected.size());
  imageInfos.reserve(reflected.size());
  std::vector<VkWriteDescriptorSet> writes;
  const VkDescriptorSet set = descriptors_.allocate(layout.setLayout());

  for (const ReflectedBinding& binding : reflected) {
    auto entry = std::find_if(bindings.entries().begin(), bindings.entries().end(),
                              [&](const Bindings::Entry& e) { return e.slot == binding.binding; });
    if (entry == bindings.entries().end())
      throw GpuError(name + ": binding " + std::to_string(binding.binding) + " (" + binding.name + ") is not bound");
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set;
    write.dstBinding = binding.binding;
    write.descriptorCount = 1;
    write.descriptorType = binding.type;
    switch (binding.type) {
      case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
      case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
        if (!entry->buffer) throw GpuError(name + ": binding " + binding.name + " needs a buffer");
        bufferInfos.push_back({entry->buffer->handle(), 0, VK_WHOLE_SIZE});
        write.pBufferInfo = &bufferInfos.back();
        if (entry->tracked)
          use(*entry->buffer,
              compute ? (binding.writable ? Usage::ComputeWrite : Usage::ComputeRead) : Usage::GraphicsRead);
        break;
      case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
        if (!entry->view || entry->sampler) throw GpuError(name + ": binding " + binding.name + " needs a storage image");
        imageInfos.push_back({VK_NULL_HANDLE, entry->view, VK_IMAGE_LAYOUT_GENERAL});
        write.pImageInfo = &imageInfos.back();
        if (entry->image) use(*entry->image, binding.writable ? Usage::ComputeWrite : Usage::ComputeRead);
        break;
      case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
        if (!entry->view || !entry->sampler)
          throw GpuError(name + ": binding " + binding.name + " needs an image with a sampler");
        imageInfos.push_back({entry->sampler, entry->view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
        write.pImageInfo = &imageInfos.back();
        if (entry->image) use(*entry->image, compute ? Usage::ComputeSampled : Usage::FragmentSampled);
        break;
      default:
        throw GpuError(name + ": binding " + binding.name + " has a descriptor type the GPU layer does not bind");
    }
    writes.push_back(write);
  }
  device_.vk().vkUpdateDescriptorSets(device_.device(), static_cast<uint32_t>(writes.size()), writes.data(), 0,
                                      nullptr);
  return set;
}

void CommandList::pushConstants(const PipelineLayout& layout, const void* data, size_t bytes) {
  if (bytes != layout.pushConstantBytes())
    throw GpuError("push constants of " + std::to_string(bytes) + " bytes for a pipeline that declares " +
                   std::to_string(layout.pushConstantBytes()));
  if (bytes)
    device_.vk().vkCmdPushConstants(commandBuffer_, layout.handle(), layout.stages(), 0, static_cast<uint32_t>(bytes),
                                    data);
}

void CommandList::bindCompute(const ComputePipeline& pipeline, const Bindings& bindings, const void* push,
                              size_t pushBytes) {
  const VkDescriptorSet set = writeDescriptors(pipeline.layout(), pipeline.name(), bindings, true);
  flushBarriers();
  device_.vk().vkCmdBindPipeline(commandBuffer_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
  if (set) {
    device_.vk().vkCmdBindDescriptorSets(commandBuffer_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout().handle(), 0,
                                         1, &set, 0, nullptr);
  }
  pushConstants(pipeline.layout(), push, pushBytes);
}

void CommandList::dispatch(const ComputePipeline& pipeline, const Bindings& bindings, glm::uvec3 threads,
                           const void* push, size_t pushBytes) {
  bindCompute(pipeline, bindings, push, pushBytes);
  const glm::uvec3 local = pipeline.localSize();
  const glm::uvec3 groups = (threads + local - 1u) / local;
  if (groups.x && groups.y && groups.z) device_.vk().vkCmdDispatch(commandBuffer_, groups.x, groups.y, groups.z);
}

void CommandList::dispatchIndirect(const ComputePipeline& pipeline, const Bindings& bindings, const Buffer& arguments,
                                   VkDeviceSize offset, const void* push, size_t pushBytes) {
  use(arguments, Usage::IndirectArgument);
  bindCompute(pipeline, bindings, push, pushBytes);
  device_.vk().vkCmdDispatchIndirect(commandBuffer_, arguments.handle(), offset);
}

void CommandList::fillBuffer(const Buffer& buffer, uint32_t value) {
  use(buffer, Usage::TransferDestination);
  flushBarriers();
  device_.vk().vkCmdFillBuffer(commandBuffer_, buffer.handle(), 0, VK_WHOLE_SIZE, value);
}

void CommandList::useExternalImage(VkImage image, VkImageLayout currentLayout, VkImageLayout layout) {
  flushBarriers();
  // The owner's earlier use is unknown: wait for all of it.
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  barrier.oldLayout = currentLayout;
  barrier.newLayout = layout;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
  device_.vk().vkCmdPipelineBarrier(commandBuffer_, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

void CommandList::updateBuffer(const Buffer& buffer, VkDeviceSize offset, const void* data, VkDeviceSize bytes) {
  use(buffer, Usage::TransferDestination);
  flushBarriers();
  device_.vk().vkCmdUpdateBuffer(commandBuffer_, buffer.handle(), offset, bytes, data);
}

void CommandList::copyBuffer(const Buffer& source, const Buffer& destination, VkDeviceSize bytes) {
  use(source, Usage::TransferSource);
  use(destination, Usage::TransferDestination);
  flushBarriers();
  const VkBufferCopy region{0, 0, bytes};
  device_.vk().vkCmdCopyBuffer(commandBuffer_, source.handle(), destination.handle(), 1, &region);
}

void CommandList::clearImage(const Image& image, const VkClearColorValue& value) {
  use(image, Usage::TransferDestination);
  flushBarriers();
  const VkImageSubresourceRange range{image.aspect(), 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
  device_.vk().vkCmdClearColorImage(commandBuffer_, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1,
                                    &range);
}

}  // namespace ssvgi::gpu
