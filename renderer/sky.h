#pragma once
// The host's side of the sky: turns the scene's Sky and Sun into the GPU's SkyParameters (shaders/shared/sky.h) and
// projects the resulting radiance onto SH2, the form in which the host hands the sky to the GI (SPEC §3).
#include "scene.h"
#include "shared/sh.h"
#include "shared/sky.h"

#include <cstdint>
#include <functional>

namespace ssvgi::renderer {

// Packs the sky for the shaders. The analytic sky (SkyKind::Default) is shaped by `sun.direction` even when the sun
// light is disabled: switching the sun's delta light off (to look at sky light alone, say) must not move the bright
// part of the sky. The direction is normalised here because the shaders take it as a unit vector.
shader::SkyParameters makeSkyParameters(const Sky& sky, const Sun& sun);

// Enough Halton directions that the projection's quadrature error is far below SH2's own truncation error, even for
// the default sky's horizon edge and circumsolar peak (see SkyTest), and still a few milliseconds on the CPU.
inline constexpr uint32_t kSkyProjectionSampleCount = 16384;

// The SH2 coefficients of any radiance field, by SPEC §2's estimator L_lm = (4π/N) Σ L(ω_i) Y_lm(ω_i) over the first
// `sampleCount` Halton directions (shaders/shared/sampling.h).
shader::Sh2Rgb projectToSh2(const std::function<glm::vec3(glm::vec3 direction)>& radiance,
                            uint32_t sampleCount = kSkyProjectionSampleCount);

// The sky's radiance as SH2, computed from the same evaluateSky() that the shaders call, so that the GI's sky matches
// what rays that leave the scene see.
shader::Sh2Rgb projectSkyToSh2(const shader::SkyParameters& sky);

}  // namespace ssvgi::renderer
