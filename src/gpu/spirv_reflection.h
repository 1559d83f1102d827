#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ssvgi::gpu {

// What a pipeline needs to know about a shader, read from its SPIR-V so that bindings are declared once, in GLSL
// (the approach of niagara's shaders.cpp).
struct ReflectedBinding {
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  uint32_t count = 1;
  bool writable = false;  // a storage buffer/image not declared readonly
  std::string name;
};

struct ShaderReflection {
  VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;
  uint32_t localSize[3] = {1, 1, 1};
  uint32_t pushConstantBytes = 0;
  std::vector<ReflectedBinding> bindings;  // descriptor set 0, sorted by binding
};

// Throws GpuError for a module that is not SPIR-V or uses descriptor sets other than 0.
ShaderReflection reflectSpirv(std::span<const uint32_t> words, const std::string& shaderName);

}  // namespace ssvgi::gpu
