#include "reference_scenarios.h"

#include "gi/context_internals.h"
#include "gpu_host/transfers.h"
#include "path_tracer.h"
#include "point_radiance.h"
#include "scenario_rendering.h"
#include "shared/probe_interface.h"
#include "sky.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ssvgi::bench {

namespace {

using renderer::FloatImage;
using reference::PixelMask;

// Σ of every colour channel over the valid pixels.
double sumOverMask(const FloatImage& image, const PixelMask& mask) {
  double sum = 0.0;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x)
      if (mask.isValid(x, y))
        for (uint32_t c = 0; c < 3; ++c) sum += image.pixels[(size_t(y) * image.width + x) * image.channels + c];
  return sum;
}

double relativeChange(double now, double before) {
  if (before > 0.0) return std::abs(now - before) / before;
  return now == before ? 0.0 : 1.0;
}

// Renders windows of frames of the still view until the mean indirect irradiance over the surface pixels settles.
Convergence renderUntilConverged(ScenarioRenderer& renderer, const renderer::Camera& camera,
                                 const ConvergenceOptions& options) {
  Convergence convergence;
  double previousMean = -1.0;
  while (convergence.frames < options.maxFrames) {
    renderer.render(camera, options.windowFrames);
    convergence.frames += options.windowFrames;
    const double mean = sumOverMask(renderer.renderer().indirectIrradiance(),
                                    reference::maskFromDepth(renderer.renderer().viewDistance()));
    if (previousMean >= 0.0) {
      convergence.lastChange = relativeChange(mean, previousMean);
      if (convergence.lastChange < options.tolerance) {
        convergence.converged = true;
        break;
      }
    }
    previousMean = mean;
  }
  return convergence;
}

// The scene as the scenario renderer shows it: still, at animation time 0, from the view's camera.
renderer::AnimatedState stillState(const ScenarioView& view) {
  renderer::AnimatedState state = renderer::evaluateAnimation(view.scene, view.camera, 0.0f);
  state.camera = view.camera;
  return state;
}

// Both halves of a reference must hold at least one sample, one round, ….
uint32_t half(uint32_t count, const char* what) {
  if (count < 2) throw std::runtime_error(std::string("the reference needs at least 2 ") + what);
  return count / 2;
}

FloatImage averageOf(const FloatImage& a, const FloatImage& b) {
  FloatImage mean = a;
  for (size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i] = 0.5f * (a.pixels[i] + b.pixels[i]);
  return mean;
}

shader::Sh2Rgb averageOf(const shader::Sh2Rgb& a, const shader::Sh2Rgb& b) {
  return {0.5f * (a.r + b.r), 0.5f * (a.g + b.g), 0.5f * (a.b + b.b)};
}

using AxisIrradiance = std::array<glm::vec3, kAxisNormals>;

// E(n) for the six axis normals, read from the SH2 as the gather reads a probe's light without sky (shared/sh.h).
AxisIrradiance axisIrradiance(const shader::Sh2Rgb& radiance) {
  AxisIrradiance irradiance;
  for (uint32_t i = 0; i < kAxisNormals; ++i)
    irradiance[i] = shader::sh2IrradianceWithoutRinging(radiance, shader::pointAxisNormal(i));
  return irradiance;
}

double total(const std::vector<AxisIrradiance>& probes) {
  double sum = 0.0;
  for (const AxisIrradiance& probe : probes)
    for (const glm::vec3& irradiance : probe) sum += double(irradiance.r) + irradiance.g + irradiance.b;
  return sum;
}

// Σ|test − reference| / Σ reference over the probes, the normals and the colour channels.
double relativeMeanAbsoluteError(const std::vector<AxisIrradiance>& test, const std::vector<AxisIrradiance>& reference) {
  double absoluteError = 0.0;
  for (size_t i = 0; i < test.size(); ++i)
    for (uint32_t n = 0; n < kAxisNormals; ++n)
      for (int c = 0; c < 3; ++c) absoluteError += std::abs(double(test[i][n][c]) - double(reference[i][n][c]));
  const double referenceTotal = total(reference);
  if (referenceTotal <= 0.0) throw std::runtime_error("the reference irradiance at the probes is black");
  return absoluteError / referenceTotal;
}

IrradianceAgreement agreement(const std::vector<AxisIrradiance>& test, const std::vector<AxisIrradiance>& against) {
  IrradianceAgreement result;
  result.relativeMeanAbsoluteError = relativeMeanAbsoluteError(test, against);
  result.meanRatio = total(test) / total(against);
  for (uint32_t n = 0; n < kAxisNormals; ++n) {
    double testSum = 0.0, againstSum = 0.0;
    for (size_t i = 0; i < test.size(); ++i) {
      testSum += double(test[i][n].r) + test[i][n].g + test[i][n].b;
      againstSum += double(against[i][n].r) + against[i][n].g + against[i][n].b;
    }
    result.ratioByNormal[n] = againstSum > 0.0 ? testSum / againstSum : 0.0;
  }
  return result;
}

// Whether the camera sees into the space around `position`: inside the frustum and nearer than the surface drawn at
// the pixel it projects to (any distance where nothing was drawn).
bool inSpaceSeenByCamera(glm::vec3 position, const shader::FrameConstants& frame, glm::vec3 cameraPosition,
                         const FloatImage& viewDistance) {
  const glm::vec4 clip = frame.viewProjection * glm::vec4(position, 1.0f);
  if (clip.w <= 0.0f) return false;
  const glm::vec3 ndc = glm::vec3(clip) / clip.w;
  if (std::abs(ndc.x) >= 1.0f || std::abs(ndc.y) >= 1.0f) return false;
  const glm::vec2 uv = shader::ssvgiNdcToUv(glm::vec2(ndc));
  const uint32_t x = std::min(uint32_t(uv.x * float(viewDistance.width)), viewDistance.width - 1);
  const uint32_t y = std::min(uint32_t(uv.y * float(viewDistance.height)), viewDistance.height - 1);
  const float surfaceDistance = viewDistance.pixels[size_t(y) * viewDistance.width + x];
  return surfaceDistance <= 0.0f || glm::distance(position, cameraPosition) < surfaceDistance;
}

// The point of triangle abc nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::vec3 closestPointOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denominator = 1.0f / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// The distance from `position` to the nearest surface of the still scene (animation time 0), by testing every
// triangle: the scenario scenes have a few thousand at most.
float distanceToScene(glm::vec3 position, const renderer::Scene& scene) {
  float nearest = std::numeric_limits<float>::max();
  for (const renderer::Instance& instance : scene.instances) {
    const renderer::Mesh& mesh = scene.meshes[instance.mesh];
    const auto corner = [&](size_t index) {
      return glm::vec3(instance.transform * glm::vec4(mesh.vertices[mesh.indices[index]].position, 1.0f));
    };
    for (size_t index = 0; index + 2 < mesh.indices.size(); index += 3)
      nearest = std::min(nearest, glm::distance(position, closestPointOnTriangle(position, corner(index),
                                                                                 corner(index + 1), corner(index + 2))));
  }
  return nearest;
}

bool insideBounds(glm::vec3 position, const renderer::Bounds& bounds) {
  return glm::all(glm::greaterThan(position, bounds.min)) && glm::all(glm::lessThan(position, bounds.max));
}

}  // namespace

ConvergedView::ConvergedView(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const ScenarioView& view,
                             const ConvergenceOptions& options)
    : rendering_(rendering), view_(view), renderer_(device, view.scene, rendering) {
  convergence_ = renderUntilConverged(renderer_, view.camera, options);
}

IndirectErrorResult measureIndirectError(gpu::OwnedDevice& device, const ScenarioRendering& rendering,
                                         const ScenarioView& view, const IndirectErrorOptions& options) {
  ConvergedView converged(device, rendering, view, options.convergence);
  return measureIndirectError(device, converged, options);
}

IndirectErrorResult measureIndirectError(gpu::OwnedDevice& device, ConvergedView& converged,
                                         const IndirectErrorOptions& options) {
  const ScenarioRendering& rendering = converged.rendering();
  const ScenarioView& view = converged.view();
  IndirectErrorResult result;
  result.convergence = converged.convergence();
  const FloatImage gi = converged.renderer().renderer().indirectIrradiance();
  const FloatImage viewDistance = converged.renderer().renderer().viewDistance();

  const renderer::AnimatedState state = stillState(view);
  const uint32_t halfSamples = half(options.referenceSamples, "samples per pixel");
  std::array<FloatImage, 2> halves;
  for (uint32_t i = 0; i < 2; ++i) {
    reference::PathTracerSettings tracerSettings;
    tracerSettings.width = rendering.width;
    tracerSettings.height = rendering.height;
    tracerSettings.seed = options.seed + i;
    reference::PathTracer tracer(device, view.scene, state, tracerSettings);
    tracer.trace(halfSamples);
    halves[i] = tracer.indirectIrradiance();
  }
  const FloatImage referenceIndirect = averageOf(halves[0], halves[1]);
  result.referenceSamples = 2 * halfSamples;

  const PixelMask mask = reference::maskFromDepth(viewDistance);
  result.comparison = reference::compareImages(gi, referenceIndirect, &mask, options.downsample);
  result.referenceNoiseFloor =
      reference::compareImages(halves[0], halves[1], &mask, options.downsample).relativeMeanAbsoluteError / 2.0;
  return result;
}

ProbeIrradianceResult measureProbeIrradiance(gpu::OwnedDevice& device, const ScenarioRendering& rendering,
                                             const ScenarioView& view, const ProbeIrradianceOptions& options) {
  ConvergedView converged(device, rendering, view, options.convergence);
  return measureProbeIrradiance(device, converged, options);
}

ProbeIrradianceResult measureProbeIrradiance(gpu::OwnedDevice& device, ConvergedView& converged,
                                             const ProbeIrradianceOptions& options) {
  const ScenarioRendering& rendering = converged.rendering();
  const ScenarioView& view = converged.view();
  ScenarioRenderer& renderer = converged.renderer();
  ProbeIrradianceResult result;
  result.convergence = converged.convergence();

  const renderer::AnimatedState state = stillState(view);
  const Context& context = *renderer.renderer().giContext();
  const gi::ProbeVolume& volume = gi::probeVolumeOf(context);
  const std::vector<shader::Probe> probes = gpu::readBufferAs<shader::Probe>(device, volume.probes());
  // The grid the context runs with: a memory budget may have chosen a smaller one than the rendering asked for.
  const Settings& settings = context.settings();
  const glm::ivec3 dimensions(settings.probeGrid[0], settings.probeGrid[1], settings.probeGrid[2]);
  const glm::ivec3 origin = volume.levelOrigin(0, view.camera.position);
  const float spacing = volume.levelSpacing(0);
  const shader::FrameConstants frame =
      renderer::makeFrameConstants(view.scene, state, rendering.width, rendering.height, 1.0f);
  const FloatImage viewDistance = renderer.renderer().viewDistance();
  const renderer::Bounds bounds = renderer::worldBounds(view.scene);
  const shader::Sh2Rgb sky = renderer::projectSkyToSh2(frame.sky);  // what the context's gather is given

  std::vector<glm::vec3> positions;
  std::vector<AxisIrradiance> giIrradiance;
  for (uint32_t slot = 0; slot < volume.probesPerLevel(); ++slot) {  // level 0 comes first
    const glm::ivec3 coordinate = shader::probeWorldCoordinate(slot, origin, dimensions);
    const shader::Probe& probe = probes[slot];
    if (!shader::probeIsUsable(probe, coordinate)) continue;
    ++result.usableProbes;
    const glm::vec3 position = shader::probeWorldPosition(coordinate, spacing, probe.state);
    if (!insideBounds(position, bounds) || !inSpaceSeenByCamera(position, frame, view.camera.position, viewDistance) ||
        distanceToScene(position, view.scene) < settings.voxelSize)
      continue;
    result.probes.push_back({.probe = coordinate, .position = position});
    positions.push_back(position);
    AxisIrradiance reading;  // as the gather reads the probe, its sky apart
    for (uint32_t i = 0; i < kAxisNormals; ++i)
      reading[i] = shader::readProbeIrradiance(probe, shader::pointAxisNormal(i), sky);
    giIrradiance.push_back(reading);
  }
  if (positions.empty()) throw std::runtime_error("no usable probe lies in the space the camera sees");

  const uint32_t halfDirections = half(options.referenceDirections, "directions per point");
  std::array<std::vector<shader::PointRadianceSums>, 2> halves;
  for (uint32_t i = 0; i < 2; ++i) {
    reference::PointRadianceTracer tracer(device, view.scene, state, positions, {.seed = options.seed + i});
    tracer.trace(halfDirections);
    halves[i] = tracer.measurements();
    result.referenceDirections += tracer.directionsPerPoint();
  }
  std::vector<AxisIrradiance> referenceIrradiance, exactIrradiance, firstHalf, secondHalf;
  for (size_t i = 0; i < positions.size(); ++i) {
    referenceIrradiance.push_back(axisIrradiance(averageOf(halves[0][i].radiance, halves[1][i].radiance)));
    firstHalf.push_back(axisIrradiance(halves[0][i].radiance));
    secondHalf.push_back(axisIrradiance(halves[1][i].radiance));
    AxisIrradiance exact;
    for (uint32_t n = 0; n < kAxisNormals; ++n)
      exact[n] = 0.5f * glm::vec3(halves[0][i].axisIrradiance[n] + halves[1][i].axisIrradiance[n]);
    exactIrradiance.push_back(exact);
    result.probes[i].gi = giIrradiance[i];
    result.probes[i].reference = referenceIrradiance[i];
    result.probes[i].exact = exact;
  }
  result.relativeMeanAbsoluteError = relativeMeanAbsoluteError(giIrradiance, referenceIrradiance);
  result.meanRatio = total(giIrradiance) / total(referenceIrradiance);
  result.referenceNoiseFloor = relativeMeanAbsoluteError(firstHalf, secondHalf) / 2.0;
  result.againstExact = agreement(giIrradiance, exactIrradiance);
  result.readingOfReference = agreement(referenceIrradiance, exactIrradiance);
  return result;
}

namespace {

nlohmann::json toJson(const Convergence& convergence) {
  return {{"frames", convergence.frames}, {"lastChange", convergence.lastChange}, {"converged", convergence.converged}};
}

nlohmann::json toJson(glm::vec3 value) { return nlohmann::json::array({value.x, value.y, value.z}); }

nlohmann::json toJson(const IrradianceAgreement& agreement) {
  return {{"relativeMeanAbsoluteError", agreement.relativeMeanAbsoluteError},
          {"meanRatio", agreement.meanRatio},
          {"ratioByNormal", agreement.ratioByNormal}};
}

}  // namespace

nlohmann::json toJson(const IndirectErrorResult& result) {
  return {{"relativeMeanAbsoluteError", result.comparison.relativeMeanAbsoluteError},
          {"rmse", result.comparison.rmse},
          {"ssim", result.comparison.ssim},
          {"validPixels", result.comparison.validPixels},
          {"downsample", result.comparison.downsample},
          {"meanRatio", result.comparison.meanRatio},
          {"referenceNoiseFloor", result.referenceNoiseFloor},
          {"referenceSamplesPerPixel", result.referenceSamples},
          {"convergence", toJson(result.convergence)}};
}

nlohmann::json toJson(const ProbeIrradianceResult& result) {
  nlohmann::json probes = nlohmann::json::array();
  for (const ProbeIrradiance& probe : result.probes) {
    nlohmann::json gi = nlohmann::json::array(), reference = nlohmann::json::array(), exact = nlohmann::json::array();
    for (uint32_t n = 0; n < kAxisNormals; ++n) {
      gi.push_back(toJson(probe.gi[n]));
      reference.push_back(toJson(probe.reference[n]));
      exact.push_back(toJson(probe.exact[n]));
    }
    probes.push_back({{"probe", {probe.probe.x, probe.probe.y, probe.probe.z}},
                      {"position", toJson(probe.position)},
                      {"irradiance", gi},
                      {"referenceIrradiance", reference},
                      {"exactReferenceIrradiance", exact}});
  }
  return {{"relativeMeanAbsoluteError", result.relativeMeanAbsoluteError},
          {"meanRatio", result.meanRatio},
          {"referenceNoiseFloor", result.referenceNoiseFloor},
          {"referenceDirections", result.referenceDirections},
          {"againstExactReference", toJson(result.againstExact)},
          {"readingOfReference", toJson(result.readingOfReference)},
          {"usableProbes", result.usableProbes},
          {"comparedProbes", result.probes.size()},
          // irradiance, referenceIrradiance (both read from SH2) and exactReferenceIrradiance: E(n) in RGB (W/m²) for
          // each of these normals, in this order; ratioByNormal in the same order
          {"normals", {"+x", "-x", "+y", "-y", "+z", "-z"}},
          {"probes", probes},
          {"convergence", toJson(result.convergence)}};
}

}  // namespace ssvgi::bench
