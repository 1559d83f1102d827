#version 450
// GBuffer: albedo, emission, world normal and motion of the visible surface (depth comes from the depth attachment).
#include "shared/renderer_interface.h"

layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec2 inUv;
layout(location = 2) in vec4 inClip;
layout(location = 3) in vec4 inPreviousClip;
layout(location = 4) in vec3 inColor;  // the vertices' colours (Vertex::color)

layout(binding = kBindDrawMaterials) readonly buffer Materials { GpuMaterial materials[]; };
layout(binding = kBindDrawBaseColor) uniform sampler2D baseColorTexture;
layout(binding = kBindDrawEmission) uniform sampler2D emissionTexture;
layout(push_constant) uniform Push { DrawPush draw; };

layout(location = 0) out vec4 outAlbedo;
layout(location = 1) out vec4 outEmission;
layout(location = 2) out vec4 outNormal;
layout(location = 3) out vec2 outMotion;

void main() {
  GpuMaterial material = materials[draw.material];
  // The view is sRGB: decoded to linear by the sampler.
  vec4 texel = material.baseColorTexture != kNoTexture ? texture(baseColorTexture, inUv) : vec4(1.0);
  if (texel.a < material.alphaCutoff) discard;  // cut out (Material::alphaCutoff)
  vec3 albedo = material.baseColor * texel.rgb * inColor;
  // Two-sided: a back face seen from the camera shades with the normal facing the camera.
  vec3 normal = normalize(inNormal);
  if (!gl_FrontFacing) normal = -normal;
  outAlbedo = vec4(albedo, 1.0);
  vec3 emission = material.emission;
  if (material.emissionTexture != kNoTexture) emission *= texture(emissionTexture, inUv).rgb;
  outEmission = vec4(emission, 0.0);
  outNormal = vec4(normal, 0.0);
  // Screen-space motion in UV units from last frame to this one (current - previous).
  vec2 current = ssvgiNdcToUv(inClip.xy / inClip.w);
  vec2 previous = ssvgiNdcToUv(inPreviousClip.xy / inPreviousClip.w);
  outMotion = current - previous;
}
