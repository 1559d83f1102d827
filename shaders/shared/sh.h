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

SSVGI_SHARED_END

#endif
