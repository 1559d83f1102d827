#version 450
// Composite: final = emission + albedo/π · (E_direct + E_indirect), the sky where nothing was drawn (SPEC §3). With GI off
// E_indirect is black: there is no ambient term at all. With GI on it is ssvgi's half-resolution output, sampled
// bilinearly (not yet edge-aware): its texel h holds full-resolution pixel 2h, so pixel p reads at texel p/2.
#include "shared/renderer_interface.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindCompositeFrame) uniform Frame { FrameConstants frame; };
layout(binding = kBindCompositeDepth) uniform sampler2D depthBuffer;
layout(binding = kBindCompositeAlbedo) uniform sampler2D albedoBuffer;
layout(binding = kBindCompositeEmission) uniform sampler2D emissionBuffer;
layout(binding = kBindCompositeDirect, rgba32f) readonly uniform image2D directIrradiance;
layout(binding = kBindCompositeIndirect) uniform sampler2D indirectIrradiance;
layout(binding = kBindCompositeFinal, rgba32f) writeonly uniform image2D finalRadiance;
layout(binding = kBindCompositeIndirectUsed, rgba32f) writeonly uniform image2D indirectUsed;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;

  vec3 radiance;
  vec3 indirect = vec3(0.0);
  if (texelFetch(depthBuffer, pixel, 0).r <= 0.0) {
    vec4 world = frame.inverseViewProjection * vec4(pixelToNdc(vec2(pixel), frame.viewportSize), 1.0, 1.0);
    vec3 direction = normalize(world.xyz / world.w - frame.cameraPositionAndNear.xyz);
    radiance = evaluateSky(frame.sky, direction);
  } else {
    vec3 albedo = texelFetch(albedoBuffer, pixel, 0).rgb;
    if (frame.lightCountAndExposure.z > 0.0) {
      vec2 uv = (vec2(pixel) * 0.5 + 0.5) / vec2(textureSize(indirectIrradiance, 0));
      indirect = textureLod(indirectIrradiance, uv, 0.0).rgb;
    }
    vec3 irradiance = imageLoad(directIrradiance, pixel).rgb + indirect;
    radiance = texelFetch(emissionBuffer, pixel, 0).rgb + albedo * (1.0 / kPi) * irradiance;
  }
  imageStore(finalRadiance, pixel, vec4(radiance, 1.0));
  imageStore(indirectUsed, pixel, vec4(indirect, 1.0));
}
