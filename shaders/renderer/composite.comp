#version 450
// Composite: final = emission + albedo/π · (E_direct + E_indirect), the sky where nothing was drawn (SPEC §3). With GI off
// E_indirect is black: there is no ambient term at all. With GI on it is ssvgi's half-resolution output, whose texel h
// holds full-resolution pixel 2h; each pixel blends the 2×2 texels around it edge-aware (SPEC §4.6 "Shading"): bilinear
// weights times how well each texel's pixel lies on this pixel's surface, so light does not bleed across silhouettes.
// ssvgi's confidence (SPEC §6.4) is sampled with the same weights and kept beside the E_indirect used, for the
// renderer's confidence.exr; the composite does not blend to a fallback (it has none: GI off means no ambient at all).
// It also writes the light without the GI's, emission + albedo/π · E_direct: ssvgi's lit frame, with the albedo, from
// which the voxels keep their direct light and are relit by the probes (ssvgi::FrameDesc::litAlbedo).
#include "shared/renderer_interface.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindCompositeFrame) uniform Frame { FrameConstants frame; };
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

// A texel's pixel counts fully on this pixel's tangent plane, not at all 2 % of the view distance off it (a depth edge,
// a crease); its normal weighs in as dot^8 (half weight at about 24°).
const float kPlaneTolerance = 0.02;
const float kNormalPower = 8.0;

vec3 worldPosition(ivec2 pixel, float depth) {
  vec4 world = frame.inverseViewProjection * vec4(pixelToNdc(vec2(pixel), frame.viewportSize), depth, 1.0);
  return world.xyz / world.w;
}

vec4 indirectTexel(ivec2 texel) {
  return vec4(texelFetch(indirectIrradiance, texel, 0).rgb, texelFetch(indirectConfidence, texel, 0).r);
}

// rgb: E_indirect; a: its confidence.
vec4 edgeAwareIndirect(ivec2 pixel, float depth) {
  vec3 position = worldPosition(pixel, depth);
  vec3 normal = normalize(texelFetch(normalBuffer, pixel, 0).xyz);
  float tolerance = kPlaneTolerance * distance(position, frame.cameraPosition.xyz);
  ivec2 lastTexel = textureSize(indirectIrradiance, 0) - 1;
  ivec2 firstTexel = pixel >> 1;  // the pixel sits at texel coordinate pixel/2: on texel 2h, or halfway to 2h + 2
  vec2 fraction = vec2(pixel & 1) * 0.5;
  vec4 sum = vec4(0.0);
  float totalWeight = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    ivec2 offset = ivec2(corner & 1, corner >> 1);
    vec2 bilinear = mix(vec2(1.0) - fraction, fraction, vec2(offset));
    ivec2 texel = min(firstTexel + offset, lastTexel);
    ivec2 texelPixel = min(2 * texel, ivec2(frame.viewportSize.xy) - 1);
    float texelDepth = texelFetch(depthBuffer, texelPixel, 0).r;
    if (bilinear.x * bilinear.y == 0.0 || texelDepth <= 0.0) continue;
    float planeDistance = abs(dot(worldPosition(texelPixel, texelDepth) - position, normal));
    float geometry = clamp(1.0 - planeDistance / tolerance, 0.0, 1.0) *
                     pow(max(dot(normal, normalize(texelFetch(normalBuffer, texelPixel, 0).xyz)), 0.0), kNormalPower);
    sum += bilinear.x * bilinear.y * geometry * indirectTexel(texel);
    totalWeight += bilinear.x * bilinear.y * geometry;
  }
  // A pixel whose texels all lie on other surfaces (a one-pixel sliver) takes the texel of the 2×2 block it belongs to.
  return totalWeight > 0.0 ? sum / totalWeight : indirectTexel(min(firstTexel, lastTexel));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;

  vec3 radiance;
  vec3 radianceWithoutGi = vec3(0.0);
  vec4 indirect = vec4(0.0);
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  if (depth <= 0.0) {
    vec4 world = frame.inverseViewProjection * vec4(pixelToNdc(vec2(pixel), frame.viewportSize), 1.0, 1.0);
    vec3 direction = normalize(world.xyz / world.w - frame.cameraPosition.xyz);
    radiance = evaluateSky(frame.sky, direction);
  } else {
    vec3 albedo = texelFetch(albedoBuffer, pixel, 0).rgb;
    if (frame.lightCountAndExposure.z > 0.0) indirect = edgeAwareIndirect(pixel, depth);
    vec3 direct = imageLoad(directIrradiance, pixel).rgb;
    vec3 emission = texelFetch(emissionBuffer, pixel, 0).rgb;
    radianceWithoutGi = emission + albedo * (1.0 / kPi) * direct;
    radiance = emission + albedo * (1.0 / kPi) * (direct + indirect.rgb);
  }
  imageStore(finalRadiance, pixel, vec4(radiance, 1.0));
  imageStore(indirectUsed, pixel, indirect);
  imageStore(directRadiance, pixel, vec4(radianceWithoutGi, 1.0));
}
