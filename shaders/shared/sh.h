// Real spherical harmonics, bands 0 and 1 ("SH2", 4 coefficients), exactly as SPEC §2 fixes them. Shared by the
// probe shaders and the host (sky projection), so both sides agree on the basis, its order and its scale.
//
// Coefficient order in a vec4: [Y00, Y1,-1, Y1,0, Y1,1], i.e. (constant, y, z, x).
// Projection with N uniform sphere samples: L_lm = (4π/N) Σ L(ω_i) Y_lm(ω_i).
#ifndef SSVGI_SHARED_SH_H
#define SSVGI_SHARED_SH_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

SSVGI_CONSTANT(float, kSh2Band0Basis, 0.282095f);  // Y00 = 1 / (2·sqrt(π))
SSVGI_CONSTANT(float, kSh2Band1Basis, 0.488603f);  // Y1m = sqrt(3 / (4π)) · (y, z, x)

// Convolving radiance with the clamped cosine lobe max(0, n·ω) scales band l by Â_l (Ramamoorthi & Hanrahan 2001,
// "An Efficient Representation for Irradiance Environment Maps"): Â0 = π, Â1 = 2π/3. These turn radiance SH into
// irradiance SH, the E(n) of SPEC §2.
SSVGI_CONSTANT(float, kSh2Band0CosineConvolution, kPi);
SSVGI_CONSTANT(float, kSh2Band1CosineConvolution, 2.0f * kPi / 3.0f);

// RGB radiance as SH2: one vec4 of coefficients per colour channel.
struct Sh2Rgb {
  vec4 r;
  vec4 g;
  vec4 b;
};
SSVGI_CHECK_SIZE(Sh2Rgb, 48);

// The basis functions at a unit direction, in coefficient order.
SSVGI_INLINE vec4 sh2Basis(vec3 direction) {
  return vec4(kSh2Band0Basis, kSh2Band1Basis * direction.y, kSh2Band1Basis * direction.z,
              kSh2Band1Basis * direction.x);
}

// Irradiance E(n) = π·L00·Y00(n) + (2π/3)·Σ_m L1m·Y1m(n) on a surface with unit normal n, from one channel's radiance
// coefficients.
SSVGI_INLINE float sh2Irradiance(vec4 radianceCoefficients, vec3 normal) {
  vec4 cosineConvolution = vec4(kSh2Band0CosineConvolution, kSh2Band1CosineConvolution, kSh2Band1CosineConvolution,
                                kSh2Band1CosineConvolution);
  return dot(radianceCoefficients * cosineConvolution, sh2Basis(normal));
}

SSVGI_INLINE vec3 sh2Irradiance(Sh2Rgb radiance, vec3 normal) {
  return vec3(sh2Irradiance(radiance.r, normal), sh2Irradiance(radiance.g, normal), sh2Irradiance(radiance.b, normal));
}


// Irradiance E(n) from one channel's radiance coefficients, read as the light of a cone: the form of Hazel's
// non-linear reconstruction (Geomerics 2017), E = mean · (a + (1 − a)(p + 1) qᵖ) with q = (1 + n·d) / 2, fitted so
// that it is exact where it can be. With r = |band 1's gradient| / (2 · mean) the light's directionality,
//   r ≤ 1/2  a = 1 − 2r, p = 1: the linear formula itself, exact for uniform light plus light from one hemisphere;
//   r > 1/2  a = 0, p = 4r − 1: a uniform cone of half-angle α has r = (1 + cos α) / 2, and this gives the surface
//            facing it exactly πL·sin²α, and the surface facing away none, where the linear formula gives a small
//            source 3/4 of its light facing it and rings to −1/4 of it facing away.
// It keeps the mean over all normals and is never negative. Hazel's own fit (p = 1 + 2r, a = (1 − r)/(1 + r)) errs
// for broad light: a surface facing a lit hemisphere gets 7/6 of its light, one facing away 1/6 (QUALITY.md,
// "Emitters": it failed the tests of a floor under the sky and of a sunlit wall by 3–6 %).
SSVGI_INLINE float sh2ConeIrradiance(vec4 radianceCoefficients, vec3 normal) {
  float mean = kSh2Band0CosineConvolution * kSh2Band0Basis * radianceCoefficients.x;  // E averaged over all normals
  if (!(mean > 0.0f)) return 0.0f;
  // The linear formula's E(n) = mean + dot(gradient, n).
  vec3 gradient = (kSh2Band1CosineConvolution * kSh2Band1Basis) *
                  vec3(radianceCoefficients.w, radianceCoefficients.y, radianceCoefficients.z);
  float gradientLength = length(gradient);
  if (!(gradientLength > 1e-6f * mean)) return mean;
  float directionality = min(0.5f * gradientLength / mean, 1.0f);
  float q = clamp(0.5f * (1.0f + dot(gradient, normal) / gradientLength), 0.0f, 1.0f);
  float a = max(1.0f - 2.0f * directionality, 0.0f);
  float p = max(4.0f * directionality - 1.0f, 1.0f);
  return mean * (a + (1.0f - a) * (p + 1.0f) * pow(q, p));
}

// Irradiance from a uniform cone of unit radiance and solid angle `solidAngle` (0..4π) on a surface whose normal
// makes cosine `cosine` with the cone's axis: π·sin²α·cosθ where the whole cone is above the surface's horizon, none
// where it is wholly below, and between, the horizon-clipped cap (Snyder's sphere-light form). A cone wider than a
// hemisphere is the whole sphere less the opposite cone.
SSVGI_INLINE float uniformConeIrradiance(float solidAngle, float cosine) {
  bool wide = solidAngle > 2.0f * kPi;
  float capAngle = wide ? 4.0f * kPi - solidAngle : solidAngle;
  float cosTheta = wide ? -cosine : cosine;
  float cosAlpha = clamp(1.0f - capAngle / (2.0f * kPi), 0.0f, 1.0f);
  float sinSquared = 1.0f - cosAlpha * cosAlpha;
  float sinAlpha = sqrt(sinSquared);
  float cap;
  if (cosTheta >= sinAlpha) {
    cap = kPi * sinSquared * cosTheta;
  } else if (cosTheta <= -sinAlpha) {
    cap = 0.0f;
  } else {
    float sinTheta = sqrt(max(1.0f - cosTheta * cosTheta, 0.0f));
    float cotAlpha = cosAlpha / max(sinAlpha, 1e-6f);
    float y = clamp(-cotAlpha * cosTheta / max(sinTheta, 1e-6f), -1.0f, 1.0f);
    float crossing = sinTheta * sqrt(max(1.0f - y * y, 0.0f));
    cap = (cosTheta * acos(y) - cotAlpha * crossing) * sinSquared + atan(crossing, cotAlpha);
  }
  return wide ? kPi - cap : cap;
}

// How bright linear RGB looks: Rec. 709 luminance.
SSVGI_INLINE float rec709Luminance(vec3 rgb) { return dot(rgb, vec3(0.2126f, 0.7152f, 0.0722f)); }

// Below this fraction of its mean a channel's irradiance is taken for ringing, and the hue moves toward the mean's.
SSVGI_CONSTANT(float, kSh2HueGuardFraction, 0.5f);

// The irradiance the gather reads from a probe's RGB SH2 (SPEC §6.7): never negative, and never a hue the probe's
// light could not give. Each channel alone is read as a cone (sh2ConeIrradiance). Where one channel falls far below its
// mean while another does not — light from a small coloured source, read opposite it — the channels disagree only
// because each is read on its own: next to a cyan panel under warm light, the per-channel clamp of the linear formula
// left red where cyan rang below zero, a halo the scene does not have. There the hue moves toward the mean light's
// hue (a mix of the light the probe sees, so a hue it can give), fully once some channel reaches zero, and the
// luminance stays the channels' own.
SSVGI_INLINE vec3 sh2IrradianceWithoutRinging(Sh2Rgb radiance, vec3 normal) {
  vec3 perChannel = vec3(sh2ConeIrradiance(radiance.r, normal), sh2ConeIrradiance(radiance.g, normal),
                         sh2ConeIrradiance(radiance.b, normal));
  vec3 mean = (kSh2Band0CosineConvolution * kSh2Band0Basis) * vec3(radiance.r.x, radiance.g.x, radiance.b.x);
  float meanLuminance = rec709Luminance(mean);
  if (!(meanLuminance > 0.0f)) return vec3(0.0f);
  // The lowest channel as a fraction of its mean, over the channels that carry light (a channel the light has none
  // of, as red in pure cyan, cannot ring).
  float lowestFraction = 1.0f;
  for (int channel = 0; channel < 3; ++channel) {
    if (mean[channel] > 1e-3f * meanLuminance) lowestFraction = min(lowestFraction, perChannel[channel] / mean[channel]);
  }
  float towardMeanHue = clamp(1.0f - lowestFraction / kSh2HueGuardFraction, 0.0f, 1.0f);
  vec3 meanHue = mean * (rec709Luminance(perChannel) / meanLuminance);
  return max(mix(perChannel, meanHue, towardMeanHue), vec3(0.0f));
}

// Arithmetic on RGB SH2, channel by channel: what sums, means, blends and projections of radiance SH are made of.
SSVGI_INLINE Sh2Rgb sh2Zero() { return Sh2Rgb(vec4(0.0f), vec4(0.0f), vec4(0.0f)); }
SSVGI_INLINE Sh2Rgb sh2Add(Sh2Rgb a, Sh2Rgb b) { return Sh2Rgb(a.r + b.r, a.g + b.g, a.b + b.b); }
SSVGI_INLINE Sh2Rgb sh2Scale(Sh2Rgb a, float factor) { return Sh2Rgb(a.r * factor, a.g * factor, a.b * factor); }
// A weighted sum over its total weight: the weighted mean.
SSVGI_INLINE Sh2Rgb sh2Divide(Sh2Rgb a, float divisor) { return Sh2Rgb(a.r / divisor, a.g / divisor, a.b / divisor); }
// (1 − t)·a + t·b.
SSVGI_INLINE Sh2Rgb sh2Mix(Sh2Rgb a, Sh2Rgb b, float t) {
  return Sh2Rgb(mix(a.r, b.r, t), mix(a.g, b.g, t), mix(a.b, b.b, t));
}

// One sample's term of the projection: radiance L arriving from a direction, times `weightedBasis`, the direction's
// sh2Basis times the sample's weight (4π/N for N uniform samples).
SSVGI_INLINE Sh2Rgb sh2Project(vec3 radiance, vec4 weightedBasis) {
  return Sh2Rgb(radiance.r * weightedBasis, radiance.g * weightedBasis, radiance.b * weightedBasis);
}

// The radiance the SH2 holds in a direction, given the direction's sh2Basis.
SSVGI_INLINE vec3 sh2Evaluate(Sh2Rgb radiance, vec4 basis) {
  return vec3(dot(radiance.r, basis), dot(radiance.g, basis), dot(radiance.b, basis));
}

SSVGI_SHARED_END

#endif
