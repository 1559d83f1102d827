// The sky: an analytic clear daylight sky and the GPU parameters that select it, shared by the shaders (probe rays that
// miss, the reference path tracer, the background) and the host (its SH projection for the GI, SPEC §3), so that every
// consumer sees the same radiance for the same direction.
#ifndef SSVGI_SHARED_SKY_H
#define SSVGI_SHARED_SKY_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

// SkyParameters::uniformRadianceAndKind.w; the values of renderer SkyKind.
SSVGI_CONSTANT(uint, kSkyKindNone, 0u);
SSVGI_CONSTANT(uint, kSkyKindDefault, 1u);
SSVGI_CONSTANT(uint, kSkyKindUniform, 2u);

struct SkyParameters {
  vec4 uniformRadianceAndKind;    // xyz: the radiance of kSkyKindUniform, W/(sr·m²); w: the kind, as a float
  vec4 sunDirectionAndIntensity;  // xyz: unit vector towards the sun (shapes kSkyKindDefault); w: its multiplier
};
SSVGI_CHECK_SIZE(SkyParameters, 32);

// Scales the analytic sky so that with intensity 1 it delivers 1–2 W/m² on an upward surface while the sun is well
// above the horizon (1.2 at 15° elevation, 1.5 at 45°, 1.7 at 90°; luminance-weighted), a plausible share next to the
// ~5–6 W/m² sun of the built-in scenes.
SSVGI_CONSTANT(float, kSkyRadianceScale, 0.75f);

// Radiance of the analytic clear sky, W/(sr·m²), for a unit direction. It is evaluated for every probe ray that misses,
// so it is a handful of arithmetic operations with no loops or tables.
//
// Above the horizon it has the shape of the CIE clear sky (CIE S 011/E:2003, standard sky type 12): luminance
// ∝ gradation(θ) · indicatrix(γ), with θ the zenith angle of the direction and γ its angle to the sun:
//   gradation(θ) = 1 - exp(-0.32 / cos θ)                 dark zenith (0.27) brightening to the horizon (1);
//   indicatrix(γ) = 0.91 + 0.45 cos²γ + 10 exp(-3γ)       haze scattering plus the circumsolar brightening.
// Colour is added on top: the gradation part goes from a saturated blue at the zenith to a pale, whitish blue at the
// horizon, the circumsolar part is warm white. The sun disc itself is not part of the sky: the sun is a separate delta
// light (renderer Sun). Below the horizon the radiance is a dim constant standing in for the ground, so the function is
// defined everywhere. The whole sky fades out as the sun sets, reaching black at the end of civil twilight (sun 6°
// below the horizon), so a time-of-day cycle gets a dark night.
SSVGI_INLINE vec3 skyRadiance(vec3 direction, vec3 sunDirection, float intensity) {
  float daylight = smoothstep(-0.1f, 0.1f, sunDirection.y);  // sin(±6°) ≈ ±0.1
  float scale = kSkyRadianceScale * intensity * daylight;
  float cosZenith = direction.y;
  if (cosZenith < 0.0f) {
    return scale * vec3(0.12f, 0.11f, 0.10f);
  }
  // max(): at the horizon exp(-0.32/0) is 0; keep the division finite.
  float gradation = 1.0f - exp(-0.32f / max(cosZenith, 1e-4f));
  float cosSunAngle = clamp(dot(direction, sunDirection), -1.0f, 1.0f);
  float haze = 0.91f + 0.45f * cosSunAngle * cosSunAngle;
  float circumsolar = 10.0f * exp(-3.0f * acos(cosSunAngle));
  vec3 skyColour = mix(vec3(0.80f, 0.90f, 1.00f), vec3(0.25f, 0.45f, 1.00f), sqrt(cosZenith));
  vec3 circumsolarColour = vec3(1.00f, 0.92f, 0.80f);
  return scale * gradation * (haze * skyColour + circumsolar * circumsolarColour);
}

// The sky's radiance in a unit direction for any kind: what a ray that leaves the scene sees.
SSVGI_INLINE vec3 evaluateSky(SkyParameters sky, vec3 direction) {
  uint kind = uint(sky.uniformRadianceAndKind.w);
  if (kind == kSkyKindUniform) {
    return vec3(sky.uniformRadianceAndKind);
  }
  if (kind == kSkyKindDefault) {
    return skyRadiance(direction, vec3(sky.sunDirectionAndIntensity), sky.sunDirectionAndIntensity.w);
  }
  return vec3(0.0f);
}

SSVGI_SHARED_END

#endif
