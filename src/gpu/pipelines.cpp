#include "pipelines.h"

#include <algorithm>
#include <array>

namespace ssvgi::gpu {

VkShaderModule createShaderModule(Device& device, const ShaderBinary& shader) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = shader.words.size_bytes();
  info.pCode = shader.words.data();
  VkShaderModule module = VK_NULL_HANDLE;
  VK_CHECK(device.vk().vkCreateShaderModule(device.device(), &info, nullptr, &module));
  return module;
}

Specialization::Specialization(const SpecializationConstants& constants) {
  for (uint32_t i = 0; i < constants.size(); ++i)
    entries.push_back({i, static_cast<uint32_t>(i * sizeof(uint32_t)), sizeof(uint32_t)});
  info.mapEntryCount = static_cast<uint32_t>(entries.size());
  info.pMapEntries = entries.data();
  info.dataSize = constants.size() * sizeof(uint32_t);
  info.pData = constants.data();
}

PipelineLayout::PipelineLayout(Device& device, const std::vector<ShaderReflection>& stages, const std::string& name)
    : device_(device) {
  std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
  for (const ShaderReflection& stage : stages) {
    stages_ |= stage.stage;
    pushConstantBytes_ = std::max(pushConstantBytes_, stage.pushConstantBytes);
    for (const ReflectedBinding& binding : stage.bindings) {
      auto existing = std::find_if(bindings_.begin(), bindings_.end(),
                                   [&](const ReflectedBinding& b) { return b.binding == binding.binding; });
      if (existing != bindings_.end()) {
        if (existing->type != binding.type)
          throw GpuError(name + ": binding " + std::to_string(binding.binding) + " has different types in two stages");
        existing->writable |= binding.writable;
        layoutBindings[size_t(existing - bindings_.begin())].stageFlags |= stage.stage;
        continue;
      }
      bindings_.push_back(binding);
      layoutBindings.push_back({binding.binding, binding.type, binding.count, VkShaderStageFlags(stage.stage), nullptr});
    }
  }
  if (pushConstantBytes_ > device.properties().limits.maxPushConstantsSize)
    throw GpuError(name + ": " + std::to_string(pushConstantBytes_) + " bytes of push constants exceed the device limit");

  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.bindingCount = static_cast<uint32_t>(layoutBindings.size());
  setInfo.pBindings = layoutBindings.data();
  VK_CHECK(device.vk().vkCreateDescriptorSetLayout(device.device(), &setInfo, nullptr, &setLayout_));

  const VkPushConstantRange range{stages_, 0, pushConstantBytes_};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout_;
  layoutInfo.pushConstantRangeCount = pushConstantBytes_ > 0 ? 1 : 0;
  layoutInfo.pPushConstantRanges = &range;
  VK_CHECK(device.vk().vkCreatePipelineLayout(device.device(), &layoutInfo, nullptr, &layout_));
  device.setName(layout_, VK_OBJECT_TYPE_PIPELINE_LAYOUT, name);
}

PipelineLayout::~PipelineLayout() {
  device_.vk().vkDestroyPipelineLayout(device_.device(), layout_, nullptr);
  device_.vk().vkDestroyDescriptorSetLayout(device_.device(), setLayout_, nullptr);
}

ComputePipeline::ComputePipeline(Device& device, const ShaderBinary& shader, const SpecializationConstants& constants)
    : ComputePipeline(device, shader, reflectSpirv(shader.words, shader.name), constants) {}

ComputePipeline::ComputePipeline(Device& device, const ShaderBinary& shader, const ShaderReflection& reflection,
                                 const SpecializationConstants& constants)
    : device_(device),
      name_(shader.name),
      layout_(device, {reflection}, shader.name),
      localSize_(reflection.localSize[0], reflection.localSize[1], reflection.localSize[2]) {
  VkShaderModule module = createShaderModule(device, shader);
  const Specialization specialization(constants);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = constants.empty() ? nullptr : &specialization.info;
  info.layout = layout_.handle();
  const VkResult result =
      device.vk().vkCreateComputePipelines(device.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  device.vk().vkDestroyShaderModule(device.device(), module, nullptr);
  VK_CHECK(result);
  device.setName(pipeline_, VK_OBJECT_TYPE_PIPELINE, name_);
}

ComputePipeline::~ComputePipeline() { device_.vk().vkDestroyPipeline(device_.device(), pipeline_, nullptr); }

Bindings& Bindings::buffer(uint32_t slot, const Buffer& buffer) {
  entries_.push_back({slot, &buffer});
  return *this;
}

Bindings& Bindings::image(uint32_t slot, const Image& image) {
  entries_.push_back({slot, nullptr, &image, image.view()});
  return *this;
}

Bindings& Bindings::imageMip(uint32_t slot, const Image& image, uint32_t mip) {
  entries_.push_back({slot, nullptr, &image, image.mipView(mip)});
  return *this;
}

Bindings& Bindings::sampled(uint32_t slot, const Image& image, VkSampler sampler) {
  entries_.push_back({slot, nullptr, &image, image.view(), sampler});
  return *this;
}

Bindings& Bindings::externalSampled(uint32_t slot, VkImageView view, VkSampler sampler) {
  entries_.push_back({slot, nullptr, nullptr, view, sampler});
  return *this;
}

Bindings& Bindings::externalStorage(uint32_t slot, VkImageView view) {
  entries_.push_back({slot, nullptr, nullptr, view});
  return *this;
}

Bindings& Bindings::accumulator(uint32_t slot, const Buffer& buffer) {
  entries_.push_back({slot, &buffer, nullptr, VK_NULL_HANDLE, VK_NULL_HANDLE, false});
  return *this;
}

DescriptorArena::DescriptorArena(Device& device) : device_(device) { pools_.push_back(newPool()); }

DescriptorArena::~DescriptorArena() {
  for (VkDescriptorPool pool : pools_) device_.vk().vkDestroyDescriptorPool(device_.device(), pool, nullptr);
}

VkDescriptorPool DescriptorArena::newPool() {
  constexpr uint32_t kSets = 512;
  const std::array<VkDescriptorPoolSize, 5> sizes{{
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kSets * 8},
      {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kSets * 2},
      {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kSets * 4},
      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kSets * 8},
      {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, kSets * 2},
  }};
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.maxSets = kSets;
  info.poolSizeCount = static_cast<uint32_t>(sizes.size());
  info.pPoolSizes = sizes.data();
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_CHECK(device_.vk().vkCreateDescriptorPool(device_.device(), &info, nullptr, &pool));
  return pool;
}

VkDescriptorSet DescriptorArena::allocate(VkDescriptorSetLayout layout) {
  for (;;) {
    VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    info.descriptorPool = pools_[current_];
    info.descriptorSetCount = 1;
    info.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    const VkResult result = device_.vk().vkAllocateDescriptorSets(device_.device(), &info, &set);
    if (result == VK_SUCCESS) return set;
    if (result != VK_ERROR_OUT_OF_POOL_MEMORY && result != VK_ERROR_FRAGMENTED_POOL) VK_CHECK(result);
    if (++current_ == pools_.size()) pools_.push_back(newPool());
  }
}

void DescriptorArena::reset() {
  for (VkDescriptorPool pool : pools_) VK_CHECK(device_.vk().vkResetDescriptorPool(device_.device(), pool, 0));
  current_ = 0;
}

}  // namespace ssvgi::gpu
