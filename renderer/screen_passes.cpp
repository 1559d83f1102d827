#include "screen_passes.h"

#include "ssvgi_renderer_shaders.h"

namespace ssvgi::renderer {

namespace {
glm::uvec3 pixels(const gpu::Image& image) { return {image.desc().width, image.desc().height, 1}; }
}  // namespace

DirectLighting::DirectLighting(gpu::Device& device) : pipeline_(device, shaders::direct_lighting_comp) {}

void DirectLighting::record(gpu::CommandList& commands, const gpu::Buffer& frameConstants, const gpu::Buffer& lights,
                            const ShadowPass& shadows, const GBuffer& gbuffer, VkSampler pointSampler,
                            const gpu::Image& irradiance, const gpu::Image& viewDistance) {
  auto scope = commands.scope("renderer: DirectLighting");
  commands.dispatch(pipeline_,
                    gpu::Bindings()
                        .buffer(shader::kBindLightingFrame, frameConstants)
                        .buffer(shader::kBindLightingLights, lights)
                        .buffer(shader::kBindLightingShadowViews, shadows.views())
                        .sampled(shader::kBindLightingDepth, gbuffer.depth, pointSampler)
                        .sampled(shader::kBindLightingNormal, gbuffer.normal, pointSampler)
                        .sampled(shader::kBindLightingSunShadow, shadows.sunShadowMap(), shadows.compareSampler())
                        .sampled(shader::kBindLightingLocalShadows, shadows.localShadowMaps(), shadows.compareSampler())
                        .image(shader::kBindLightingIrradiance, irradiance)
                        .image(shader::kBindLightingViewDistance, viewDistance),
                    pixels(gbuffer.depth));
}

Composite::Composite(gpu::Device& device) : pipeline_(device, shaders::composite_comp) {}

void Composite::record(gpu::CommandList& commands, const gpu::Buffer& frameConstants, const gpu::Buffer& fallback,
                       const GBuffer& gbuffer, VkSampler pointSampler, const gpu::Image& directIrradiance,
                       VkImageView indirectIrradiance, VkImageView indirectConfidence,
                       const gpu::Image& finalRadiance, const gpu::Image& indirectUsed,
                       const gpu::Image& directRadiance) {
  auto scope = commands.scope("renderer: Composite");
  commands.dispatch(pipeline_,
                    gpu::Bindings()
                        .buffer(shader::kBindCompositeFrame, frameConstants)
                        .buffer(shader::kBindCompositeFallback, fallback)
                        .sampled(shader::kBindCompositeDepth, gbuffer.depth, pointSampler)
                        .sampled(shader::kBindCompositeAlbedo, gbuffer.albedo, pointSampler)
                        .sampled(shader::kBindCompositeEmission, gbuffer.emission, pointSampler)
                        .sampled(shader::kBindCompositeNormal, gbuffer.normal, pointSampler)
                        .image(shader::kBindCompositeDirect, directIrradiance)
                        .externalSampled(shader::kBindCompositeIndirect, indirectIrradiance, pointSampler)
                        .externalSampled(shader::kBindCompositeConfidence, indirectConfidence, pointSampler)
                        .image(shader::kBindCompositeFinal, finalRadiance)
                        .image(shader::kBindCompositeIndirectUsed, indirectUsed)
                        .image(shader::kBindCompositeDirectRadiance, directRadiance),
                    pixels(finalRadiance));
}

Tonemap::Tonemap(gpu::Device& device) : pipeline_(device, shaders::tonemap_comp) {}

void Tonemap::record(gpu::CommandList& commands, const gpu::Buffer& frameConstants, const gpu::Image& hdr,
                     const gpu::Image& ldr) {
  auto scope = commands.scope("renderer: Tonemap");
  commands.dispatch(pipeline_,
                    gpu::Bindings()
                        .buffer(shader::kBindTonemapFrame, frameConstants)
                        .image(shader::kBindTonemapInput, hdr)
                        .image(shader::kBindTonemapOutput, ldr),
                    pixels(ldr));
}

}  // namespace ssvgi::renderer
