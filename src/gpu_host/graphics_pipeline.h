#pragma once
#include "gpu/pipelines.h"

#include <string>
#include <vector>

namespace ssvgi::gpu {

struct VertexAttribute {
  uint32_t location;
  VkFormat format;
  uint32_t offset;
};

struct GraphicsPipelineDesc {
  const ShaderBinary* vertexShader = nullptr;
  const ShaderBinary* fragmentShader = nullptr;  // null: depth only
  uint32_t vertexStride = 0;
  std::vector<VertexAttribute> vertexAttributes;
  std::vector<VkFormat> colorFormats;
  VkFormat depthFormat = VK_FORMAT_UNDEFINED;
  VkCompareOp depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reversed-Z
  VkCullModeFlags cullMode = VK_CULL_MODE_BACK_BIT;
  bool depthBias = false;  // dynamic depth bias (shadow maps)
  SpecializationConstants constants;
};

class GraphicsPipeline {
 public:
  GraphicsPipeline(Device& device, const GraphicsPipelineDesc& desc);
  ~GraphicsPipeline();
  GraphicsPipeline(const GraphicsPipeline&) = delete;
  GraphicsPipeline& operator=(const GraphicsPipeline&) = delete;

  VkPipeline handle() const { return pipeline_; }
  const PipelineLayout& layout() const { return layout_; }
  const std::string& name() const { return name_; }

 private:
  Device& device_;
  std::string name_;
  PipelineLayout layout_;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace ssvgi::gpu
