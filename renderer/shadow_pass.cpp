#include "shadow_pass.h"

#include "ssvgi_renderer_shaders.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace ssvgi::renderer {

namespace {

constexpr float kLocalNear = 0.02f;  // metres; local shadow frusta start this close to the light

// `cutsOut`: with the fragment shader that leaves out where the material's texture cuts the surface out.
gpu::GraphicsPipelineDesc shadowPipelineDesc(bool cutsOut) {
  gpu::GraphicsPipelineDesc desc;
  desc.vertexShader = &shaders::shadow_vert;
  desc.fragmentShader = cutsOut ? &shaders::shadow_frag : nullptr;
  desc.vertexStride = sizeof(Vertex);
  desc.vertexAttributes = {{0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
                           {1, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)}};
  desc.depthFormat = VK_FORMAT_D32_SFLOAT;
  desc.depthCompare = VK_COMPARE_OP_LESS_OR_EQUAL;  // shadow maps use standard [0,1] depth
  desc.cullMode = VK_CULL_MODE_NONE;                // thin and open geometry must cast from both sides
  desc.depthBias = true;
  return desc;
}

VkSamplerCreateInfo compareSamplerInfo() {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = VK_FILTER_LINEAR;  // 2×2 percentage-closer filtering in hardware
  info.minFilter = VK_FILTER_LINEAR;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.compareEnable = VK_TRUE;
  info.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;  // lit when the receiver is no farther than the occluder
  return info;
}

gpu::Image shadowImage(gpu::Device& device, const char* name, uint32_t resolution, uint32_t layers, bool arrayView) {
  return gpu::Image(device, {name, VK_FORMAT_D32_SFLOAT, resolution, resolution, 1, std::max(1u, layers),
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, arrayView});
}

// An up vector that is not parallel to `forward`.
glm::vec3 upFor(glm::vec3 forward) {
  return std::abs(forward.y) > 0.99f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
}

float floatBits(uint32_t value) {
  float bits = 0.0f;
  std::memcpy(&bits, &value, sizeof(bits));
  return bits;
}

}  // namespace

ShadowPass::ShadowPass(gpu::Device& device, const ShadowSettings& settings)
    : device_(device),
      settings_(settings),
      pipeline_(device, shadowPipelineDesc(false)),
      cutOutPipeline_(device, shadowPipelineDesc(true)),
      compareSampler_(device, compareSamplerInfo(), "shadow compare sampler"),
      sunMap_(shadowImage(device, "sun shadow map", 1, 1, false)),
      localMaps_(shadowImage(device, "local shadow maps", 1, 1, true)),
      views_(device, "shadow views", (1 + shader::kMaxShadowLayers) * sizeof(shader::ShadowView),
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload) {}

void ShadowPass::prepare(const Scene& scene, const Bounds& sceneBounds, const Sun& sun, shader::FrameConstants& frame,
                         std::vector<shader::GpuLight>& lights) {
  std::vector<shader::ShadowView> views(1);

  sunEnabled_ = sun.enabled;
  if (sunEnabled_) {
    if (sunMap_.desc().width != settings_.sunResolution)
      sunMap_ = shadowImage(device_, "sun shadow map", settings_.sunResolution, 1, false);
    // Orthographic along the sun, fitted to the scene's bounds seen from the sun so that every caster and receiver
    // is inside and no texel is spent outside the scene.
    const glm::vec3 center = 0.5f * (sceneBounds.min + sceneBounds.max);
    const float radius = glm::length(sceneBounds.max - sceneBounds.min) * 0.5f + 1.0f;
    const glm::mat4 view = glm::lookAtRH(center + sun.direction * radius, center, upFor(sun.direction));
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p((corner & 1) ? sceneBounds.max.x : sceneBounds.min.x,
                        (corner & 2) ? sceneBounds.max.y : sceneBounds.min.y,
                        (corner & 4) ? sceneBounds.max.z : sceneBounds.min.z);
      const glm::vec3 v = glm::vec3(view * glm::vec4(p, 1.0f));
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    const glm::mat4 projection = glm::orthoRH_ZO(lo.x, hi.x, lo.y, hi.y, -hi.z - 1.0f, -lo.z + 1.0f);
    views[0].viewProjection = projection * view;
    const float texelSize = std::max(hi.x - lo.x, hi.y - lo.y) / float(settings_.sunResolution);
    views[0].texelWorldSize = texelSize;
    frame.sunShadowMatrix = views[0].viewProjection;
    frame.sunShadowTexelSize = texelSize;
  }

  // Local lights in scene order until the layer budget is spent.
  const float sceneExtent = glm::length(sceneBounds.max - sceneBounds.min) + 1.0f;
  uint32_t layer = 0;
  unshadowedLights_ = 0;
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const LocalLight& light = scene.lights[i];
    uint32_t firstLayer = shader::kNoShadow;
    const uint32_t needed = light.type == LightType::Point ? 6u : 1u;
    if (light.castsShadow && layer + needed <= shader::kMaxShadowLayers) {
      firstLayer = layer;
      const float far = light.range > 0.0f ? light.range : sceneExtent;
      if (light.type == LightType::Point) {
        // Cube faces +X, -X, +Y, -Y, +Z, -Z, each a 90° frustum (matches cubeFace() in the lighting shader).
        static const std::array<glm::vec3, 6> kFaces{glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0),
                                                     glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)};
        // Each face is widened by two texels so that the 2×2 filter footprint at a seam stays inside the face.
        const float halfWidth = 1.0f + 2.0f / float(settings_.localResolution);
        const glm::mat4 projection = glm::perspectiveRH_ZO(2.0f * std::atan(halfWidth), 1.0f, kLocalNear, far);
        for (const glm::vec3& face : kFaces) {
          const glm::mat4 view = glm::lookAtRH(light.position, light.position + face, upFor(face));
          views.push_back({projection * view, 2.0f * halfWidth / float(settings_.localResolution)});
        }
      } else {
        const float fov = std::min(2.0f * light.outerConeAngle + 0.05f, glm::radians(170.0f));
        const glm::mat4 projection = glm::perspectiveRH_ZO(fov, 1.0f, kLocalNear, far);
        const glm::mat4 view = glm::lookAtRH(light.position, light.position + light.direction, upFor(light.direction));
        views.push_back({projection * view, 2.0f * std::tan(fov * 0.5f) / float(settings_.localResolution)});
      }
      layer += needed;
    } else if (light.castsShadow) {
      ++unshadowedLights_;
    }
    lights[i].intensityAndShadow.w = floatBits(firstLayer);
  }
  if (layer != localLayers_ || localMaps_.desc().width != settings_.localResolution) {
    localLayers_ = layer;
    localMaps_ = shadowImage(device_, "local shadow maps", layer ? settings_.localResolution : 1, layer, true);
  }
  std::memcpy(views_.mapped(), views.data(), views.size() * sizeof(shader::ShadowView));
}

void ShadowPass::record(gpu::HostCommandList& commands, const GpuScene& scene) {
  auto scope = commands.scope("renderer: Shadow");
  commands.use(scene.instances(), gpu::Usage::GraphicsRead);
  commands.use(views_, gpu::Usage::GraphicsRead);
  commands.use(scene.vertices(), gpu::Usage::VertexInput);
  commands.use(scene.indices(), gpu::Usage::VertexInput);
  commands.use(scene.materials(), gpu::Usage::GraphicsRead);
  for (const Draw& draw : scene.draws())
    if (draw.cutsOut) commands.use(scene.baseColorTexture(draw.material), gpu::Usage::FragmentSampled);
  const gpu::Bindings bindings = gpu::Bindings()
                                     .buffer(shader::kBindDrawInstances, scene.instances())
                                     .buffer(shader::kBindDrawShadowViews, views_);

  auto drawView = [&](const gpu::Image& target, uint32_t layer, uint32_t view) {
    VkClearValue clear{};
    clear.depthStencil.depth = 1.0f;
    commands.beginRendering({}, {&target, layer, clear});
    const VkDeviceSize offset = 0;
    const VkBuffer vertexBuffer = scene.vertices().handle();
    // Slope-scaled bias against acne on surfaces at grazing angles to the light; the lighting shader adds a normal
    // offset for the rest.
    vkCmdSetDepthBias(commands.handle(), 1.0f, 0.0f, 1.5f);
    vkCmdBindVertexBuffers(commands.handle(), 0, 1, &vertexBuffer, &offset);
    vkCmdBindIndexBuffer(commands.handle(), scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
    commands.bindGraphics(pipeline_, bindings);
    for (const Draw& draw : scene.draws()) {
      if (draw.cutsOut) continue;
      const shader::DrawPush push{draw.instance, draw.material, view, 0};
      commands.pushConstants(pipeline_.layout(), &push, sizeof(push));
      vkCmdDrawIndexed(commands.handle(), draw.indexCount, 1, draw.firstIndex, draw.vertexOffset, 0);
    }
    // Then the draws whose material cuts the surface out, each with its texture.
    for (const Draw& draw : scene.draws()) {
      if (!draw.cutsOut) continue;
      gpu::Bindings withTexture = bindings;
      withTexture.buffer(shader::kBindDrawMaterials, scene.materials())
          .sampled(shader::kBindDrawBaseColor, scene.baseColorTexture(draw.material), scene.textureSampler());
      commands.bindGraphics(cutOutPipeline_, withTexture);
      const shader::DrawPush push{draw.instance, draw.material, view, 0};
      commands.pushConstants(cutOutPipeline_.layout(), &push, sizeof(push));
      vkCmdDrawIndexed(commands.handle(), draw.indexCount, 1, draw.firstIndex, draw.vertexOffset, 0);
    }
    commands.endRendering();
  };

  if (sunEnabled_) drawView(sunMap_, 0, 0);
  for (uint32_t layer = 0; layer < localLayers_; ++layer) drawView(localMaps_, layer, 1 + layer);
}

}  // namespace ssvgi::renderer
