#include "graphics_pipeline.h"

namespace ssvgi::gpu {

namespace {
std::vector<ShaderReflection> reflectStages(const GraphicsPipelineDesc& desc) {
  if (!desc.vertexShader) throw GpuError("graphics pipeline without a vertex shader");
  std::vector<ShaderReflection> stages{reflectSpirv(desc.vertexShader->words, desc.vertexShader->name)};
  if (desc.fragmentShader) stages.push_back(reflectSpirv(desc.fragmentShader->words, desc.fragmentShader->name));
  return stages;
}
}  // namespace

GraphicsPipeline::GraphicsPipeline(Device& device, const GraphicsPipelineDesc& desc)
    : device_(device),
      name_(std::string(desc.vertexShader ? desc.vertexShader->name : "?") + (desc.fragmentShader ? std::string("+") + desc.fragmentShader->name : "")),
      layout_(device, reflectStages(desc), name_) {
  const Specialization specialization(desc.constants);
  std::vector<VkShaderModule> modules{createShaderModule(device, *desc.vertexShader)};
  std::vector<VkPipelineShaderStageCreateInfo> stages(1, {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO});
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = modules[0];
  stages[0].pName = "main";
  stages[0].pSpecializationInfo = desc.constants.empty() ? nullptr : &specialization.info;
  if (desc.fragmentShader) {
    modules.push_back(createShaderModule(device, *desc.fragmentShader));
    stages.push_back(stages[0]);
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = modules[1];
  }

  const VkVertexInputBindingDescription vertexBinding{0, desc.vertexStride, VK_VERTEX_INPUT_RATE_VERTEX};
  std::vector<VkVertexInputAttributeDescription> attributes;
  for (const VertexAttribute& attribute : desc.vertexAttributes)
    attributes.push_back({attribute.location, 0, attribute.format, attribute.offset});
  VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertexInput.vertexBindingDescriptionCount = desc.vertexStride ? 1 : 0;
  vertexInput.pVertexBindingDescriptions = &vertexBinding;
  vertexInput.vertexAttributeDescriptionCount = static_cast<uint32_t>(attributes.size());
  vertexInput.pVertexAttributeDescriptions = attributes.data();

  VkPipelineInputAssemblyStateCreateInfo inputAssembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  inputAssembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rasterization{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rasterization.polygonMode = VK_POLYGON_MODE_FILL;
  rasterization.cullMode = desc.cullMode;
  rasterization.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rasterization.depthBiasEnable = desc.depthBias ? VK_TRUE : VK_FALSE;
  rasterization.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depthStencil{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depthStencil.depthTestEnable = desc.depthFormat != VK_FORMAT_UNDEFINED;
  depthStencil.depthWriteEnable = desc.depthFormat != VK_FORMAT_UNDEFINED;
  depthStencil.depthCompareOp = desc.depthCompare;
  std::vector<VkPipelineColorBlendAttachmentState> blendAttachments(desc.colorFormats.size());
  for (auto& attachment : blendAttachments) attachment.colorWriteMask = 0xf;
  VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = static_cast<uint32_t>(blendAttachments.size());
  blend.pAttachments = blendAttachments.data();
  std::vector<VkDynamicState> dynamicStates{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  if (desc.depthBias) dynamicStates.push_back(VK_DYNAMIC_STATE_DEPTH_BIAS);
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = static_cast<uint32_t>(dynamicStates.size());
  dynamic.pDynamicStates = dynamicStates.data();

  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = static_cast<uint32_t>(desc.colorFormats.size());
  rendering.pColorAttachmentFormats = desc.colorFormats.data();
  rendering.depthAttachmentFormat = desc.depthFormat;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.pVertexInputState = &vertexInput;
  info.pInputAssemblyState = &inputAssembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &rasterization;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depthStencil;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = layout_.handle();
  const VkResult result = vkCreateGraphicsPipelines(device.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  for (VkShaderModule module : modules) vkDestroyShaderModule(device.device(), module, nullptr);
  VK_CHECK(result);
  device.setName(pipeline_, VK_OBJECT_TYPE_PIPELINE, name_);
}

GraphicsPipeline::~GraphicsPipeline() { vkDestroyPipeline(device_.device(), pipeline_, nullptr); }

}  // namespace ssvgi::gpu
