#include "sky.h"

#include "shared/sampling.h"

#include <cassert>

namespace ssvgi::renderer {

namespace {

uint32_t gpuSkyKind(SkyKind kind) {
  switch (kind) {
    case SkyKind::None:
      return shader::kSkyKindNone;
    case SkyKind::Default:
      return shader::kSkyKindDefault;
    case SkyKind::Uniform:
      return shader::kSkyKindUniform;
  }
  assert(false && "unknown SkyKind");
  return shader::kSkyKindNone;
}

}  // namespace

shader::SkyParameters makeSkyParameters(const Sky& sky, const Sun& sun) {
  assert(glm::length(sun.direction) > 0.0f && "the sun needs a direction, even when disabled");
  return shader::SkyParameters{
      .uniformRadianceAndKind = glm::vec4(sky.uniformRadiance, static_cast<float>(gpuSkyKind(sky.kind))),
      .sunDirectionAndIntensity = glm::vec4(glm::normalize(sun.direction), sky.intensity),
  };
}

shader::Sh2Rgb projectToSh2(const std::function<glm::vec3(glm::vec3 direction)>& radiance, uint32_t sampleCount) {
  assert(sampleCount > 0);
  // Summed in double: a float running sum of 16384 terms drifts by up to ~1e-3 relative.
  glm::dvec4 sumR{0.0}, sumG{0.0}, sumB{0.0};
  for (uint32_t index = 0; index < sampleCount; ++index) {
    const glm::vec3 direction = shader::haltonSphereDirection(index);
    const glm::dvec4 basis{shader::sh2Basis(direction)};
    const glm::dvec3 sample{radiance(direction)};
    sumR += sample.r * basis;
    sumG += sample.g * basis;
    sumB += sample.b * basis;
  }
  const double sampleSolidAngle = 4.0 * glm::pi<double>() / sampleCount;
  return shader::Sh2Rgb{
      .r = glm::vec4(sumR * sampleSolidAngle),
      .g = glm::vec4(sumG * sampleSolidAngle),
      .b = glm::vec4(sumB * sampleSolidAngle),
  };
}

shader::Sh2Rgb projectSkyToSh2(const shader::SkyParameters& sky) {
  return projectToSh2([&sky](glm::vec3 direction) { return shader::evaluateSky(sky, direction); });
}

}  // namespace ssvgi::renderer
