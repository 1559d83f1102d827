// GPU structs, binding slots and constants of the host renderer, shared by its shaders and renderer/*.cpp.
#ifndef SSVGI_SHARED_RENDERER_INTERFACE_H
#define SSVGI_SHARED_RENDERER_INTERFACE_H

#include "shared/glsl_cpp.h"
#include "ssvgi/pixel_coordinates.h"
#include "shared/sh.h"
#include "shared/sky.h"

SSVGI_SHARED_BEGIN

// Shadowed local lights: a point light takes 6 layers of the local shadow array (cube faces +X,-X,+Y,-Y,+Z,-Z), a spot
// light one. Lights past the layer budget are drawn unshadowed (and reported by the renderer).
SSVGI_CONSTANT(uint, kMaxShadowLayers, 48u);
SSVGI_CONSTANT(uint, kNoShadow, 0xffffffffu);
SSVGI_CONSTANT(uint, kLightPoint, 0u);
SSVGI_CONSTANT(uint, kLightSpot, 1u);
SSVGI_CONSTANT(uint, kNoTexture, 0xffffffffu);

struct FrameConstants {
  mat4 viewProjection;          // world -> clip, reversed-Z: the camera's infinite perspective, or an extra view's
                                // perspective or orthographic projection
  mat4 inverseViewProjection;   // clip -> world
  mat4 previousViewProjection;  // last frame's, for motion vectors
  mat4 sunShadowMatrix;         // world -> sun shadow clip (orthographic, [0,1] depth)
  vec4 cameraPosition;          // xyz: world position (of an orthographic view: the centre of its near plane)
  vec4 cameraForward;           // xyz: unit view direction
  vec4 viewportSize;            // width, height, 1/width, 1/height
  vec4 sunDirectionAndEnabled;  // xyz: unit vector towards the sun; w: 1 when the sun is on
  vec3 sunIlluminance;          // irradiance on a surface facing the sun, W/m²
  float sunShadowTexelSize;     // metres
  uint localLightCount;
  float exposure;               // multiplier before tonemapping
  uint addsIndirectLight;       // 1: the composite adds albedo/π · ssvgi's indirect irradiance
  uint shownLight;              // the light the final image shows on surfaces, kShow* (renderer::ShownLight)
  SkyParameters sky;
};
SSVGI_CHECK_SIZE(FrameConstants, 4 * 64 + 6 * 16 + 32);

// The light the composite gives surfaces beyond ssvgi's reach (SPEC §6.4: a host blends to a fallback where ssvgi knows
// little). Outside ssvgi's voxel volume there are no voxels and no probes stand among them: the gather finds none for
// a surface there and gives it no light at all, and ssvgi's confidence there says so. There the composite blends to
// the sky's irradiance, E = mix(E_sky(n), E_ssvgi, confidence): the light of distant ground under open sky, which
// sees the sky alone. Inside the volume it does not: there a low confidence means space no view has observed, where
// unknown is not sky (a roof the camera never saw).
struct CompositeFallback {
  vec3 knownVolumeMinimum;  // the corner of ssvgi's voxel volume (ssvgi::Context::voxelVolume())
  uint blendsToFallback;    // 1 when the composite blends to the fallback (GI on), 0 when not
  vec3 knownVolumeMaximum;  // its opposite corner
  uint unused;
  Sh2Rgb skyRadiance;       // the host's sky as SH2, as ssvgi is given it (ssvgi::FrameDesc::skyRadianceSh)
};
SSVGI_CHECK_SIZE(CompositeFallback, 2 * 16 + 48);

// What the composite's final radiance holds on surfaces (the sky stays): all the light, direct and emitted light only,
// or only the GI's light, albedo/π · E_indirect.
SSVGI_CONSTANT(uint, kShowAllLight, 0u);
SSVGI_CONSTANT(uint, kShowDirectLight, 1u);
SSVGI_CONSTANT(uint, kShowIndirectLight, 2u);

// A local light as the lighting shader reads it.
struct GpuLight {
  vec4 positionAndType;         // xyz: world position; w: kLightPoint / kLightSpot
  vec4 directionAndRange;       // xyz: spot axis (away from the light); w: range, 0 = unlimited
  vec4 intensityAndShadow;      // rgb: radiant intensity, W/sr; w: first shadow layer (uintBitsToFloat), kNoShadow
  float cosInnerCone;           // cos(inner cone angle)
  float cosOuterCone;           // cos(outer cone angle)
  vec2 unused;
};
SSVGI_CHECK_SIZE(GpuLight, 64);

// One rendered shadow view: a sun cascade or a face/spot of the local shadow array.
struct ShadowView {
  mat4 viewProjection;          // world -> clip, [0,1] depth
  float texelWorldSize;         // size of a shadow texel at unit distance (perspective) or in metres (ortho)
  float unused0;
  float unused1;
  float unused2;
};
SSVGI_CHECK_SIZE(ShadowView, 80);

struct GpuInstance {
  mat4 model;
  mat4 previousModel;
  mat4 normalMatrix;            // inverse transpose of model (upper 3×3 used)
};
SSVGI_CHECK_SIZE(GpuInstance, 192);

struct GpuMaterial {
  vec3 baseColor;               // linear
  uint baseColorTexture;        // kNoTexture when none
  vec3 emission;                // emitted radiance, W/(sr·m²), times the emission texture where there is one
  float alphaCutoff;            // Material::alphaCutoff: the texture's alpha below which the surface is cut out
  uint emissionTexture;         // kNoTexture when none
  uint padding0;
  uint padding1;
  uint padding2;
};
SSVGI_CHECK_SIZE(GpuMaterial, 48);

struct DrawPush {
  uint instance;
  uint material;
  uint shadowView;              // shadow passes: which ShadowView
  uint padding;
};
SSVGI_CHECK_SIZE(DrawPush, 16);

// Binding slots (descriptor set 0), one group per pass.
// GBuffer (gbuffer.vert/.frag) and Shadow (shadow.vert):
SSVGI_CONSTANT(uint, kBindDrawFrame, 0u);          // FrameConstants (uniform)
SSVGI_CONSTANT(uint, kBindDrawInstances, 1u);      // GpuInstance[]
SSVGI_CONSTANT(uint, kBindDrawMaterials, 2u);      // GpuMaterial[]
SSVGI_CONSTANT(uint, kBindDrawBaseColor, 3u);      // the draw's base colour texture (sRGB)
SSVGI_CONSTANT(uint, kBindDrawShadowViews, 4u);
SSVGI_CONSTANT(uint, kBindDrawEmission, 5u);        // the draw's emission texture (sRGB)    // ShadowView[]
// DirectLighting (direct_lighting.comp):
SSVGI_CONSTANT(uint, kBindLightingFrame, 0u);
SSVGI_CONSTANT(uint, kBindLightingLights, 1u);       // GpuLight[]
SSVGI_CONSTANT(uint, kBindLightingShadowViews, 2u);  // ShadowView[]
SSVGI_CONSTANT(uint, kBindLightingDepth, 3u);        // G-buffer depth (reversed-Z)
SSVGI_CONSTANT(uint, kBindLightingNormal, 4u);       // G-buffer world normal
SSVGI_CONSTANT(uint, kBindLightingSunShadow, 5u);    // sun shadow map (compare sampler)
SSVGI_CONSTANT(uint, kBindLightingLocalShadows, 6u); // local shadow array (compare sampler)
SSVGI_CONSTANT(uint, kBindLightingIrradiance, 7u);   // out: direct irradiance E_direct, rgba32f
SSVGI_CONSTANT(uint, kBindLightingViewDistance, 8u); // out: distance from the camera, r32f (0 where there is no surface)
// Composite (composite.comp):
SSVGI_CONSTANT(uint, kBindCompositeFrame, 0u);
SSVGI_CONSTANT(uint, kBindCompositeDepth, 1u);
SSVGI_CONSTANT(uint, kBindCompositeAlbedo, 2u);
SSVGI_CONSTANT(uint, kBindCompositeEmission, 3u);
SSVGI_CONSTANT(uint, kBindCompositeDirect, 4u);      // E_direct
SSVGI_CONSTANT(uint, kBindCompositeIndirect, 5u);    // E_indirect (from the GI; black until it exists or when off)
SSVGI_CONSTANT(uint, kBindCompositeFinal, 6u);       // out: linear HDR radiance, rgba32f
SSVGI_CONSTANT(uint, kBindCompositeIndirectUsed, 7u); // out: the E_indirect each pixel was shaded with, rgba32f;
                                                      // a: the GI's confidence there (0 with GI off)
SSVGI_CONSTANT(uint, kBindCompositeNormal, 8u);       // G-buffer world normal (edge-aware sampling of E_indirect)
SSVGI_CONSTANT(uint, kBindCompositeConfidence, 9u);   // the GI's confidence of E_indirect (ssvgi::Context::confidence)
SSVGI_CONSTANT(uint, kBindCompositeDirectRadiance, 10u); // out: emission + albedo/π · E_direct, rgba16f: the light
                                                          // without the GI's, ssvgi's lit frame (FrameDesc::litAlbedo)
SSVGI_CONSTANT(uint, kBindCompositeFallback, 11u);    // CompositeFallback
// Tonemap (tonemap.comp):
SSVGI_CONSTANT(uint, kBindTonemapFrame, 0u);
SSVGI_CONSTANT(uint, kBindTonemapInput, 1u);
SSVGI_CONSTANT(uint, kBindTonemapOutput, 2u);        // out: rgba8, sRGB-encoded
// SkyMap (sky_map.comp):
SSVGI_CONSTANT(uint, kBindSkyMapFrame, 0u);
SSVGI_CONSTANT(uint, kBindSkyMapOutput, 1u);         // out: the sky's radiance, rgba16f, equirectangular (sky_map.h)

// Radiant intensity reaching a point from a local light, per unit of cos(incidence): I · spot · window / d², as glTF's
// KHR_lights_punctual recommends (smooth range window, quadratic spot falloff).
SSVGI_INLINE vec3 localLightIrradianceScale(GpuLight light, vec3 toLight, float distanceSquared) {
  float range = light.directionAndRange.w;
  float window = 1.0f;
  if (range > 0.0f) {
    float ratio = distanceSquared / (range * range);
    float fade = clamp(1.0f - ratio * ratio, 0.0f, 1.0f);
    window = fade * fade;
  }
  float spot = 1.0f;
  if (uint(light.positionAndType.w) == kLightSpot) {
    float cosAngle = dot(-toLight, vec3(light.directionAndRange));
    float t = clamp((cosAngle - light.cosOuterCone) / max(light.cosInnerCone - light.cosOuterCone, 1e-4f), 0.0f, 1.0f);
    spot = t * t;
  }
  return vec3(light.intensityAndShadow) * (spot * window / max(distanceSquared, 1e-8f));
}

// The cube face a point lies in as seen from a point light (+X,-X,+Y,-Y,+Z,-Z), matching the renderer's face views.
SSVGI_INLINE uint cubeFace(vec3 fromLight) {
  vec3 a = abs(fromLight);
  if (a.x >= a.y && a.x >= a.z) return fromLight.x > 0.0f ? 0u : 1u;
  if (a.y >= a.z) return fromLight.y > 0.0f ? 2u : 3u;
  return fromLight.z > 0.0f ? 4u : 5u;
}

SSVGI_SHARED_END

#endif
