#pragma once
#include "resources.h"
#include "shader_binary.h"
#include "spirv_reflection.h"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace ssvgi::gpu {

// Values for a shader's specialization constants (constant_id = index in this list), for variants without #if.
using SpecializationConstants = std::vector<uint32_t>;

// What every kind of pipeline is built from: a shader module (destroyed by the caller once the pipeline exists) and the
// specialization info for its constants (pointing into `constants`, which must outlive it).
VkShaderModule createShaderModule(Device& device, const ShaderBinary& shader);
struct Specialization {
  explicit Specialization(const SpecializationConstants& constants);
  Specialization(const Specialization&) = delete;  // info points into entries
  Specialization& operator=(const Specialization&) = delete;
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo info{};
};

// Set 0 layout + pipeline layout built from the reflection of a pipeline's stages, shared by every kind of pipeline.
class PipelineLayout {
 public:
  PipelineLayout(Device& device, const std::vector<ShaderReflection>& stages, const std::string& name);
  ~PipelineLayout();
  PipelineLayout(const PipelineLayout&) = delete;
  PipelineLayout& operator=(const PipelineLayout&) = delete;

  VkPipelineLayout handle() const { return layout_; }
  VkDescriptorSetLayout setLayout() const { return setLayout_; }
  const std::vector<ReflectedBinding>& bindings() const { return bindings_; }
  VkShaderStageFlags stages() const { return stages_; }
  uint32_t pushConstantBytes() const { return pushConstantBytes_; }

 private:
  Device& device_;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  std::vector<ReflectedBinding> bindings_;
  VkShaderStageFlags stages_ = 0;
  uint32_t pushConstantBytes_ = 0;
};

class ComputePipeline {
 public:
  ComputePipeline(Device& device, const ShaderBinary& shader, const SpecializationConstants& constants = {});
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  VkPipeline handle() const { return pipeline_; }
  const PipelineLayout& layout() const { return layout_; }
  const std::string& name() const { return name_; }
  glm::uvec3 localSize() const { return localSize_; }

 private:
  ComputePipeline(Device& device, const ShaderBinary& shader, const ShaderReflection& reflection,
                  const SpecializationConstants& constants);
  Device& device_;
  std::string name_;
  PipelineLayout layout_;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  glm::uvec3 localSize_{1};
};

// The resources bound to a pipeline's set 0 for one dispatch or draw, by binding slot. Slots and descriptor types are
// checked against the shader's reflection when bound; the usage (read, write, sampled) comes from the shader too.
class Bindings {
 public:
  Bindings& buffer(uint32_t slot, const Buffer& buffer);
  Bindings& image(uint32_t slot, const Image& image);                   // storage image, all mips
  Bindings& imageMip(uint32_t slot, const Image& image, uint32_t mip);  // storage image, one mip
  Bindings& sampled(uint32_t slot, const Image& image, VkSampler sampler);
  // An image someone else owns and keeps in SHADER_READ_ONLY_OPTIMAL with its writes visible (the GI library's host
  // images): bound, but not tracked.
  Bindings& externalSampled(uint32_t slot, VkImageView view, VkSampler sampler);
  // A storage image someone else owns, in VK_IMAGE_LAYOUT_GENERAL (see CommandList::useExternalImage): not tracked.
  Bindings& externalStorage(uint32_t slot, VkImageView view);
  // A buffer that dispatches only add to with atomics (counters): the adds commute, so no barrier orders the
  // dispatches among themselves for it. Bound, not tracked; whoever records them orders the buffer against its other
  // uses (a clear before, a copy after) with CommandList::use.
  Bindings& accumulator(uint32_t slot, const Buffer& buffer);

  struct Entry {
    uint32_t slot;
    const Buffer* buffer = nullptr;
    const Image* image = nullptr;
    VkImageView view = VK_NULL_HANDLE;
    VkSampler sampler = VK_NULL_HANDLE;
    bool tracked = true;
  };
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  std::vector<Entry> entries_;
};

// Descriptor sets for one frame's dispatches, allocated from pools that are reset together once the frame's commands
// have completed. Owned by whoever records (the renderer, a GI context per frame in flight).
class DescriptorArena {
 public:
  explicit DescriptorArena(Device& device);
  ~DescriptorArena();
  DescriptorArena(const DescriptorArena&) = delete;
  DescriptorArena& operator=(const DescriptorArena&) = delete;

  VkDescriptorSet allocate(VkDescriptorSetLayout layout);
  void reset();

 private:
  VkDescriptorPool newPool();
  Device& device_;
  std::vector<VkDescriptorPool> pools_;
  size_t current_ = 0;
};

}  // namespace ssvgi::gpu
