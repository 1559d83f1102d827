// SH2 (shaders/shared/sh.h), the Halton direction set (shaders/shared/sampling.h) and the sky (shaders/shared/sky.h,
// renderer/sky.h), checked against analytic values and brute-force integration (SPEC §2).
#include "sky.h"
#include "white_and_colour.h"

#include "shared/probe_interface.h"
#include "shared/sampling.h"
#include "shared/sky_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace ssvgi::renderer {
namespace {

using RadianceField = std::function<glm::vec3(glm::vec3 direction)>;

constexpr double kPi = 3.14159265358979323846;

// ∫ L(ω) weight(n·ω) dω over the sphere, by the midpoint rule on a grid in (t = n·ω, φ) about n, where dω = dt dφ.
// The resolution is even so that a cell edge lies at t = 0, where max(0, t) has its kink: the rule keeps its
// O(1/resolution²) error, about 1e-5 relative here.
glm::dvec3 integrateOverSphere(const RadianceField& radiance, glm::vec3 normal,
                               const std::function<double(double cosAngle)>& weight) {
  constexpr int kResolution = 256;
  const glm::vec3 helper = std::abs(normal.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::dvec3 tangent = glm::normalize(glm::cross(helper, normal));
  const glm::dvec3 bitangent = glm::cross(glm::dvec3(normal), tangent);
  glm::dvec3 sum{0.0};
  for (int row = 0; row < kResolution; ++row) {
    const double cosAngle = -1.0 + 2.0 * (row + 0.5) / kResolution;
    const double sinAngle = std::sqrt(1.0 - cosAngle * cosAngle);
    for (int column = 0; column < kResolution; ++column) {
      const double phi = 2.0 * kPi * (column + 0.5) / kResolution;
      const glm::dvec3 direction = sinAngle * std::cos(phi) * tangent + sinAngle * std::sin(phi) * bitangent +
                                   cosAngle * glm::dvec3(normal);
      sum += glm::dvec3(radiance(glm::vec3(direction))) * weight(cosAngle);
    }
  }
  return sum * (2.0 * 2.0 * kPi / (kResolution * kResolution));
}

// Irradiance E(n) = ∫ L(ω) max(0, n·ω) dω, the quantity SH2 irradiance approximates.
glm::dvec3 bruteForceIrradiance(const RadianceField& radiance, glm::vec3 normal) {
  return integrateOverSphere(radiance, normal, [](double cosAngle) { return std::max(0.0, cosAngle); });
}

// The part of E(n) carried by SH band l: Â_l · Σ_m L_lm Y_lm(n), which by the addition theorem
// Σ_m Y_lm(n) Y_lm(ω) = (2l+1)/(4π) P_l(n·ω) is Â_l (2l+1)/(4π) ∫ L(ω) P_l(n·ω) dω. Â_l is the clamped cosine's
// coefficient (Ramamoorthi & Hanrahan 2001): Â2 = π/4, Â4 = -π/24 (odd bands above 1 vanish).
glm::dvec3 irradianceOfBand2(const RadianceField& radiance, glm::vec3 normal) {
  const auto legendre2 = [](double t) { return (3.0 * t * t - 1.0) / 2.0; };
  return (kPi / 4.0) * (5.0 / (4.0 * kPi)) * integrateOverSphere(radiance, normal, legendre2);
}
glm::dvec3 irradianceOfBand4(const RadianceField& radiance, glm::vec3 normal) {
  const auto legendre4 = [](double t) { return (35.0 * t * t * t * t - 30.0 * t * t + 3.0) / 8.0; };
  return (-kPi / 24.0) * (9.0 / (4.0 * kPi)) * integrateOverSphere(radiance, normal, legendre4);
}

// The first moments of the Halton directions: SamplingTest checks that the mean of the first N directions is within
// 3/N of zero per component, which bounds the quadrature error of projecting low-order fields onto SH.
double haltonMeanBound(uint32_t sampleCount) { return 3.0 / sampleCount; }

std::vector<glm::vec3> testNormals() {
  return {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(1.0f, 0.0f, 0.0f),
          glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f)), glm::normalize(glm::vec3(-2.0f, 1.0f, -1.0f))};
}

// A radiance field linear in the direction, L(ω) = a + b·(ω·d): exactly bands 0 and 1.
struct LinearRadiance {
  float constant = 1.0f;
  float slope = 0.6f;  // |slope| < constant keeps the radiance positive
  glm::vec3 axis = glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f));

  glm::vec3 operator()(glm::vec3 direction) const { return glm::vec3(constant + slope * glm::dot(direction, axis)); }

  // ∫ (a + b ω·d) Y_lm(ω) dω: ∫ Y00 dω = 4π·Y00, and ∫ (ω·d) ω_m dω = (4π/3) d_m for the band-1 functions ∝ ω_m.
  glm::vec4 coefficients() const {
    const float band1 = slope * shader::kSh2Band1Basis * 4.0f * shader::kPi / 3.0f;
    return glm::vec4(constant * shader::kSh2Band0Basis * 4.0f * shader::kPi, band1 * axis.y, band1 * axis.z,
                     band1 * axis.x);
  }

  // ∫ (a + b ω·d) max(0, n·ω) dω = π·a + (2π/3)·b·(n·d): write d = (n·d) n + d⊥; the d⊥ part integrates to zero by
  // symmetry about n, and ∫_{hemisphere} cos²θ dω = 2π·(1/3).
  double irradiance(glm::vec3 normal) const {
    return kPi * constant + (2.0 * kPi / 3.0) * slope * glm::dot(normal, axis);
  }
};

// Relative error of exact identities computed with SPEC §2's 6-digit basis constants: Y00²·4π = 1.0000014 and
// Y1²·4π/3 = 1.0000020 instead of 1, plus a few float roundings (6e-8 each).
constexpr double kBasisConstantTolerance = 3e-6;

TEST(Sh2Test, basisFollowsSpecOrderAndConstants) {
  const glm::vec4 alongX = shader::sh2Basis(glm::vec3(1.0f, 0.0f, 0.0f));
  const glm::vec4 alongY = shader::sh2Basis(glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::vec4 alongZ = shader::sh2Basis(glm::vec3(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(alongX, glm::vec4(0.282095f, 0.0f, 0.0f, 0.488603f));
  EXPECT_EQ(alongY, glm::vec4(0.282095f, 0.488603f, 0.0f, 0.0f));
  EXPECT_EQ(alongZ, glm::vec4(0.282095f, 0.0f, 0.488603f, 0.0f));
}

TEST(Sh2Test, projectionOfConstantRadianceHasBandZeroOnly) {
  const glm::vec3 radiance(1.7f, 0.3f, 2.5f);
  const shader::Sh2Rgb sh = projectToSh2([&radiance](glm::vec3) { return radiance; });
  const glm::vec4 coefficients[3] = {sh.r, sh.g, sh.b};
  for (int channel = 0; channel < 3; ++channel) {
    const double expectedL00 = radiance[channel] * shader::kSh2Band0Basis * 4.0 * kPi;
    // L00 sums N equal terms: exact up to float rounding of the result.
    EXPECT_NEAR(coefficients[channel].x, expectedL00, 1e-6 * expectedL00);
    // Band 1 of a constant is L·Y1·4π·(mean of the N directions), bounded by the Halton mean.
    const double band1Tolerance = radiance[channel] * shader::kSh2Band1Basis * 4.0 * kPi *
                                  haltonMeanBound(kSkyProjectionSampleCount);
    EXPECT_NEAR(coefficients[channel].y, 0.0, band1Tolerance);
    EXPECT_NEAR(coefficients[channel].z, 0.0, band1Tolerance);
    EXPECT_NEAR(coefficients[channel].w, 0.0, band1Tolerance);
  }
}

TEST(Sh2Test, constantRadianceGivesIrradiancePiTimesRadiance) {
  const float radiance = 0.8f;
  const glm::vec4 coefficients(radiance * shader::kSh2Band0Basis * 4.0f * shader::kPi, 0.0f, 0.0f, 0.0f);
  for (const glm::vec3& normal : testNormals()) {
    EXPECT_NEAR(shader::sh2Irradiance(coefficients, normal), kPi * radiance,
                kBasisConstantTolerance * kPi * radiance);
  }
}

TEST(Sh2Test, linearRadianceIsRepresentedExactly) {
  const LinearRadiance field;
  const glm::vec4 coefficients = field.coefficients();
  for (uint32_t index = 0; index < 64; ++index) {
    const glm::vec3 direction = shader::haltonSphereDirection(index);
    const double reconstructed = glm::dot(coefficients, shader::sh2Basis(direction));
    EXPECT_NEAR(reconstructed, field(direction).x, kBasisConstantTolerance * (field.constant + field.slope));
  }
}

TEST(Sh2Test, projectionOfLinearRadianceMatchesAnalyticCoefficients) {
  const LinearRadiance field;
  const glm::vec4 projected = projectToSh2(field).r;
  const glm::vec4 expected = field.coefficients();
  // Quasi-Monte Carlo error of the low-order moments, ~1/N per moment for the Halton set (measured 1.7/N).
  const double tolerance = (field.constant + field.slope) * 4.0 * kPi * shader::kSh2Band1Basis *
                           haltonMeanBound(kSkyProjectionSampleCount);
  for (int coefficient = 0; coefficient < 4; ++coefficient) {
    EXPECT_NEAR(projected[coefficient], expected[coefficient], tolerance) << "coefficient " << coefficient;
  }
}

TEST(Sh2Test, irradianceOfLinearRadianceIsPiAPlusTwoPiThirdsBTimesNDotD) {
  const LinearRadiance field;
  for (const glm::vec3& normal : testNormals()) {
    const double expected = field.irradiance(normal);
    EXPECT_NEAR(shader::sh2Irradiance(field.coefficients(), normal), expected, kBasisConstantTolerance * 4.0 * kPi);
  }
}

TEST(Sh2Test, irradianceMatchesNumericalCosineIntegral) {
  const LinearRadiance field;
  const shader::Sh2Rgb projected = projectToSh2(field);
  for (const glm::vec3& normal : testNormals()) {
    const double bruteForce = bruteForceIrradiance(field, normal).x;
    // The brute-force integral checks the analytic derivation independently of any SH code (midpoint rule, 1e-5).
    EXPECT_NEAR(bruteForce, field.irradiance(normal), 1e-4 * bruteForce);
    // Projection (measured 1e-4 relative) plus the brute-force error: well inside 1e-3.
    EXPECT_NEAR(shader::sh2Irradiance(projected.r, normal), bruteForce, 1e-3 * bruteForce);
  }
}

// ---- The gather's reading of SH2 (shared/sh.h: sh2ConeIrradiance, sh2IrradianceWithoutRinging) ----

// The SH2 of a single distant source: radiance `intensity` (W/m² at normal incidence) from one direction, as a delta:
// L_lm = I·Y_lm(d).
glm::vec4 deltaSourceCoefficients(float intensity, glm::vec3 direction) {
  return intensity * shader::sh2Basis(direction);
}

std::vector<glm::vec3> sphereOfNormals() {
  std::vector<glm::vec3> normals;
  for (int row = 0; row < 24; ++row) {
    const float cosAngle = -1.0f + 2.0f * (float(row) + 0.5f) / 24.0f;
    const float sinAngle = std::sqrt(1.0f - cosAngle * cosAngle);
    for (int column = 0; column < 48; ++column) {
      const float phi = 2.0f * shader::kPi * (float(column) + 0.5f) / 48.0f;
      normals.emplace_back(sinAngle * std::cos(phi), cosAngle, sinAngle * std::sin(phi));
    }
  }
  return normals;  // equal-area cells: their mean is the mean over the sphere
}

// A uniform cone of radiance L and half-angle α about an axis, and its exact SH2 coefficients: L00 = L·Y00·Ω with
// Ω = 2π(1 − cos α), and band 1 L·Y1·∫ω dω = L·Y1·π·sin²α·axis. Its exact irradiance on the surface facing the axis
// is π·L·sin²α.
struct UniformCone {
  float radiance = 1.0f;
  float halfAngle = 0.5f;
  glm::vec3 axis = glm::normalize(glm::vec3(0.4f, 1.0f, -0.3f));

  glm::vec3 operator()(glm::vec3 direction) const {
    return glm::vec3(glm::dot(direction, axis) >= std::cos(halfAngle) ? radiance : 0.0f);
  }
  glm::vec4 coefficients() const {
    const float solidAngle = 2.0f * shader::kPi * (1.0f - std::cos(halfAngle));
    const glm::vec3 band1 = radiance * shader::kSh2Band1Basis * shader::kPi * std::sin(halfAngle) *
                            std::sin(halfAngle) * axis;
    return {radiance * shader::kSh2Band0Basis * solidAngle, band1.y, band1.z, band1.x};
  }
};

TEST(Sh2ReadingTest, aUniformConeIsExactOnItsAxisWhateverItsWidth) {
  for (float degrees : {2.0f, 10.0f, 30.0f, 60.0f, 89.0f}) {
    const UniformCone cone{.halfAngle = glm::radians(degrees)};
    const double exact = kPi * cone.radiance * std::sin(cone.halfAngle) * std::sin(cone.halfAngle);
    EXPECT_NEAR(shader::sh2ConeIrradiance(cone.coefficients(), cone.axis), exact, 1e-4 * exact)
        << "half-angle " << degrees << "°";
  }
}

// Off the axis the reading is not exact, but nearer the truth than the linear formula, which flattens a small cone's
// light (3/4 of it facing it, 1/4 at 90° to it) — and facing away from it, where there is none, it gives none.
TEST(Sh2ReadingTest, aSmallConeIsNearerTheTruthThanTheLinearFormulaAndGivesNothingFacingAway) {
  const UniformCone cone{.halfAngle = glm::radians(10.0f)};
  const glm::vec3 helper = glm::normalize(glm::cross(cone.axis, glm::vec3(1.0f, 0.0f, 0.0f)));
  for (float degrees : {20.0f, 45.0f, 70.0f}) {
    const float angle = glm::radians(degrees);
    const glm::vec3 normal = std::cos(angle) * cone.axis + std::sin(angle) * helper;
    const double exact = bruteForceIrradiance(cone, normal).x;
    const double read = shader::sh2ConeIrradiance(cone.coefficients(), normal);
    const double linear = shader::sh2Irradiance(cone.coefficients(), normal);
    EXPECT_LT(std::abs(read - exact), std::abs(linear - exact)) << degrees << "° off the axis";
  }
  EXPECT_LT(shader::sh2Irradiance(cone.coefficients(), -cone.axis), 0.0f);  // the ringing the reading removes
  EXPECT_EQ(shader::sh2ConeIrradiance(cone.coefficients(), -cone.axis), 0.0f);
}

// Uniform light plus light from one hemisphere is exactly bands 0 and 1 in E, so the linear formula is exact there,
// and the reading must be the linear formula: a floor under the sky gets π·L, not Hazel's 7/6 of it.
TEST(Sh2ReadingTest, uniformPlusHemisphereLightIsTheLinearFormula) {
  for (float background : {0.0f, 0.3f, 2.0f}) {
    const UniformCone hemisphere{.radiance = 1.5f, .halfAngle = 0.5f * shader::kPi};
    const glm::vec4 coefficients =
        hemisphere.coefficients() + glm::vec4(background * shader::kSh2Band0Basis * 4.0f * shader::kPi, 0, 0, 0);
    for (const glm::vec3& normal : testNormals()) {
      const float linear = shader::sh2Irradiance(coefficients, normal);
      EXPECT_NEAR(shader::sh2ConeIrradiance(coefficients, normal), linear, 1e-4f * (linear + 1.0f))
          << "background " << background;
    }
  }
}

// Over all normals its mean is the linear formula's (π·L00·Y00: band 1 averages to nothing), and it is never negative.
TEST(Sh2ReadingTest, theMeanOverNormalsIsKeptAndNothingIsNegative) {
  constexpr uint32_t kNormals = 16384;
  for (float degrees : {5.0f, 40.0f, 90.0f}) {
    const glm::vec4 coefficients = UniformCone{.halfAngle = glm::radians(degrees)}.coefficients() +
                                   glm::vec4(0.1f * shader::kSh2Band0Basis * 4.0f * shader::kPi, 0, 0, 0);
    double sum = 0.0;
    float smallest = 1.0f;
    for (uint32_t index = 0; index < kNormals; ++index) {
      const float irradiance = shader::sh2ConeIrradiance(coefficients, shader::haltonSphereDirection(index));
      sum += irradiance;
      smallest = std::min(smallest, irradiance);
    }
    const double mean = shader::kSh2Band0CosineConvolution * shader::kSh2Band0Basis * coefficients.x;
    // Quasi-Monte Carlo over 16384 normals of a function with a sharp lobe: 0.5 % is a few times its error.
    EXPECT_NEAR(sum / kNormals, mean, 5e-3 * mean) << "half-angle " << degrees << "°";
    EXPECT_GE(smallest, 0.0f);
  }
}

// White ambient light and a small cyan source, both of which a white wall reflects unchanged: the light at every
// normal is a·white + b·cyan with a, b ≥ 0, so E has no hue outside that cone (testing::splitIntoWhiteAnd).
TEST(Sh2ReadingTest, aSmallColouredSourceBesideWhiteLightGivesNoHueOfItsOwn) {
  const glm::vec3 cyan(0.1f, 0.85f, 1.0f);
  const glm::vec3 toSource = glm::normalize(glm::vec3(0.0f, 0.2f, -1.0f));
  const float ambient = 0.5f;     // white radiance from everywhere: E = π/2 ≈ 1.6 W/m²
  const float intensity = 12.0f;  // the source: E up to 12 W/m² facing it, 3× the ambient's ringing margin
  const glm::vec4 ambientCoefficients(ambient * shader::kSh2Band0Basis * 4.0f * shader::kPi, 0.0f, 0.0f, 0.0f);
  const glm::vec4 sourceCoefficients = deltaSourceCoefficients(intensity, toSource);
  const shader::Sh2Rgb radiance{ambientCoefficients + cyan.r * sourceCoefficients,
                                ambientCoefficients + cyan.g * sourceCoefficients,
                                ambientCoefficients + cyan.b * sourceCoefficients};
  // The per-channel clamp of the linear formula leaves red where cyan rings below zero (the halo of issue 20): this
  // is what the test would catch.
  const testing::WhiteAndColour clamped = testing::splitIntoWhiteAnd(
      cyan, glm::max(shader::sh2Irradiance(radiance, -toSource), glm::vec3(0.0f)));
  EXPECT_LT(clamped.colour, -0.1);
  double lowestCyan = 1e9, lowestWhite = 1e9, largestOutside = 0.0;
  for (const glm::vec3& normal : sphereOfNormals()) {
    const glm::dvec3 irradiance = shader::sh2IrradianceWithoutRinging(radiance, normal);
    ASSERT_TRUE(glm::all(glm::greaterThanEqual(irradiance, glm::dvec3(0.0))));
    const testing::WhiteAndColour split = testing::splitIntoWhiteAnd(cyan, irradiance);
    lowestCyan = std::min(lowestCyan, split.colour / glm::length(irradiance));
    lowestWhite = std::min(lowestWhite, split.white / glm::length(irradiance));
    largestOutside = std::max(largestOutside, split.outside / glm::length(irradiance));
  }
  // The channels read alone give a cyan part of −118 % of |E| opposite the source; the guard must bring every
  // normal's cyan part to at least −2 % of |E|, a hue shift below what a viewer sees next to the white.
  EXPECT_GT(lowestCyan, -0.02);
  EXPECT_GT(lowestWhite, -0.02);
  EXPECT_LT(largestOutside, 0.02);
}

TEST(Sh2ReadingTest, lightWithoutAChannelKeepsItAtZero) {
  // Pure cyan light with no red at all: red stays 0 everywhere, and green and blue keep their ratio.
  const glm::vec4 source = deltaSourceCoefficients(5.0f, glm::vec3(0.0f, 1.0f, 0.0f));
  const shader::Sh2Rgb radiance{glm::vec4(0.0f), 0.5f * source, source};
  for (const glm::vec3& normal : sphereOfNormals()) {
    const glm::vec3 irradiance = shader::sh2IrradianceWithoutRinging(radiance, normal);
    ASSERT_EQ(irradiance.r, 0.0f);
    ASSERT_NEAR(irradiance.g, 0.5f * irradiance.b, 1e-5f * (1.0f + irradiance.b));
  }
}

// ---- A probe's sky read apart (shared/sh.h: uniformConeIrradiance; probe_interface.h: readProbeIrradiance) ----

// ∫ max(0, n·ω) dω over a cap of half-angle α about +Z, n at cosine `cosine` to it, by the midpoint rule on a grid
// in (t = cos θ, φ) over the cap, where dω = dt dφ: 1e-4 of π at 1024², the kink where n·ω = 0 included.
double capIrradianceByIntegration(double halfAngle, double cosine) {
  constexpr int kResolution = 1024;
  const double sine = std::sqrt(1.0 - cosine * cosine), lowest = std::cos(halfAngle);
  double sum = 0.0;
  for (int row = 0; row < kResolution; ++row) {
    const double t = lowest + (1.0 - lowest) * (row + 0.5) / kResolution, ring = std::sqrt(1.0 - t * t);
    for (int column = 0; column < kResolution; ++column) {
      const double phi = 2.0 * kPi * (column + 0.5) / kResolution;
      sum += std::max(0.0, sine * ring * std::cos(phi) + cosine * t);
    }
  }
  return sum * (1.0 - lowest) * 2.0 * kPi / (double(kResolution) * kResolution);
}

TEST(SkyConeReadingTest, aUniformConesIrradianceIsTheIntegralOverItAtEveryWidthAndAngle) {
  // Caps narrower and wider than a hemisphere, facing the surface, beside it, across its horizon and behind it.
  for (double degrees : {5.0, 30.0, 60.0, 90.0, 120.0, 170.0}) {
    const double halfAngle = degrees * kPi / 180.0;
    const float solidAngle = float(2.0 * kPi * (1.0 - std::cos(halfAngle)));
    for (double cosine : {1.0, 0.8, 0.5, 0.2, 0.0, -0.3, -0.7, -1.0}) {
      const double exact = capIrradianceByIntegration(halfAngle, cosine);
      EXPECT_NEAR(shader::uniformConeIrradiance(solidAngle, float(cosine)), exact, 1e-3 * (exact + 0.01))
          << "half-angle " << degrees << "°, cosine " << cosine;
    }
  }
}

// The probe ProbeTrace leaves after many updates where it sees `radiance` all round and the sky through the region
// `sky`: its radiance SH2 and its sky's visibility SH2, projected over a Fibonacci sphere of 2^18 directions.
shader::Probe probeSeeing(const RadianceField& radiance, const std::function<bool(glm::vec3)>& sky) {
  constexpr uint32_t kDirections = 1u << 18;
  glm::dvec4 radianceSum{0.0}, visibility{0.0};
  for (uint32_t i = 0; i < kDirections; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / kDirections, ring = std::sqrt(1.0 - y * y);
    const double phi = double(i) * kPi * (3.0 - std::sqrt(5.0));
    const glm::vec3 direction(ring * std::cos(phi), y, ring * std::sin(phi));
    const glm::dvec4 basis(shader::sh2Basis(direction));
    radianceSum += double(radiance(direction).x) * basis;
    visibility += (sky(direction) ? 1.0 : 0.0) * basis;
  }
  const glm::vec4 radianceSh(radianceSum * (4.0 * kPi / kDirections));
  return shader::makeProbe({radianceSh, radianceSh, radianceSh}, glm::vec4(visibility * (4.0 * kPi / kDirections)), 0u,
                           0u, shader::packProbeState(1, 0, shader::kProbeStateActive), 0u);
}

// A probe under a uniform sky of radiance L that sees it through the region `sky` and surfaces of radiance
// `surfaces(ω)` elsewhere, as ProbeTrace leaves it after many updates: its radiance SH2 and its sky's visibility SH2,
// projected over a fine direction set, with the host's sky L everywhere.
struct ProbeUnderASky {
  std::function<bool(glm::vec3)> sky;
  std::function<float(glm::vec3)> surfaces = [](glm::vec3) { return 0.0f; };
  float skyRadiance = 1.0f;

  glm::vec3 operator()(glm::vec3 direction) const {
    return glm::vec3(sky(direction) ? skyRadiance : surfaces(direction));
  }
  shader::Probe probe() const { return probeSeeing(*this, sky); }
  shader::Sh2Rgb hostSky() const {
    const glm::vec4 uniform(skyRadiance / shader::kSh2Band0Basis, 0.0f, 0.0f, 0.0f);
    return {uniform, uniform, uniform};
  }
};

// As ProbeUnderASky, under a sky whose radiance is linear in the direction — exactly what a host's SH2 sky holds.
struct ProbeUnderALinearSky {
  std::function<bool(glm::vec3)> sky;
  LinearRadiance skyRadiance;
  std::function<float(glm::vec3)> surfaces = [](glm::vec3) { return 0.0f; };

  glm::vec3 operator()(glm::vec3 direction) const {
    return sky(direction) ? skyRadiance(direction) : glm::vec3(surfaces(direction));
  }
  shader::Probe probe() const { return probeSeeing(*this, sky); }
  shader::Sh2Rgb hostSky() const {
    const glm::vec4 coefficients = skyRadiance.coefficients();
    return {coefficients, coefficients, coefficients};
  }
};

TEST(SkyConeReadingTest, skyThroughAnOpeningBesideLitSurfacesIsReadWithinTwoPercentWhereOneSh2ReadsItAsBroadLight) {
  // A 30° opening overhead in a dark ceiling, above a floor of radiance 0.5·L: the sky is a cap, read exactly, and the
  // surfaces a hemisphere, which SH2 holds exactly. Read as one SH2, the mix is broad light: the floor under the
  // opening gets too little of the sky (the hall's deficit in docs/QUALITY.md).
  const ProbeUnderASky hall{.sky = [](glm::vec3 d) { return d.y > std::cos(glm::radians(30.0f)); },
                            .surfaces = [](glm::vec3 d) { return d.y < 0.0f ? 0.5f : 0.0f; }};
  const shader::Probe probe = hall.probe();
  for (const glm::vec3& normal : sphereOfNormals()) {
    const double exact = bruteForceIrradiance(hall, normal).x;
    EXPECT_NEAR(shader::readProbeIrradiance(probe, normal, hall.hostSky()).x, exact, 0.02 * kPi * hall.skyRadiance)
        << "normal " << normal.x << "," << normal.y << "," << normal.z;
  }
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const double exactUp = bruteForceIrradiance(hall, up).x;
  EXPECT_LT(shader::sh2IrradianceWithoutRinging(shader::probeRadianceSh(probe), up).x, 0.9 * exactUp);
}

TEST(SkyConeReadingTest, skyAllAroundTheHorizonIsReadAsTheCapOfItsSpread) {
  // A ring of sky from the horizon to 30° above it (an open colonnade's arches all around): the solid angle of a 60°
  // cap (π), but its mean direction only 1/4 of a unit vector long. Read as that round cap about the zenith it would
  // light the floor with 3π/4·L where it gets π/4·L; the cap of its spread ((1 + cos α)/2 = 1/4: the upper
  // hemisphere) dimmed to its solid angle gives π/3·L, and within a fifth of the exact E on walls.
  const ProbeUnderASky colonnade{.sky = [](glm::vec3 d) { return d.y > 0.0f && d.y < 0.5f; }};
  const shader::Probe probe = colonnade.probe();
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  EXPECT_NEAR(bruteForceIrradiance(colonnade, up).x, kPi / 4.0, 0.01 * kPi);
  EXPECT_NEAR(shader::readProbeIrradiance(probe, up, colonnade.hostSky()).x, kPi / 3.0, 0.01 * kPi);
  EXPECT_NEAR(shader::uniformConeIrradiance(shader::kPi, 1.0f), 3.0 * kPi / 4.0, 1e-4);  // a round cap of its solid angle
  for (const glm::vec3 wall : {glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f)}) {
    const double exact = bruteForceIrradiance(colonnade, wall).x;
    EXPECT_NEAR(shader::readProbeIrradiance(probe, wall, colonnade.hostSky()).x, exact, exact / 5.0);
  }
}

TEST(SkyConeReadingTest, aSkyBrighterTowardsOneSideIsReadBrighterOnTheSurfacesThatFaceThatSide) {
  // A 60° opening overhead under a sky three times as bright towards the sun (56° from the zenith) as away from it,
  // over dim surfaces: the sky as a host's SH2 holds it, linear in the direction. Every normal's E within 2 % of π of
  // the exact, as for a uniform sky; read with the sky's radiance at the opening's middle alone, a wall facing the
  // sun's side gets as little as one facing away, and the error reached 5.7 % of π.
  const ProbeUnderALinearSky court{.sky = [](glm::vec3 d) { return d.y > 0.5f; },
                                   .skyRadiance = {.constant = 1.0f, .slope = 0.5f,
                                                   .axis = glm::normalize(glm::vec3(1.0f, 0.7f, 0.3f))},
                                   .surfaces = [](glm::vec3 d) { return d.y < 0.0f ? 0.2f : 0.05f; }};
  const shader::Probe probe = court.probe();
  double worst = 0.0;
  for (const glm::vec3& normal : sphereOfNormals()) {
    const double exact = bruteForceIrradiance(court, normal).x;
    const double read = shader::readProbeIrradiance(probe, normal, court.hostSky()).x;
    worst = std::max(worst, std::abs(read - exact) / kPi);
    EXPECT_NEAR(read, exact, 0.02 * kPi) << "normal " << normal.x << "," << normal.y << "," << normal.z;
  }
  std::printf("worst error over the normals: %.4f of pi\n", worst);
}

TEST(SkyConeReadingTest, aProbeThatSeesNoSkyIsReadAsBeforeAndOneThatSeesOnlySkyGetsPiLEverywhere) {
  const ProbeUnderASky closed{.sky = [](glm::vec3) { return false; },
                              .surfaces = [](glm::vec3 d) { return 1.0f + 0.5f * d.x; }};
  const shader::Probe inside = closed.probe();
  const ProbeUnderASky open{.sky = [](glm::vec3) { return true; }};
  const shader::Probe outside = open.probe();
  for (const glm::vec3& normal : sphereOfNormals()) {
    EXPECT_EQ(shader::readProbeIrradiance(inside, normal, closed.hostSky()),
              shader::sh2IrradianceWithoutRinging(shader::probeRadianceSh(inside), normal));
    EXPECT_NEAR(shader::readProbeIrradiance(outside, normal, open.hostSky()).x, kPi, 0.01 * kPi);
  }
}

TEST(SkyMapTest, theMapsCoordinatesFollowFrameDescsLayoutAndComeBackToTheirDirection) {
  // ssvgi::FrameDesc::skyRadianceMap: u the azimuth from +Z towards +X, 1/2 along +Z; v 0 at the zenith, 1 at the
  // nadir.
  EXPECT_NEAR(shader::skyMapCoordinates({0, 0, 1}).x, 0.5f, 1e-6f);
  EXPECT_NEAR(shader::skyMapCoordinates({1, 0, 0}).x, 0.75f, 1e-6f);
  EXPECT_NEAR(shader::skyMapCoordinates({-1, 0, 0}).x, 0.25f, 1e-6f);
  EXPECT_NEAR(shader::skyMapCoordinates({0, 0, 1}).y, 0.5f, 1e-6f);
  EXPECT_NEAR(shader::skyMapCoordinates({0, 1, 0}).y, 0.0f, 1e-6f);
  EXPECT_NEAR(shader::skyMapCoordinates({0, -1, 0}).y, 1.0f, 1e-6f);
  for (const glm::vec3& direction : sphereOfNormals()) {
    const glm::vec3 back = shader::skyMapDirection(shader::skyMapCoordinates(direction));
    EXPECT_NEAR(glm::distance(back, direction), 0.0f, 1e-5f) << direction.x << "," << direction.y << "," << direction.z;
  }
}

TEST(SamplingTest, radicalInverseMirrorsDigitsAboutTheRadixPoint) {
  EXPECT_EQ(shader::radicalInverse(0u, 2u), 0.0f);
  EXPECT_EQ(shader::radicalInverse(1u, 2u), 0.5f);
  EXPECT_EQ(shader::radicalInverse(2u, 2u), 0.25f);
  EXPECT_EQ(shader::radicalInverse(3u, 2u), 0.75f);
  EXPECT_EQ(shader::radicalInverse(6u, 2u), 0.375f);
  EXPECT_FLOAT_EQ(shader::radicalInverse(1u, 3u), 1.0f / 3.0f);
  EXPECT_FLOAT_EQ(shader::radicalInverse(2u, 3u), 2.0f / 3.0f);
  EXPECT_FLOAT_EQ(shader::radicalInverse(3u, 3u), 1.0f / 9.0f);
  EXPECT_FLOAT_EQ(shader::radicalInverse(5u, 3u), 2.0f / 3.0f + 1.0f / 9.0f);  // 12 in base 3 -> 0.21
}

// A probe that follows a change turns its directions by a random rotation per update (probeRecoveryRotation), so that
// an update's estimate is unbiased on its own: any fixed direction, turned by them, must be spread evenly over the
// sphere — mean 0 and second moment I/3 — and each turn must keep lengths and angles.
TEST(SamplingTest, randomRotationsTurnAFixedDirectionEvenlyOverTheSphereAndKeepAngles) {
  constexpr uint32_t kRotations = 4096;
  const glm::vec3 fixed = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
  const glm::vec3 other = glm::normalize(glm::vec3(-1.0f, 0.1f, 0.4f));
  glm::dvec3 mean(0.0);
  glm::dmat3 secondMoment(0.0);
  for (uint32_t frame = 0; frame < kRotations; ++frame) {
    const glm::vec4 rotation = shader::probeRecoveryRotation(frame, frame % shader::kProbeLevels);
    ASSERT_NEAR(glm::length(rotation), 1.0f, 1e-5f);
    const glm::vec3 turned = shader::rotateByQuaternion(fixed, rotation);
    ASSERT_NEAR(glm::length(turned), 1.0f, 1e-5f);
    ASSERT_NEAR(glm::dot(turned, shader::rotateByQuaternion(other, rotation)), glm::dot(fixed, other), 1e-5f);
    mean += glm::dvec3(turned) / double(kRotations);
    secondMoment += glm::outerProduct(glm::dvec3(turned), glm::dvec3(turned)) / double(kRotations);
  }
  // Uniform directions: each mean component has a standard error of √(1/3 / 4096) ≈ 0.009, each second moment of
  // about 0.005; the bounds are four to five of them.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(mean[axis], 0.0, 0.04) << "axis " << axis;
    for (int column = 0; column < 3; ++column)
      EXPECT_NEAR(secondMoment[axis][column], axis == column ? 1.0 / 3.0 : 0.0, 0.025) << axis << ", " << column;
  }
}

TEST(SamplingTest, haltonDirectionsPairBases2And3AndMapThemAsSpecified) {
  // Index 5: 101b -> 0.101b = 0.625 and 12 (base 3) -> 0.21 (base 3) = 7/9.
  const glm::vec2 point = shader::halton23(5u);
  EXPECT_FLOAT_EQ(point.x, 0.625f);
  EXPECT_FLOAT_EQ(point.y, 7.0f / 9.0f);
  // z = 1 - 2u = -0.25, φ = 2πv.
  const double z = -0.25;
  const double phi = 2.0 * kPi * 7.0 / 9.0;
  const double radius = std::sqrt(1.0 - z * z);
  const glm::vec3 direction = shader::haltonSphereDirection(5u);
  EXPECT_NEAR(direction.x, radius * std::cos(phi), 1e-6);  // float trigonometry: a few ulps
  EXPECT_NEAR(direction.y, radius * std::sin(phi), 1e-6);
  EXPECT_NEAR(direction.z, z, 1e-6);
}

TEST(SamplingTest, haltonDirectionsAreUnitLength) {
  for (uint32_t index = 0; index < kSkyProjectionSampleCount; ++index) {
    // sqrt, cos and sin each round to within a few float ulps (1.2e-7 each).
    EXPECT_NEAR(glm::length(shader::haltonSphereDirection(index)), 1.0f, 1e-6f) << "index " << index;
  }
}

TEST(SamplingTest, probeDirectionSetHasMeanNearZero) {
  glm::dvec3 sum{0.0};
  for (uint32_t index = 0; index < shader::kProbeRayDirectionCount; ++index) {
    sum += glm::dvec3(shader::haltonSphereDirection(index));
  }
  const glm::dvec3 mean = sum / double(shader::kProbeRayDirectionCount);
  // A low-discrepancy set integrates smooth functions with error O(log N / N) per dimension (Koksma–Hlawka with the
  // Halton discrepancy); the base-2 coordinate of the first 1024 points is exactly {i/1024}, so mean z is exactly 1/N.
  // 3/N = 0.003 sits above the measured 0.001 and far below the 0.018 standard deviation of a merely random set of
  // 1024 directions (1/sqrt(3N)), so it fails for a set that is not well spread.
  const double tolerance = haltonMeanBound(shader::kProbeRayDirectionCount);
  EXPECT_NEAR(mean.x, 0.0, tolerance);
  EXPECT_NEAR(mean.y, 0.0, tolerance);
  EXPECT_NEAR(mean.z, 0.0, tolerance);
}

TEST(SamplingTest, everyUpdateOf32DirectionsCoversBothHemispheresOfEachAxis) {
  // SPEC §2: a probe traces 32 directions per update, so each update on its own must look all around. The 32 directions
  // of each aligned block should split 16/16 across any plane through the centre; at least 12 on each side of the
  // x, y and z planes rules out clumping (a random set would miss this bound in several of the 192 checks).
  constexpr uint32_t kRaysPerUpdate = 32;
  for (uint32_t update = 0; update < shader::kProbeRayDirectionCount / kRaysPerUpdate; ++update) {
    for (int axis = 0; axis < 3; ++axis) {
      int positive = 0;
      int negative = 0;
      for (uint32_t ray = 0; ray < kRaysPerUpdate; ++ray) {
        const float component = shader::haltonSphereDirection(update * kRaysPerUpdate + ray)[axis];
        positive += component > 0.0f ? 1 : 0;
        negative += component < 0.0f ? 1 : 0;
      }
      EXPECT_GE(positive, 12) << "update " << update << " axis " << axis;
      EXPECT_GE(negative, 12) << "update " << update << " axis " << axis;
    }
  }
}

double luminance(glm::vec3 radiance) {
  return 0.2126 * radiance.r + 0.7152 * radiance.g + 0.0722 * radiance.b;  // Rec. 709 weights
}

glm::vec3 sunAtElevation(float degrees) {
  const float elevation = glm::radians(degrees);
  return glm::vec3(0.6f * std::cos(elevation), std::sin(elevation), 0.8f * std::cos(elevation));
}

shader::SkyParameters defaultSky(float sunElevationDegrees, float intensity = 1.0f) {
  return makeSkyParameters(Sky{.kind = SkyKind::Default, .intensity = intensity},
                           Sun{.enabled = true, .direction = sunAtElevation(sunElevationDegrees)});
}

RadianceField radianceOf(const shader::SkyParameters& sky) {
  return [sky](glm::vec3 direction) { return shader::evaluateSky(sky, direction); };
}

// Directions to probe the sky with: a spread set plus the special ones (poles, exactly on the horizon).
std::vector<glm::vec3> skyTestDirections() {
  std::vector<glm::vec3> directions = {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f),
                                       glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
  for (uint32_t index = 0; index < 1024; ++index) {
    directions.push_back(shader::haltonSphereDirection(index));
  }
  return directions;
}

TEST(SkyTest, kindNoneIsBlack) {
  const shader::SkyParameters sky = makeSkyParameters(
      Sky{.kind = SkyKind::None, .uniformRadiance = glm::vec3(1.0f), .intensity = 1.0f}, Sun{.enabled = true});
  for (const glm::vec3& direction : skyTestDirections()) {
    EXPECT_EQ(shader::evaluateSky(sky, direction), glm::vec3(0.0f));
  }
}

TEST(SkyTest, uniformKindIsTheSameRadianceEverywhere) {
  const glm::vec3 radiance(0.2f, 0.5f, 1.0f);
  const shader::SkyParameters sky =
      makeSkyParameters(Sky{.kind = SkyKind::Uniform, .uniformRadiance = radiance}, Sun{.enabled = true});
  for (const glm::vec3& direction : skyTestDirections()) {
    EXPECT_EQ(shader::evaluateSky(sky, direction), radiance);
  }
}

TEST(SkyTest, defaultSkyIsPositiveAndFiniteEverywhere) {
  for (float sunElevation : {0.0f, 10.0f, 45.0f, 90.0f}) {
    const shader::SkyParameters sky = defaultSky(sunElevation);
    std::vector<glm::vec3> directions = skyTestDirections();
    directions.push_back(glm::vec3(sky.sunDirectionAndIntensity));
    directions.push_back(-glm::vec3(sky.sunDirectionAndIntensity));
    for (const glm::vec3& direction : directions) {
      const glm::vec3 radiance = shader::evaluateSky(sky, direction);
      for (int channel = 0; channel < 3; ++channel) {
        EXPECT_TRUE(std::isfinite(radiance[channel]) && radiance[channel] > 0.0f)
            << "sun elevation " << sunElevation << ", direction (" << direction.x << ", " << direction.y << ", "
            << direction.z << "), channel " << channel << ": " << radiance[channel];
      }
    }
  }
}

TEST(SkyTest, defaultSkyIsBrighterTowardsTheSunThanAwayFromIt) {
  const shader::SkyParameters sky = defaultSky(30.0f);
  const glm::vec3 sun = glm::vec3(sky.sunDirectionAndIntensity);
  const glm::vec3 sunAzimuth = glm::normalize(glm::vec3(sun.x, 0.0f, sun.z));
  for (float elevation : {2.0f, 15.0f, 30.0f, 60.0f}) {
    const float radians = glm::radians(elevation);
    const glm::vec3 up(0.0f, std::sin(radians), 0.0f);
    const glm::vec3 towards = std::cos(radians) * sunAzimuth + up;
    const glm::vec3 away = -std::cos(radians) * sunAzimuth + up;
    EXPECT_GT(luminance(shader::evaluateSky(sky, towards)), luminance(shader::evaluateSky(sky, away)))
        << "elevation " << elevation;
  }
}

TEST(SkyTest, defaultSkyIsBlueAtTheZenithAndBrighterAndWhiterAtTheHorizon) {
  const shader::SkyParameters sky = defaultSky(45.0f);
  const glm::vec3 zenith = shader::evaluateSky(sky, glm::vec3(0.0f, 1.0f, 0.0f));
  // On the horizon, 90° in azimuth from the sun (which stands towards (0.6, ·, 0.8)).
  const glm::vec3 horizon = shader::evaluateSky(sky, glm::normalize(glm::vec3(0.8f, 0.01f, -0.6f)));
  EXPECT_GT(zenith.b, 1.3f * zenith.r);
  EXPECT_GT(luminance(horizon), luminance(zenith));
  EXPECT_LT(horizon.b / horizon.r, zenith.b / zenith.r);
}

TEST(SkyTest, defaultSkyScalesWithIntensity) {
  const shader::SkyParameters single = defaultSky(45.0f, 1.0f);
  const shader::SkyParameters triple = defaultSky(45.0f, 3.0f);
  for (const glm::vec3& direction : skyTestDirections()) {
    const glm::vec3 expected = 3.0f * shader::evaluateSky(single, direction);
    const glm::vec3 actual = shader::evaluateSky(triple, direction);
    for (int channel = 0; channel < 3; ++channel) {
      EXPECT_FLOAT_EQ(actual[channel], expected[channel]);
    }
  }
}

TEST(SkyTest, defaultSkyFadesToBlackAfterSunset) {
  // Civil twilight ends with the sun 6° below the horizon.
  const shader::SkyParameters twilight = defaultSky(-3.0f);
  const shader::SkyParameters night = defaultSky(-7.0f);
  const glm::vec3 zenith(0.0f, 1.0f, 0.0f);
  EXPECT_GT(luminance(shader::evaluateSky(twilight, zenith)), 0.0);
  EXPECT_LT(luminance(shader::evaluateSky(twilight, zenith)), luminance(shader::evaluateSky(defaultSky(3.0f), zenith)));
  for (const glm::vec3& direction : skyTestDirections()) {
    EXPECT_EQ(shader::evaluateSky(night, direction), glm::vec3(0.0f));
  }
}

TEST(SkyTest, defaultSkyGivesOneToTwoWattsPerSquareMetreOnAnUpwardSurface) {
  // The documented calibration (shaders/shared/sky.h): next to the built-in scenes' ~5–6 W/m² sun.
  for (float sunElevation : {15.0f, 30.0f, 45.0f, 60.0f, 90.0f}) {
    const double irradiance = luminance(glm::vec3(bruteForceIrradiance(radianceOf(defaultSky(sunElevation)),
                                                                       glm::vec3(0.0f, 1.0f, 0.0f))));
    EXPECT_GE(irradiance, 1.0) << "sun elevation " << sunElevation;
    EXPECT_LE(irradiance, 2.0) << "sun elevation " << sunElevation;
  }
}

TEST(SkyTest, makeSkyParametersKeepsTheSunDirectionWhenTheSunIsDisabledAndNormalisesIt) {
  const shader::SkyParameters sky = makeSkyParameters(
      Sky{.kind = SkyKind::Default, .intensity = 2.5f},
      Sun{.enabled = false, .direction = glm::vec3(0.0f, 3.0f, 4.0f), .illuminance = glm::vec3(0.0f)});
  EXPECT_EQ(sky.uniformRadianceAndKind.w, static_cast<float>(shader::kSkyKindDefault));
  EXPECT_FLOAT_EQ(sky.sunDirectionAndIntensity.x, 0.0f);
  EXPECT_FLOAT_EQ(sky.sunDirectionAndIntensity.y, 0.6f);
  EXPECT_FLOAT_EQ(sky.sunDirectionAndIntensity.z, 0.8f);
  EXPECT_EQ(sky.sunDirectionAndIntensity.w, 2.5f);
}

TEST(SkyTest, projectionOfUniformSkyIsAnalytic) {
  const glm::vec3 radiance(0.2f, 0.5f, 1.0f);
  const shader::Sh2Rgb sh = projectSkyToSh2(
      makeSkyParameters(Sky{.kind = SkyKind::Uniform, .uniformRadiance = radiance}, Sun{.enabled = true}));
  const glm::vec4 coefficients[3] = {sh.r, sh.g, sh.b};
  for (int channel = 0; channel < 3; ++channel) {
    const double expectedL00 = radiance[channel] * shader::kSh2Band0Basis * 4.0 * kPi;
    EXPECT_NEAR(coefficients[channel].x, expectedL00, 1e-6 * expectedL00);  // N equal terms: float rounding only
    const double band1Tolerance = radiance[channel] * shader::kSh2Band1Basis * 4.0 * kPi *
                                  haltonMeanBound(kSkyProjectionSampleCount);  // see the constant-radiance SH test
    for (int coefficient = 1; coefficient < 4; ++coefficient) {
      EXPECT_NEAR(coefficients[channel][coefficient], 0.0, band1Tolerance);
    }
  }
  const glm::vec3 irradiance = shader::sh2Irradiance(sh, glm::vec3(0.0f, 1.0f, 0.0f));
  for (int channel = 0; channel < 3; ++channel) {
    // π·L, off by band 1's bound above times 2π/3·Y1 (about 1e-3 relative)
    EXPECT_NEAR(irradiance[channel], kPi * radiance[channel], 1e-3 * kPi * radiance[channel]);
  }
}

TEST(SkyTest, projectionOfDefaultSkyReproducesItsIrradianceOnAnUpwardSurfaceUpToTheDroppedBands) {
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  for (float sunElevation : {5.0f, 30.0f, 45.0f, 90.0f}) {
    const shader::SkyParameters sky = defaultSky(sunElevation);
    const RadianceField radiance = radianceOf(sky);
    const glm::dvec3 exact = bruteForceIrradiance(radiance, up);
    const glm::dvec3 sh2 = glm::dvec3(shader::sh2Irradiance(projectSkyToSh2(sky), up));
    const glm::dvec3 droppedBands = irradianceOfBand2(radiance, up) + irradianceOfBand4(radiance, up);
    for (int channel = 0; channel < 3; ++channel) {
      // SH2's error is the bands it drops. With bands 2 and 4 added back, what remains is bands 6 and up
      // (|Â6| = π/64) plus the quadrature errors of the Halton projection (~1e-3, from the change between N = 16384
      // and 65536) and of the brute-force integrals (~3e-4 at the circumsolar cusp): measured at most 1.6 %.
      EXPECT_NEAR(sh2[channel] + droppedBands[channel], exact[channel], 0.025 * exact[channel])
          << "sun elevation " << sunElevation << ", channel " << channel;
    }
    if (sunElevation >= 45.0f) {
      // SH2 alone: a high sun puts most of the light well above the horizon, where SH2's cosine kernel
      // 1/4 + (n·ω)/2 is close to max(0, n·ω); measured 8 % at 45°, 3 % at 90°. A low sun brightens the horizon,
      // where that kernel is 1/4 instead of 0, and SH2 overestimates by up to 37 % at sunrise.
      EXPECT_NEAR(luminance(glm::vec3(sh2)), luminance(glm::vec3(exact)), 0.1 * luminance(glm::vec3(exact)))
          << "sun elevation " << sunElevation;
    }
  }
}

}  // namespace
}  // namespace ssvgi::renderer
