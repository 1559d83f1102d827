#version 450
// Composite: final = emission + albedo/π · (E_direct + E_indirect), the sky where nothing was drawn (SPEC §3). With GI off
// E_indirect is black: there is no ambient term at all. With GI on it is ssvgi's half-resolution output, whose texel h
// holds full-resolution pixel 2h; each pixel resolves it with the library's edge-aware sampling (ssvgi/resolve.glsl,
// SPEC §4.6 "Shading", §8), so light does not bleed across silhouettes. ssvgi's confidence (SPEC §6.4) is resolved
// with the same weights and kept beside the E_indirect used, for the renderer's confidence.exr. Beyond ssvgi's voxel
// volume, where ssvgi has no probes, the composite blends to the sky's light by that confidence (CompositeFallback);
// inside it never does, and with GI off there is no ambient term at all.
// It also writes the light without the GI's, emission + albedo/π · E_direct: ssvgi's lit frame, with the albedo, from
// which the voxels keep their direct light and are relit by the probes (ssvgi::FrameDesc::litAlbedo). The final
// radiance may show one part of the light alone on surfaces (the viewer's direct only / indirect only, kShow*).
#include "shared/renderer_interface.h"
#include "ssvgi/resolve.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindCompositeFrame, std140) readonly buffer Frame { FrameConstants frame; };
layout(binding = kBindCompositeDepth) uniform sampler2D depthBuffer;
layout(binding = kBindCompositeAlbedo) uniform sampler2D albedoBuffer;
layout(binding = kBindCompositeEmission) uniform sampler2D emissionBuffer;
layout(binding = kBindCompositeNormal) uniform sampler2D normalBuffer;
layout(binding = kBindCompositeDirect, rgba32f) readonly uniform image2D directIrradiance;
layout(binding = kBindCompositeIndirect) uniform sampler2D indirectIrradiance;
layout(binding = kBindCompositeConfidence) uniform sampler2D indirectConfidence;
layout(binding = kBindCompositeFinal, rgba32f) writeonly uniform image2D finalRadiance;
layout(binding = kBindCompositeIndirectUsed, rgba32f) writeonly uniform image2D indirectUsed;
layout(binding = kBindCompositeDirectRadiance, rgba16f) writeonly uniform image2D directRadiance;
layout(binding = kBindCompositeFallback, std140) readonly buffer Fallback { CompositeFallback fallback; };

// E_indirect with the fallback blended in where the surface at `pixel` lies beyond ssvgi's voxel volume.
vec3 withFallback(vec4 indirect, vec3 position, ivec2 pixel) {
  bool beyondVolume = any(lessThan(position, fallback.knownVolumeMinimum)) ||
                      any(greaterThan(position, fallback.knownVolumeMaximum));
  if (fallback.blendsToFallback == 0u || !beyondVolume) return indirect.rgb;
  vec3 normal = normalize(texelFetch(normalBuffer, pixel, 0).xyz);
  return mix(sh2IrradianceWithoutRinging(fallback.skyRadiance, normal), indirect.rgb, indirect.a);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;

  vec3 radiance;
  vec3 radianceWithoutGi = vec3(0.0);
  vec4 indirect = vec4(0.0);
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  if (depth <= 0.0) {
    vec4 world = frame.inverseViewProjection * vec4(ssvgiPixelToNdc(vec2(pixel), frame.viewportSize.xy), 1.0, 1.0);
    vec3 direction = normalize(world.xyz / world.w - frame.cameraPosition.xyz);
    radiance = evaluateSky(frame.sky, direction);
  } else {
    vec3 albedo = texelFetch(albedoBuffer, pixel, 0).rgb;
    if (frame.addsIndirectLight != 0u) {
      SsvgiResolveView view = SsvgiResolveView(frame.inverseViewProjection, frame.cameraPosition.xyz,
                                               frame.viewportSize.xy);
      SsvgiResolved resolved =
          ssvgiResolve(indirectIrradiance, indirectConfidence, depthBuffer, normalBuffer, view, pixel);
      indirect = vec4(resolved.irradiance, resolved.confidence);
      indirect.rgb = withFallback(indirect, ssvgiPixelPosition(view, pixel, depth), pixel);
    }
    vec3 direct = imageLoad(directIrradiance, pixel).rgb;
    vec3 emission = texelFetch(emissionBuffer, pixel, 0).rgb;
    radianceWithoutGi = emission + albedo * (1.0 / kPi) * direct;
    radiance = emission + albedo * (1.0 / kPi) * (direct + indirect.rgb);
    uint shown = frame.shownLight;
    if (shown == kShowDirectLight) radiance = radianceWithoutGi;
    if (shown == kShowIndirectLight) radiance = albedo * (1.0 / kPi) * indirect.rgb;
  }
  imageStore(finalRadiance, pixel, vec4(radiance, 1.0));
  imageStore(indirectUsed, pixel, indirect);
  imageStore(directRadiance, pixel, vec4(radianceWithoutGi, 1.0));
}
