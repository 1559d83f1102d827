#version 450
// DirectLighting: irradiance E_direct at each visible surface from the sun and the local lights, with their shadows.
// Lambertian only, so irradiance is all the composite needs (outgoing radiance = albedo/π · E).
#include "shared/renderer_interface.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindLightingFrame, std140) readonly buffer Frame { FrameConstants frame; };
layout(binding = kBindLightingLights) readonly buffer Lights { GpuLight lights[]; };
layout(binding = kBindLightingShadowViews) readonly buffer ShadowViews { ShadowView shadowViews[]; };
layout(binding = kBindLightingDepth) uniform sampler2D depthBuffer;
layout(binding = kBindLightingNormal) uniform sampler2D normalBuffer;
layout(binding = kBindLightingSunShadow) uniform sampler2DShadow sunShadowMap;
layout(binding = kBindLightingLocalShadows) uniform sampler2DArrayShadow localShadowMaps;
layout(binding = kBindLightingIrradiance, rgba32f) writeonly uniform image2D directIrradiance;
layout(binding = kBindLightingViewDistance, r32f) writeonly uniform image2D viewDistance;

// Offsets the receiver along its normal by a few shadow texels: removes acne on lit surfaces without the light leaking
// that a large constant depth bias causes at contact points.
const float kNormalOffsetTexels = 1.5;

float sunVisibility(vec3 position, vec3 normal) {
  vec3 offsetPosition = position + normal * (kNormalOffsetTexels * frame.sunShadowTexelSize);
  vec4 clip = frame.sunShadowMatrix * vec4(offsetPosition, 1.0);
  vec2 uv = ssvgiNdcToUv(clip.xy);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || clip.z > 1.0) return 1.0;
  return texture(sunShadowMap, vec3(uv, clip.z));
}

float localVisibility(GpuLight light, vec3 position, vec3 normal) {
  uint firstLayer = floatBitsToUint(light.intensityAndShadow.w);
  if (firstLayer == kNoShadow) return 1.0;
  // The texel footprint is the same for every face of a light, so the offset can be found before the face: choosing
  // the face from the offset point keeps it inside that face's frustum at cube seams.
  float texelSize = shadowViews[1u + firstLayer].texelWorldSize * distance(position, light.positionAndType.xyz);
  vec3 offsetPosition = position + normal * (kNormalOffsetTexels * texelSize);
  vec3 fromLight = offsetPosition - light.positionAndType.xyz;
  uint layer = firstLayer + (uint(light.positionAndType.w) == kLightPoint ? cubeFace(fromLight) : 0u);
  ShadowView view = shadowViews[1u + layer];
  vec4 clip = view.viewProjection * vec4(offsetPosition, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  vec2 uv = ssvgiNdcToUv(ndc.xy);
  if (clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 0.0;  // outside the cone
  return texture(localShadowMaps, vec4(uv, float(layer), ndc.z));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;

  float depth = texelFetch(depthBuffer, pixel, 0).r;
  if (depth <= 0.0) {  // reversed-Z: 0 is infinitely far, nothing was drawn
    imageStore(directIrradiance, pixel, vec4(0.0));
    imageStore(viewDistance, pixel, vec4(0.0));
    return;
  }
  vec4 world = frame.inverseViewProjection * vec4(ssvgiPixelToNdc(vec2(pixel), frame.viewportSize.xy), depth, 1.0);
  vec3 position = world.xyz / world.w;
  vec3 normal = normalize(texelFetch(normalBuffer, pixel, 0).xyz);

  vec3 irradiance = vec3(0.0);
  if (frame.sunDirectionAndEnabled.w > 0.0) {
    float cosine = dot(normal, frame.sunDirectionAndEnabled.xyz);
    if (cosine > 0.0) irradiance += frame.sunIlluminance * cosine * sunVisibility(position, normal);
  }
  uint lightCount = frame.localLightCount;
  for (uint i = 0u; i < lightCount; ++i) {
    GpuLight light = lights[i];
    vec3 toLight = light.positionAndType.xyz - position;
    float distanceSquared = dot(toLight, toLight);
    vec3 direction = toLight * inversesqrt(distanceSquared);
    float cosine = dot(normal, direction);
    if (cosine <= 0.0) continue;
    irradiance += localLightIrradianceScale(light, direction, distanceSquared) * cosine *
                  localVisibility(light, position, normal);
  }
  imageStore(directIrradiance, pixel, vec4(irradiance, 1.0));
  imageStore(viewDistance, pixel, vec4(distance(position, frame.cameraPosition.xyz)));
}
