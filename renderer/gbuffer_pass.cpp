#include "gbuffer_pass.h"

#include "ssvgi_renderer_shaders.h"

namespace ssvgi::renderer {

namespace {

constexpr VkFormat kAlbedoFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kEmissionFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kMotionFormat = VK_FORMAT_R16G16_SFLOAT;

gpu::Image target(gpu::Device& device, const char* name, VkFormat format, uint32_t width, uint32_t height) {
  const VkImageUsageFlags attachment = format == VK_FORMAT_D32_SFLOAT ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                                                                       : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  return gpu::Image(device, {name, format, width, height, 1, 1, attachment | VK_IMAGE_USAGE_SAMPLED_BIT});
}

gpu::GraphicsPipelineDesc gbufferPipelineDesc() {
  gpu::GraphicsPipelineDesc desc;
  desc.vertexShader = &shaders::gbuffer_vert;
  desc.fragmentShader = &shaders::gbuffer_frag;
  desc.vertexStride = sizeof(Vertex);
  desc.vertexAttributes = {{0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
                           {1, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
                           {2, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)},
                           {3, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, color)}};
  desc.colorFormats = {kAlbedoFormat, kEmissionFormat, kNormalFormat, kMotionFormat};
  desc.depthFormat = VK_FORMAT_D32_SFLOAT;
  desc.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reversed-Z
  desc.cullMode = VK_CULL_MODE_NONE;  // glTF planes may be seen from behind; the fragment shader faces the normal
  return desc;
}

}  // namespace

GBuffer::GBuffer(gpu::Device& device, uint32_t width, uint32_t height)
    : depth(target(device, "gbuffer depth", VK_FORMAT_D32_SFLOAT, width, height)),
      albedo(target(device, "gbuffer albedo", kAlbedoFormat, width, height)),
      emission(target(device, "gbuffer emission", kEmissionFormat, width, height)),
      normal(target(device, "gbuffer normal", kNormalFormat, width, height)),
      motion(target(device, "gbuffer motion", kMotionFormat, width, height)) {}

GBufferPass::GBufferPass(gpu::Device& device) : pipeline_(device, gbufferPipelineDesc()) {}

void GBufferPass::record(gpu::HostCommandList& commands, const GpuScene& scene, const gpu::Buffer& frameConstants,
                         const GBuffer& target) {
  auto scope = commands.scope("renderer: GBuffer");
  commands.use(frameConstants, gpu::Usage::GraphicsRead);
  commands.use(scene.instances(), gpu::Usage::GraphicsRead);
  commands.use(scene.materials(), gpu::Usage::GraphicsRead);
  commands.use(scene.vertices(), gpu::Usage::VertexInput);
  commands.use(scene.indices(), gpu::Usage::VertexInput);
  for (const Draw& draw : scene.draws()) {
    commands.use(scene.baseColorTexture(draw.material), gpu::Usage::FragmentSampled);
    commands.use(scene.emissionTexture(draw.material), gpu::Usage::FragmentSampled);
  }

  const VkClearValue black{};
  VkClearValue farDepth{};
  farDepth.depthStencil.depth = 0.0f;  // reversed-Z: cleared to infinitely far
  commands.beginRendering({{&target.albedo, 0, black}, {&target.emission, 0, black}, {&target.normal, 0, black},
                           {&target.motion, 0, black}},
                          {&target.depth, 0, farDepth});
  const VkDeviceSize offset = 0;
  const VkBuffer vertexBuffer = scene.vertices().handle();
  for (const Draw& draw : scene.draws()) {
    commands.bindGraphics(pipeline_, gpu::Bindings()
                                         .buffer(shader::kBindDrawFrame, frameConstants)
                                         .buffer(shader::kBindDrawInstances, scene.instances())
                                         .buffer(shader::kBindDrawMaterials, scene.materials())
                                         .sampled(shader::kBindDrawBaseColor, scene.baseColorTexture(draw.material),
                                                  scene.textureSampler())
                                         .sampled(shader::kBindDrawEmission, scene.emissionTexture(draw.material),
                                                  scene.textureSampler()));
    vkCmdBindVertexBuffers(commands.handle(), 0, 1, &vertexBuffer, &offset);
    vkCmdBindIndexBuffer(commands.handle(), scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
    const shader::DrawPush push{draw.instance, draw.material, 0, 0};
    commands.pushConstants(pipeline_.layout(), &push, sizeof(push));
    vkCmdDrawIndexed(commands.handle(), draw.indexCount, 1, draw.firstIndex, draw.vertexOffset, 0);
  }
  commands.endRendering();
}

}  // namespace ssvgi::renderer
