// ssvgi's half-resolution results (Context::output(), Context::confidence()) resolved at a full-resolution pixel, for a
// host's GLSL composite (SPEC §4.6 "Shading", §8): `#include "ssvgi/resolve.glsl"` — the package installs it beside
// ssvgi.h — and shade the pixel with albedo/π · E, E = ssvgiResolve(…).irradiance.
//
// The 2×2 texels around the pixel (texel h holds full-resolution pixel 2h), each weighted bilinearly times how well
// its pixel lies on this pixel's surface (ssvgiPlaneWeight × ssvgiNormalWeight) — so that light does not bleed across
// silhouettes. A pixel whose texels all lie on other surfaces (a one-pixel sliver) takes the texel of the 2×2 block it
// belongs to. ssvgi's own half-resolution filter (TemporalUpsample) weighs its neighbours with the same two
// functions, so that what they keep apart the resolve keeps apart too.
#ifndef SSVGI_RESOLVE_GLSL
#define SSVGI_RESOLVE_GLSL

#include "ssvgi/pixel_coordinates.h"

// A neighbour counts fully on the pixel's tangent plane and not at all this fraction of the pixel's view distance off
// it: a depth test that tilted surfaces pass and depth edges and creases fail.
const float kSsvgiResolvePlaneTolerance = 0.02;

float ssvgiPlaneWeight(vec3 position, vec3 normal, float viewDistance, vec3 neighbourPosition) {
  float planeDistance = abs(dot(neighbourPosition - position, normal));
  return clamp(1.0 - planeDistance / (kSsvgiResolvePlaneTolerance * viewDistance), 0.0, 1.0);
}

// A neighbour's normal counts as dot^8 (half weight at about 24°), by three squarings: pow is a log and an exponential,
// which a CPU device (lavapipe) evaluates as two polynomials, and this runs for every tap of every pixel.
float ssvgiNormalWeight(vec3 normal, vec3 neighbourNormal) {
  float weight = max(dot(normal, neighbourNormal), 0.0);
  weight *= weight;
  weight *= weight;
  return weight * weight;
}

// The frame the results are resolved for, as given to Context::dispatch() (FrameDesc::camera) with its images.
struct SsvgiResolveView {
  mat4 inverseViewProjection;  // of the reversed-Z view-projection
  vec3 cameraPosition;
  vec2 size;                   // pixels
};

struct SsvgiResolved {
  vec3 irradiance;   // E_indirect, W/m²
  float confidence;  // 0–1 (Context::confidence())
};

// A pixel's surface point, from its depth (D32 reversed-Z).
vec3 ssvgiPixelPosition(SsvgiResolveView view, ivec2 pixel, float depth) {
  vec4 world = view.inverseViewProjection * vec4(ssvgiPixelToNdc(vec2(pixel), view.size), depth, 1.0);
  return world.xyz / world.w;
}

// `depth` and `normal` are the frame's (FrameDesc::depth, FrameDesc::normal); the pixel must show a surface (depth > 0).
SsvgiResolved ssvgiResolve(sampler2D irradiance, sampler2D confidence, sampler2D depth, sampler2D normal,
                           SsvgiResolveView view, ivec2 pixel) {
  vec3 position = ssvgiPixelPosition(view, pixel, texelFetch(depth, pixel, 0).r);
  vec3 surfaceNormal = normalize(texelFetch(normal, pixel, 0).xyz);
  float viewDistance = distance(position, view.cameraPosition);
  ivec2 lastTexel = textureSize(irradiance, 0) - 1;
  ivec2 firstTexel = pixel >> 1;  // the pixel sits at texel coordinate pixel/2: on texel 2h, or halfway to 2h + 2
  vec2 fraction = vec2(pixel & 1) * 0.5;
  vec4 sum = vec4(0.0);
  float totalWeight = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    ivec2 offset = ivec2(corner & 1, corner >> 1);
    vec2 bilinear = mix(vec2(1.0) - fraction, fraction, vec2(offset));
    ivec2 texel = min(firstTexel + offset, lastTexel);
    ivec2 texelPixel = min(2 * texel, ivec2(view.size) - 1);
    float texelDepth = texelFetch(depth, texelPixel, 0).r;
    if (bilinear.x * bilinear.y == 0.0 || texelDepth <= 0.0) continue;
    float geometry =
        ssvgiPlaneWeight(position, surfaceNormal, viewDistance, ssvgiPixelPosition(view, texelPixel, texelDepth)) *
        ssvgiNormalWeight(surfaceNormal, normalize(texelFetch(normal, texelPixel, 0).xyz));
    vec4 texelValue = vec4(texelFetch(irradiance, texel, 0).rgb, texelFetch(confidence, texel, 0).r);
    sum += bilinear.x * bilinear.y * geometry * texelValue;
    totalWeight += bilinear.x * bilinear.y * geometry;
  }
  if (totalWeight <= 0.0) {
    ivec2 own = min(firstTexel, lastTexel);
    sum = vec4(texelFetch(irradiance, own, 0).rgb, texelFetch(confidence, own, 0).r);
    totalWeight = 1.0;
  }
  return SsvgiResolved(sum.rgb / totalWeight, sum.a / totalWeight);
}

#endif
