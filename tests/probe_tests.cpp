// The probe radiance cache (SPEC §4.5), first slice: the discretisation of the 1024-direction set on the CPU; then
// ProbePlacement and ProbeTrace through the public API on voxel scenes written straight into the context's voxel scene
// (the frames themselves inject nothing: their depth is empty and there is no lit frame), checked against analytic
// irradiance: a furnace, a closed box, a wall hiding half the sky, the history count and α, the budget, the memory.
#include "builtin_scenes.h"
#include "camera.h"
#include "gi/context_internals.h"
#include "gi/voxels/build_octree.h"
#include "gpu_host/transfers.h"
#include "gpu_test_device.h"
#include "renderer.h"
#include "shared/probe_interface.h"
#include "shared/sky_map.h"
#include "ssvgi/ssvgi.h"
#include "voxel_readback.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <optional>
#include <vector>

namespace ssvgi {
namespace {

using shader::kPi;

constexpr float kSkyRadiance = 1.0f;  // the uniform sky of every test; exact in R11G11B10F, so a voxel can match it

// Uniform radiance L as SH2 of every channel: L00 = 4π·Y00·L, the band-1 coefficients zero.
std::array<float, 12> uniformSkySh(float radiance) {
  const float band0 = 4.0f * kPi * shader::kSh2Band0Basis * radiance;
  return {band0, 0, 0, 0, band0, 0, 0, 0, band0, 0, 0, 0};
}
shader::Sh2Rgb skySh(float radiance) {
  const glm::vec4 channel(4.0f * kPi * shader::kSh2Band0Basis * radiance, 0.0f, 0.0f, 0.0f);
  return {channel, channel, channel};
}

// Normals to evaluate irradiance at: the six axes and the eight diagonals.
std::vector<glm::vec3> testNormals() {
  std::vector<glm::vec3> normals;
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 normal(0.0f);
      normal[axis] = sign;
      normals.push_back(normal);
    }
  for (int corner = 0; corner < 8; ++corner)
    normals.push_back(glm::normalize(glm::vec3(corner & 1 ? 1.0f : -1.0f, corner & 2 ? 1.0f : -1.0f,
                                               corner & 4 ? 1.0f : -1.0f)));
  return normals;
}

// ---------------------------------------------------------------------------------------------------------------------
// CPU: the discretisation the GPU uses.

TEST(ProbeDirections, theThirtyTwoSlicesOfTheDirectionSetProjectConstantRadianceToIrradianceWithinOnePercent) {
  // 32 updates of 32 rays, each projected with the weight 4π/32 and averaged with α = 1/(m+1) (a plain mean), as
  // ProbeTrace does: this is the exact estimate a probe under a uniform sky converges to, so its error bounds the GPU
  // tests' tolerance.
  constexpr uint32_t kRays = 32, kUpdates = shader::kProbeRayDirectionCount / kRays;
  glm::vec4 mean(0.0f);
  for (uint32_t update = 0; update < kUpdates; ++update) {
    glm::vec4 slice(0.0f);
    for (uint32_t ray = 0; ray < kRays; ++ray) {
      const glm::vec3 direction = shader::probeRayDirection(update * kRays, ray);
      ASSERT_NEAR(glm::length(direction), 1.0f, 1e-5f);
      slice += kSkyRadiance * shader::sh2Basis(direction) * (4.0f * kPi / float(kRays));
    }
    mean += (slice - mean) / float(update + 1);
  }
  for (const glm::vec3& normal : testNormals())
    EXPECT_NEAR(shader::sh2Irradiance(mean, normal), kPi * kSkyRadiance, 0.01f * kPi * kSkyRadiance)
        << normal.x << " " << normal.y << " " << normal.z;
}

TEST(ProbeDirections, theStrataMeanBasisAndDeviationOfAnSh2FunctionMatchNumericIntegration) {
  // Midpoint rule on a 256×256 grid of each stratum's (z, φ) cell, where dω = dz·dφ: its error is far below the
  // tolerance for these smooth integrands. A constant f has no deviation from its mean.
  const std::array<glm::vec4, 3> functions{glm::vec4(1.0f, 0.0f, 0.0f, 0.0f), glm::vec4(0.7f, -0.3f, 0.5f, 0.9f),
                                           glm::vec4(-0.2f, 1.1f, -0.8f, 0.4f)};
  constexpr int kSteps = 256;
  for (uint32_t stratum = 0; stratum < shader::kProbeStrata; ++stratum) {
    const glm::vec4 bounds = shader::probeStratumBounds(stratum);
    const float cell = (bounds.y - bounds.x) * (bounds.w - bounds.z) / float(kSteps * kSteps);
    glm::dvec4 basisSum(0.0);
    std::array<glm::dvec4, 3> deviations{};
    const glm::vec4 meanBasis = shader::probeStratumMeanBasis(stratum);
    for (int i = 0; i < kSteps; ++i)
      for (int j = 0; j < kSteps; ++j) {
        const float z = bounds.x + (float(i) + 0.5f) * (bounds.y - bounds.x) / kSteps;
        const float phi = bounds.z + (float(j) + 0.5f) * (bounds.w - bounds.z) / kSteps;
        const float radius = std::sqrt(1.0f - z * z);
        const glm::vec4 basis = shader::sh2Basis({radius * std::cos(phi), radius * std::sin(phi), z});
        basisSum += glm::dvec4(basis) * double(cell);
        for (size_t f = 0; f < functions.size(); ++f)
          deviations[f] += glm::dvec4(glm::dot(functions[f], basis) * (basis - meanBasis)) * double(cell);
      }
    SCOPED_TRACE("stratum " + std::to_string(stratum));
    EXPECT_NEAR(shader::kProbeStratumSolidAngle, (bounds.y - bounds.x) * (bounds.w - bounds.z), 1e-6f);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(meanBasis[k], basisSum[k] / shader::kProbeStratumSolidAngle, 1e-5);
    for (size_t f = 0; f < functions.size(); ++f) {
      const glm::vec4 analytic =
          shader::probeStratumDeviation(shader::probeStratumCovariance(stratum), functions[f]);
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(analytic[k], deviations[f][k], 1e-5) << "function " << f << " coefficient " << k;
    }
  }
}

TEST(ProbeDirections, aSlotRecognisesItsProbeAfterWrappingAndAStaleOneDoesNot) {
  const glm::ivec3 dimensions(16, 8, 16), origin(-21, -3, 5);
  for (uint32_t slot = 0; slot < uint32_t(dimensions.x * dimensions.y * dimensions.z); ++slot) {
    const glm::ivec3 probe = shader::probeWorldCoordinate(slot, origin, dimensions);
    ASSERT_TRUE(glm::all(glm::greaterThanEqual(probe, origin)) && glm::all(glm::lessThan(probe, origin + dimensions)));
    ASSERT_EQ(shader::probeSlotIndex(probe, dimensions), slot);
    ASSERT_NE(shader::probeCoordinateTag(probe), shader::probeCoordinateTag(probe + glm::ivec3(16, 0, 0)));
  }
}

TEST(ProbeDirections, theStateWordKeepsHistoryDirectionOffsetAndPlacementApartAndTheOffsetUnderHalfASpacing) {
  EXPECT_LT(float(shader::kProbeMaxOffsetSteps) / shader::kProbeOffsetStepsPerSpacing, 0.5f);
  const int limit = shader::kProbeMaxOffsetSteps;
  for (int z = -limit; z <= limit; ++z)
    for (int y = -limit; y <= limit; ++y)
      for (int x = -limit; x <= limit; ++x) {
        const glm::ivec3 steps(x, y, z);
        const uint32_t state = shader::packProbeState(255u, 1023u, shader::kProbeStateInvalid,
                                                      shader::packProbeOffset(steps));
        ASSERT_EQ(shader::probeHistoryCount(state), 255u);
        ASSERT_EQ(shader::probeNextDirection(state), 1023u);
        ASSERT_EQ(shader::probePlacement(state), shader::kProbeStateInvalid);
        ASSERT_EQ(shader::unpackProbeOffset(shader::probeOffsetCode(state)), steps);
      }
  // The 26 neighbours: distinct, none the probe itself.
  std::vector<glm::ivec3> neighbours;
  for (uint32_t i = 0; i < shader::kProbeNeighbourCount; ++i) {
    const glm::ivec3 offset = shader::probeNeighbourOffset(i);
    EXPECT_NE(offset, glm::ivec3(0));
    EXPECT_LE(glm::max(glm::abs(offset.x), glm::max(glm::abs(offset.y), glm::abs(offset.z))), 1);
    EXPECT_EQ(std::count(neighbours.begin(), neighbours.end(), offset), 0);
    neighbours.push_back(offset);
  }
}

TEST(ProbeDirections, theChangeWordKeepsTheDriftSumToWithinAStepAndItsSign) {
  for (const float dither : {0.0f, 0.5f, 0.999f}) {
    for (float drift = -shader::kProbeDriftLimit + 0.01f; drift < shader::kProbeDriftLimit; drift += 0.13f) {
      shader::ProbeChange change{0.5f, 0.01f, 3u, drift};
      const shader::ProbeChange unpacked = shader::unpackProbeChange(shader::packProbeChange(change, dither));
      ASSERT_NEAR(unpacked.drift, drift, shader::kProbeDriftStep) << "dither " << dither;
      if (unpacked.drift != 0.0f) {
        ASSERT_EQ(unpacked.drift < 0.0f, drift < 0.0f) << drift;
      }
      ASSERT_EQ(unpacked.recoveryUpdates, 3u);
      ASSERT_NEAR(unpacked.mean, 0.5f, 1e-3f);
    }
  }
}

TEST(ProbeDirections, theDriftSumClimbsWithUpdatesThatKeepStrayingOneWayAndNotWithNoise) {
  // Noise that strays by up to the allowance either way leaves it at zero; updates 1.5 deviations up climb 0.5 each.
  float drift = 0.0f;
  for (int update = 0; update < 100; ++update)
    drift = shader::accumulateProbeDrift(drift, update % 2 ? shader::kProbeDriftAllowance
                                                           : -shader::kProbeDriftAllowance);
  EXPECT_EQ(drift, 0.0f);
  const float stray = shader::kProbeDriftAllowance + 0.5f;
  for (int update = 1; update <= 4; ++update) {
    drift = shader::accumulateProbeDrift(drift, stray);
    EXPECT_FLOAT_EQ(drift, 0.5f * float(update));
  }
  // An update the other way takes it back toward zero, and past zero it starts again on that side.
  EXPECT_FLOAT_EQ(shader::accumulateProbeDrift(drift, -0.5f), drift - 0.5f - shader::kProbeDriftAllowance);
  EXPECT_FLOAT_EQ(shader::accumulateProbeDrift(0.5f, -3.0f), -3.0f + shader::kProbeDriftAllowance);
  EXPECT_FLOAT_EQ(shader::accumulateProbeDrift(-0.5f, -1.5f), -0.5f - 1.5f + shader::kProbeDriftAllowance);
}

// A drift many probes share (shared/probe_interface.h): a frame's tally as ProbeTrace sums it, from each watched
// probe's update T = H·(1 + ε) and the direct share of its light.
shader::ProbeChangeTally leaningTally(const std::vector<float>& strays, float directShare = 1.0f) {
  shader::ProbeChangeTally tally{};
  for (const float stray : strays) {
    const float leaning = shader::probeUpdateLeaning(1.0f + stray, 1.0f);
    ++tally.watchedProbes;
    ++tally.leaningProbes;
    tally.leaningSum += int32_t(std::round(leaning * shader::kProbeLeaningScale));
    tally.leaningSquares += uint32_t(std::round(leaning * leaning * shader::kProbeLeaningScale));
    tally.directShareSum += uint32_t(std::round(directShare * shader::kProbeLeaningScale));
  }
  return tally;
}

gi::ProbeLeaning leaningOf(const std::vector<float>& strays, float directShare = 1.0f) {
  const shader::ProbeChangeTally tally = leaningTally(strays, directShare);
  return gi::probeLeaning({&tally, 1});
}

// Noise alone leans the probes neither way, whatever its shape: half the updates 40 % above their history and half
// 40 % below, or half meeting no light at all and half twice the history — where d + d² (d = (T − H)/(T + H), the
// leaning before) had a mean of +0.22, ten times the gap floor's lean.
TEST(ProbeSharedDrift, noiseOfAnyShapeDoesNotLeanTheProbesEitherWay) {
  for (const float spread : {0.4f, 1.0f}) {
    std::vector<float> strays;
    for (int probe = 0; probe < 400; ++probe) strays.push_back(probe % 2 ? spread : -spread);
    const gi::ProbeLeaning leaning = leaningOf(strays);
    EXPECT_NEAR(leaning.mean, 0.0, 0.001) << spread;
    EXPECT_NEAR(leaning.standardError, spread / 2.0 / std::sqrt(400.0), 0.001) << spread;
    EXPECT_FALSE(gi::showsSharedDrift(leaning)) << spread;
  }
}

// Light coming round the loop: every probe's update 10 % above its history, give or take 20 %: a lean of 0.05, many
// standard errors over 400 probes; by 31 it is not counted at all, and by 32 with a spread four times the lean it is
// within four standard errors. Pooled over frames, the same probes' evidence adds up.
TEST(ProbeSharedDrift, manyProbesLeaningTowardMoreLightShowADriftAndFewOrScatteredOnesDoNot) {
  std::vector<float> strays;
  for (int probe = 0; probe < 400; ++probe) strays.push_back(0.1f + (probe % 2 ? 0.2f : -0.2f));
  const gi::ProbeLeaning leaning = leaningOf(strays);
  EXPECT_NEAR(leaning.mean, 0.05, 0.001);
  EXPECT_NEAR(leaning.gap(), 0.1, 0.002);
  EXPECT_TRUE(gi::showsSharedDrift(leaning));

  strays.resize(shader::kProbeSharedChangeMinimumProbes - 1);
  EXPECT_EQ(leaningOf(strays).mean, 0.0);
  EXPECT_FALSE(gi::showsSharedDrift(leaningOf(strays)));

  std::vector<float> scattered;
  for (uint32_t probe = 0; probe < shader::kProbeSharedChangeMinimumProbes; ++probe)
    scattered.push_back(0.1f + (probe % 2 ? 0.8f : -0.6f));
  EXPECT_GT(leaningOf(scattered).gap(), shader::kProbeSharedDriftGapFloor);
  EXPECT_FALSE(gi::showsSharedDrift(leaningOf(scattered)));
  const std::vector<shader::ProbeChangeTally> frames(shader::kProbeSharedDriftWindow, leaningTally(scattered));
  EXPECT_TRUE(gi::showsSharedDrift(gi::probeLeaning(frames)));

  // Light that fades leans them the other way: no drift toward more light.
  for (float& stray : strays) stray = -0.1f;
  strays.resize(400, -0.1f);
  EXPECT_FALSE(gi::showsSharedDrift(leaningOf(strays)));
}

// The same lean tells a gap in proportion to the light that comes round the loop: updates 4 % above their histories
// are their last 4 % where all their light is direct, and 13 % short of the loop's end where 70 % of it has bounced.
TEST(ProbeSharedDrift, theSameLeanTellsALargerGapWhereMoreOfTheLightHasBounced) {
  std::vector<float> strays;
  for (int probe = 0; probe < 1000; ++probe) strays.push_back(0.04f + (probe % 2 ? 0.1f : -0.1f));
  const gi::ProbeLeaning open = leaningOf(strays, 1.0f);
  const gi::ProbeLeaning bounced = leaningOf(strays, 0.3f);
  EXPECT_NEAR(open.mean, bounced.mean, 1e-9);
  EXPECT_GT(open.mean, shader::kProbeSharedDriftErrors * open.standardError);
  EXPECT_NEAR(open.gap(), 0.04, 0.002);
  EXPECT_NEAR(bounced.gap(), 0.04 / 0.3, 0.005);
  EXPECT_FALSE(gi::showsSharedDrift(open));
  EXPECT_TRUE(gi::showsSharedDrift(bounced));
  EXPECT_TRUE(gi::showsSharedDrift(leaningOf(strays, 0.0f)));  // all of it bounced: any significant lean is a gap
}

// A drift is started by a lean of four standard errors and followed while its window leans by one: a small room's
// few probes, far from their end, tell their lean by four only now and then (docs/QUALITY.md, "A drift followed while
// it lasts"). A lean within a standard error, or a gap under the floor, ends it.
TEST(ProbeSharedDrift, aDriftFollowedGoesOnWhileItsWindowStillLeans) {
  std::vector<float> strays;
  for (int probe = 0; probe < 100; ++probe) strays.push_back(0.06f + (probe % 2 ? 0.3f : -0.3f));
  const gi::ProbeLeaning twoErrors = leaningOf(strays, 0.3f);
  ASSERT_GT(twoErrors.mean, 1.5 * twoErrors.standardError);
  ASSERT_LT(twoErrors.mean, 3.0 * twoErrors.standardError);
  EXPECT_GT(twoErrors.gap(), 0.1);
  EXPECT_FALSE(gi::showsSharedDrift(twoErrors, false));
  EXPECT_TRUE(gi::showsSharedDrift(twoErrors, true));

  for (float& stray : strays) stray -= 0.04f;  // a lean of 0.01: within a standard error (0.015)
  const gi::ProbeLeaning settling = leaningOf(strays, 0.3f);
  ASSERT_LT(settling.mean, settling.standardError);
  EXPECT_FALSE(gi::showsSharedDrift(settling, true));

  for (float& stray : strays) stray += 0.04f;
  const gi::ProbeLeaning open = leaningOf(strays, 1.0f);  // the same lean, all of the light direct: a 6 % gap
  EXPECT_TRUE(gi::showsSharedDrift(open, true));
  const gi::ProbeLeaning nearlyThere = leaningOf(std::vector<float>(strays.size(), 0.04f), 1.0f);
  EXPECT_LT(nearlyThere.gap(), shader::kProbeSharedDriftGapFloor);
  EXPECT_FALSE(gi::showsSharedDrift(nearlyThere, true));
}

// The window a drift holds the probes to: about 1/gap updates, from 16 for the smallest gap followed down to 8.
TEST(ProbeSharedDrift, theLargerTheGapTheShorterTheHistoryItHoldsTheProbesTo) {
  auto capForGap = [](double gap) {
    gi::ProbeLeaning leaning;
    leaning.mean = gap / 2.0;
    leaning.directShare = 1.0;
    return gi::sharedDriftHistoryCap(leaning);
  };
  EXPECT_EQ(capForGap(shader::kProbeSharedDriftGapFloor), shader::kProbeSharedDriftHistoryCap);
  EXPECT_EQ(capForGap(0.1), 10u);
  EXPECT_EQ(capForGap(0.125), shader::kProbeSharedDriftShortestHistoryCap);
  EXPECT_EQ(capForGap(0.9), shader::kProbeSharedDriftShortestHistoryCap);
  gi::ProbeLeaning allBounced;
  allBounced.mean = 0.01;
  EXPECT_EQ(gi::sharedDriftHistoryCap(allBounced), shader::kProbeSharedDriftShortestHistoryCap);
}

// ---------------------------------------------------------------------------------------------------------------------
// GPU: scenes of bricks under the probes.

constexpr uint32_t kFrameSize = 32;
// The camera looks along −Z at the scenes, which lie around kProbe: world (0, 0, 4) m, a probe of all three levels
// (coordinates (0, 0, 4), (0, 0, 2), (0, 0, 1)).
constexpr glm::vec3 kCameraPosition(2.5f, 0.5f, 10.5f);
constexpr glm::ivec3 kProbe(0, 0, 4);
// The voxel volume around kCameraPosition spans x −16..16 and these (m).
constexpr glm::vec2 kVolumeY(-8.0f, 8.0f), kVolumeZ(-8.0f, 24.0f);

Settings probeTestSettings() {
  Settings settings;
  settings.volumeBricks = {32, 16, 32};  // around the camera: bricks x −16..15, y −8..7, z −8..23
  settings.brickPoolCapacity = 1024;
  settings.probeGrid = {16, 8, 16};  // level 0 around the camera: probes x −6..9, y −4..3, z 2..17
  // The scenes are written straight into the brick pool, not seen by a view: the open space around them is each
  // test's premise, so a ray that meets no voxel sees the sky (ObservedSpace's tests cover space no view has seen).
  settings.skyOnlyThroughObservedSpace = false;
  // The relight tests look at the voxels after one frame: the whole pool relit every frame.
  settings.voxelRelightPeriod = 1;
  // The tests count a probe's updates: each update of its level traces it, also once it is settled (the settled
  // probes' turns have a test of their own).
  settings.settledProbeInterval = 1;
  return settings;
}

// A brick of a test scene: every voxel of `mask` with the same radiance and normal, but those of `brightMask`, which
// have `brightRadiance`.
struct TestBrick {
  glm::ivec3 coordinate;  // world brick coordinate
  uint64_t mask;
  glm::vec3 radiance;
  glm::vec3 normal;
  uint64_t brightMask = 0;
  glm::vec3 brightRadiance{0.0f};
  // Given, the voxels are relit (VoxelRelight): they keep this direct light and albedo, as an extra view lit by direct
  // light only leaves them (which also counts its visits: the camera's lit frame has not lit them since).
  std::optional<glm::vec3> albedo;
  glm::vec3 directRadiance{0.0f};
};

constexpr uint64_t kFullBrick = ~uint64_t(0);

bool isActive(const shader::Probe& probe);

class ProbeCache : public testing::GpuTest {
 protected:
  // `depth`: what every pixel of the camera's frames shows (reversed-Z; 0, nothing drawn, by default).
  void create(const Settings& settings, glm::vec3 cameraPosition = kCameraPosition, float depth = 0.0f) {
    settings_ = settings;
    const ContextDesc desc = testing::gpuTestContextDesc(settings, kFrameSize);
    auto result = Context::create(desc);
    ASSERT_TRUE(result.ok()) << result.error().message;
    context_ = std::move(result.value());

    // Nothing drawn (reversed-Z 0 is infinitely far): BrickAllocate finds no surface and the scene stays as written.
    depth_ = gpu::Image(device(), {"test depth", VK_FORMAT_R32_SFLOAT, kFrameSize, kFrameSize, 1, 1,
                                   VK_IMAGE_USAGE_SAMPLED_BIT});
    const std::vector<float> pixels(kFrameSize * kFrameSize, depth);
    gpu::uploadImage(device(), depth_, std::as_bytes(std::span(pixels)));
    moveCamera(cameraPosition);
    runFrames(1);  // places the voxel volume and clears it
  }

  // The scene of the unknown-is-not-sky tests (defined beside them): the black wall beside kProbe, watched by a camera
  // that sees only a surface in front of it.
  void createBesideTheBlackWallAmidUnobservedSpace();

  // Gives the following frames one extra view that only observes (no colour): orthographic, looking along −X through
  // the whole volume (x 16 → −16) over z ∈ [z.x, z.y] and y ∈ [y.x, y.y], at `depth` everywhere (0: nothing drawn).
  // The image is kept in `observerDepth_`.
  void observeAlongMinusX(glm::vec2 z, glm::vec2 y, float depth);

  // The camera of the following frames: at `position`, looking along −Z.
  void moveCamera(glm::vec3 position) {
    renderer::Camera camera;
    camera.position = position;
    camera.target = position - glm::vec3(0.0f, 0.0f, 1.0f);
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.verticalFov = glm::radians(90.0f);
    camera.nearPlane = 0.1f;
    const glm::mat4 viewProjection =
        renderer::reversedZInfiniteProjection(camera.verticalFov, 1.0f, camera.nearPlane) * renderer::viewMatrix(camera);
    std::copy(glm::value_ptr(viewProjection), glm::value_ptr(viewProjection) + 16, view_.viewProjection.begin());
    view_.position = {position.x, position.y, position.z};
    view_.width = view_.height = kFrameSize;
  }

  void runFrames(uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) {
      FrameDesc frame;
      frame.frameIndex = frameIndex_++;
      frame.camera = view_;
      frame.depth.view = depth_.view();
      frame.normal.view = depth_.view();  // nothing is drawn, so the gather never reads a normal
      frame.skyRadianceSh = uniformSkySh(kSkyRadiance);
      if (skyMap_) frame.skyRadianceMap.view = skyMap_->view();
      frame.extraViews = extraViews_;
      frame.countWork = countWork_;
      Error error;
      device().submitAndWait([&](VkCommandBuffer commandBuffer) { error = context_->dispatch(frame, commandBuffer); });
      ASSERT_FALSE(error) << error.message;
    }
  }

  // Runs frames until every level has been updated `updates` more times.
  void runUpdates(uint32_t updates) { runFrames(updates * shader::kProbeLevels); }

  // The test-only way in: writes bricks into the context's voxel scene as live pool entries and brings the occupancy
  // hierarchy up to date with BuildOctree, as a frame's injection would.
  void writeScene(const std::vector<TestBrick>& scene) {
    const gi::VoxelScene& voxels = gi::voxelSceneOf(*context_);
    const glm::ivec3 dimensions(voxels.current().dimensionsBricks);
    std::vector<uint32_t> lookup(voxels.cellCount(), shader::kInvalidBrick);
    std::vector<shader::Brick> bricks;
    std::vector<shader::Voxel> voxelData;
    std::vector<uint32_t> changed{uint32_t(scene.size() + 63) / 64, 1u, 1u, uint32_t(scene.size())};
    for (const TestBrick& brick : scene) {
      ASSERT_TRUE(shader::brickInVolume(brick.coordinate, voxels.current()));
      const uint32_t cell = shader::brickCellIndex(brick.coordinate, dimensions);
      ASSERT_EQ(lookup[cell], shader::kInvalidBrick) << "two bricks in one cell";
      lookup[cell] = uint32_t(bricks.size());
      // Every voxel observed: the scene as views that saw all of it left it.
      bricks.push_back({brick.coordinate, 1u, glm::uvec2(uint32_t(brick.mask), uint32_t(brick.mask >> 32)),
                        glm::uvec2(~0u), 0u, 0u, glm::uvec2(0u)});
      for (uint32_t voxel = 0; voxel < shader::kVoxelsPerBrick; ++voxel) {
        const bool bright = (brick.brightMask >> voxel) & 1u;
        const uint32_t extraViews = brick.albedo ? shader::kVoxelExtraViewsBeforeWrite : 0u;
        voxelData.push_back({shader::packR11G11B10F(bright ? brick.brightRadiance : brick.radiance),
                             shader::packOctahedralNormal(brick.normal) | (extraViews << shader::kVoxelExtraViewsShift),
                             shader::packR11G11B10F(brick.directRadiance),
                             brick.albedo ? shader::packVoxelAlbedo(*brick.albedo) : 0u});
      }
      changed.push_back(cell);
    }
    shader::BrickPoolState pool{};
    pool.bumpCount = uint32_t(bricks.size());
    gpu::uploadBuffer(device(), voxels.brickLookup(), std::as_bytes(std::span(lookup)));
    gpu::uploadBuffer(device(), voxels.bricks(), std::as_bytes(std::span(bricks)));
    gpu::uploadBuffer(device(), voxels.voxels(), std::as_bytes(std::span(voxelData)));
    gpu::uploadBuffer(device(), voxels.poolState(), std::as_bytes(std::span(&pool, 1)));
    gpu::uploadBuffer(device(), voxels.changedCells(), std::as_bytes(std::span(changed)));
    gi::BuildOctree buildOctree(device());
    gpu::DescriptorArena descriptors(device());
    device().submitAndWait([&](VkCommandBuffer commandBuffer) {
      gpu::CommandList commands(device(), commandBuffer, descriptors);
      buildOctree.record(commands, voxels);
    });
  }

  // Each level's probe at kProbe as the probes stand now: it must be active; `check(probe, level)` looks at it.
  template <typename Check>
  void forEachLevelsProbeAtKProbe(Check check) {
    const std::vector<shader::Probe> probes = readProbes();
    for (uint32_t level = 0; level < shader::kProbeLevels; ++level) {
      SCOPED_TRACE("level " + std::to_string(level));
      const shader::Probe probe = probeAt(probes, level, glm::vec3(kProbe));
      ASSERT_TRUE(isActive(probe));
      check(probe, level);
    }
  }

  std::vector<shader::Probe> readProbes() {
    return gpu::readBufferAs<shader::Probe>(device(), gi::probeVolumeOf(*context_).probes());
  }

  uint32_t probesPerLevel() const { return settings_.probeGrid[0] * settings_.probeGrid[1] * settings_.probeGrid[2]; }
  glm::ivec3 probeGrid() const { return {settings_.probeGrid[0], settings_.probeGrid[1], settings_.probeGrid[2]}; }
  float spacing(uint32_t level) const { return settings_.probeSpacing * float(1u << level); }

  // The probe of `level` at a world position (a multiple of the level's spacing).
  shader::Probe probeAt(const std::vector<shader::Probe>& probes, uint32_t level, glm::vec3 position) const {
    const glm::ivec3 coordinate(glm::round(position / spacing(level)));
    const shader::Probe& probe = probes[level * probesPerLevel() + shader::probeSlotIndex(coordinate, probeGrid())];
    EXPECT_TRUE(shader::probeHoldsCoordinate(probe, coordinate)) << "level " << level;
    return probe;
  }

  std::unique_ptr<Context> context_;
  Settings settings_;
  gpu::Image depth_;
  View view_;
  std::vector<ExtraView> extraViews_;  // given with every frame
  std::optional<gpu::Image> observerDepth_;
  const gpu::Image* skyMap_ = nullptr;  // the host's sky map given with every frame, if any
  bool countWork_ = false;             // the frames count their work (FrameDesc::countWork)
  uint32_t frameIndex_ = 0;
};

shader::Sh2Rgb radianceSh(const shader::Probe& probe) { return shader::probeRadianceSh(probe); }
glm::vec4 normalDotSh(const shader::Probe& probe) { return shader::probeNormalDotSh(probe); }
uint32_t historyCount(const shader::Probe& probe) { return shader::probeHistoryCount(probe.state); }
bool isActive(const shader::Probe& probe) {
  return shader::probePlacement(probe.state) == shader::kProbeStateActive;
}
// Traced at least once: active, or found inside geometry (invalid).
bool wasTraced(const shader::Probe& probe) {
  return shader::probePlacement(probe.state) != shader::kProbeStateNeverTraced;
}
// The Y coordinate of a probe from its tag's 8 bits (the scenes lie within ±128 probes of the world origin).
int tagY(uint32_t tag) {
  const int y = int((tag >> 8) & 0xffu);
  return y >= 128 ? y - 256 : y;
}

// The mean of an SH2 over the sphere: L00 / (4π·Y00).
float sphereMean(glm::vec4 sh) { return sh.x / (4.0f * kPi * shader::kSh2Band0Basis); }

// A closed box around kProbe: the outer voxel layer of the 2×2×2 bricks around it, so the cavity is 1.5 m wide and
// the box lies within one spacing of the probe at every level. Each brick's voxels face the probe (along the brick's
// diagonal), so every ray from inside meets a front face.
std::vector<TestBrick> closedBox(glm::vec3 wallRadiance) {
  std::vector<TestBrick> bricks;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::ivec3 side(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);  // 0: the low side of the box
    const glm::ivec3 coordinate = kProbe - 1 + side;
    const glm::ivec3 outerLayer = side * 3;  // the voxel coordinate of the box's face on each axis
    uint64_t mask = 0;
    for (uint32_t bit = 0; bit < shader::kVoxelsPerBrick; ++bit) {
      const glm::ivec3 voxel(int(bit & 3u), int((bit >> 2) & 3u), int(bit >> 4));
      if (glm::any(glm::equal(voxel, outerLayer))) mask |= uint64_t(1) << bit;
    }
    const glm::vec3 centre = glm::vec3(coordinate) + 0.5f;
    bricks.push_back({coordinate, mask, wallRadiance, glm::normalize(glm::vec3(kProbe) - centre)});
  }
  return bricks;
}

// The change-detection tests' start: a context with change detection on or off (the plain blend), its probe settled
// in a closed box of walls of the given radiance, its history at the cap.
class ProbeChangeDetection : public ProbeCache {
 protected:
  Settings settleInClosedBox(bool detection, float wallRadiance) {
    Settings settings = probeTestSettings();
    if (!detection) settings.probeChangeThreshold = 0.0f;
    create(settings);
    writeScene(closedBox(glm::vec3(wallRadiance)));
    runUpdates(40);
    return settings;
  }
};

// The tests that run with and without level 0's reservoirs (Settings::probeReservoirs): the parameter.
class ProbeCacheReservoirs : public ProbeCache, public ::testing::WithParamInterface<bool> {
 protected:
  Settings settingsWithReservoirsAsParameter() const {
    Settings settings = probeTestSettings();
    settings.probeReservoirs = GetParam();
    return settings;
  }
};

INSTANTIATE_TEST_SUITE_P(ProbeReservoirs, ProbeCacheReservoirs, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& parameter) { return parameter.param ? "on" : "off"; });

TEST_P(ProbeCacheReservoirs, aProbeUnderAUniformSkyBesideAVoxelOfTheSameRadianceConvergesToPiTimesTheRadiance) {
  // Placement keeps only probes with a voxel within one spacing, so the sky test needs a voxel; it glows with the
  // sky's radiance and faces up, and the probes checked lie above it, so every ray — hit or miss — sees kSkyRadiance
  // (a furnace). After 32 updates each has traced all 1024 directions: E(n) = π·L to the CPU test's 1 %. With
  // reservoirs (level 0) the estimate must stay unbiased: under constant radiance the reservoirs' part equals the
  // stratum's exact integral and the candidates' 3 × 8 stratified directions per update walk each stratum's set.
  create(settingsWithReservoirsAsParameter());
  const float brickTop = -2.0f;
  writeScene({{{0, -3, 4}, kFullBrick, glm::vec3(kSkyRadiance), {0.0f, 1.0f, 0.0f}}});
  runUpdates(32);
  const std::vector<shader::Probe> probes = readProbes();
  for (uint32_t level = 0; level < shader::kProbeLevels; ++level) {
    uint32_t checked = 0;
    for (uint32_t slot = 0; slot < probesPerLevel(); ++slot) {
      const shader::Probe& probe = probes[level * probesPerLevel() + slot];
      if (!isActive(probe)) continue;
      const int y = tagY(probe.tag);
      if (float(y) * spacing(level) < brickTop) continue;  // below the top: it sees the brick's back faces
      ++checked;
      EXPECT_EQ(historyCount(probe), 32u);
      const shader::Sh2Rgb radiance = radianceSh(probe);
      for (const glm::vec3& normal : testNormals()) {
        const glm::vec3 irradiance = shader::sh2Irradiance(radiance, normal);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(irradiance[c], kPi * kSkyRadiance, 0.01f * kPi * kSkyRadiance)
              << "level " << level << " probe y " << y << " normal " << normal.x << " " << normal.y << " " << normal.z;
      }
    }
    EXPECT_GT(checked, 0u) << "level " << level << ": no probe was placed above the brick";
  }
}

// Voxels follow the light (SPEC §6.1): a voxel that keeps direct light D and albedo a is relit as D + a/π · E of the
// probes. Under a uniform sky of radiance L, with D = (1 − a)·L, the fixed point is the voxel sending out L itself:
// then the probes see L in every direction, E = π·L at any point and normal, and D + a/π · π·L = L exactly. The relit
// bricks start black and must reach it (a missing 1/π would give D + π·a·L, no relight stays black, E = 0 gives D);
// a brick given all its light by its view (no albedo) keeps it as written, relight or not.
TEST_F(ProbeCache, relitVoxelsTakeTheirDirectLightPlusAlbedoOverPiTimesTheProbesIrradiance) {
  Settings settings = probeTestSettings();
  settings.probeHistoryCap = 1;  // the probes follow the voxels as they brighten within a few updates
  create(settings);
  const glm::vec3 albedo(0.2f, 0.4f, 0.8f);  // 51, 102 and 204 of 255: exact in the voxel's 8 bits
  // The top layer of voxels of two bricks (y ∈ [−2.25, −2) m): their surface points, lifted by the normal bias, lie
  // among level 0's probes at y = −2 and −1, which see the layers' front faces and the sky.
  constexpr uint64_t kTopLayer = 0xf000'f000'f000'f000ull;
  TestBrick relit{{0, -3, 4}, kTopLayer, glm::vec3(0.0f), {0.0f, 1.0f, 0.0f}};
  relit.albedo = albedo;
  relit.directRadiance = (glm::vec3(1.0f) - albedo) * kSkyRadiance;
  const TestBrick given{{2, -3, 4}, kTopLayer, glm::vec3(kSkyRadiance), {0.0f, 1.0f, 0.0f}};
  writeScene({relit, given});
  runUpdates(8);
  const gi::VoxelScene& scene = gi::voxelSceneOf(*context_);
  const auto voxels = gpu::readBufferAs<shader::Voxel>(device(), scene.voxels());
  for (uint32_t voxel = 0; voxel < shader::kVoxelsPerBrick; ++voxel) {
    if (((kTopLayer >> voxel) & 1u) == 0) continue;
    SCOPED_TRACE("voxel " + std::to_string(voxel));
    const glm::vec3 radiance = shader::unpackR11G11B10F(voxels[voxel].radiance);
    // R11G11B10F rounds to 2^-7 (R, G) and 2^-6 (B) relative, the probes' half floats to 2^-11.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance[c], kSkyRadiance, 0.02f * kSkyRadiance) << "channel " << c;
    EXPECT_EQ(voxels[shader::kVoxelsPerBrick + voxel].radiance, shader::packR11G11B10F(glm::vec3(kSkyRadiance)));
  }
}

TEST_F(ProbeCache, aProbeInsideAClosedBoxOfBlackVoxelsSeesNoSky) {
  create(probeTestSettings());
  writeScene(closedBox(glm::vec3(0.0f)));
  runUpdates(2);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t level) {
    // Every ray hits a black wall: exactly zero. One sky ray leaking would add (4π/32)·Y00·L ≈ 0.11 to L00.
    const shader::Sh2Rgb radiance = radianceSh(probe);
    for (const glm::vec4& channel : {radiance.r, radiance.g, radiance.b})
      for (int i = 0; i < 4; ++i) EXPECT_EQ(channel[i], 0.0f);
    // The walls are 0.75 to 0.75·√3 m away, all seen from the front (their normals face the probe).
    EXPECT_GE(sphereMean(shader::probeDistanceSh(probe, spacing(level))), 0.75f);
    EXPECT_LE(sphereMean(shader::probeDistanceSh(probe, spacing(level))), 0.75f * std::sqrt(3.0f));
    EXPECT_GT(sphereMean(normalDotSh(probe)), 0.5f);
  });
}

// A black voxel layer at x ∈ [−0.5, −0.25) m spanning the whole volume (y −8..8 m, z −8..24 m), facing +X, a quarter
// metre from kProbe. It hides the −X half of the sky but for the strips past its edges: from 0.25 m an 8 m
// half-width leaves about 1.4 % of the sphere.
std::vector<TestBrick> blackWallBesideTheProbe() {
  std::vector<TestBrick> wall;
  for (int z = -8; z < 24; ++z)
    for (int y = -8; y < 8; ++y) wall.push_back({{-1, y, z}, 0x4444'4444'4444'4444ull, glm::vec3(0.0f), {1, 0, 0}});
  return wall;
}

TEST_F(ProbeCache, aProbeBesideALargeWallSeesHalfTheSky) {
  // The edge strips (1.4 % of the sphere) are within the ±3 % allowed.
  create(probeTestSettings());
  writeScene(blackWallBesideTheProbe());
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    const shader::Sh2Rgb radiance = radianceSh(probe);
    const float skyVisibility = sphereMean(radiance.g) / kSkyRadiance;
    EXPECT_NEAR(skyVisibility, 0.5f, 0.03f);
    // SH2 holds a half-space exactly: E = π·L facing away from the wall, 0 facing it (up to the edge strips).
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {1, 0, 0}), kPi * kSkyRadiance, 0.05f * kPi * kSkyRadiance);
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {-1, 0, 0}), 0.0f, 0.05f * kPi * kSkyRadiance);
    // Where its rays found the sky, which the gather reads apart (readProbeIrradiance): half the sphere's solid angle
    // about +X, read as the same E.
    const glm::vec4 visibility = shader::probeSkyVisibilitySh(probe);
    EXPECT_NEAR(visibility.x / shader::kSh2Band0Basis, 2.0f * kPi, 0.03f * 4.0f * kPi);
    EXPECT_GT(glm::normalize(glm::vec3(visibility.w, visibility.y, visibility.z)).x, 0.99f);
    const shader::Sh2Rgb sky = skySh(kSkyRadiance);
    EXPECT_NEAR(shader::readProbeIrradiance(probe, {1, 0, 0}, sky).g, kPi * kSkyRadiance, 0.05f * kPi * kSkyRadiance);
    EXPECT_NEAR(shader::readProbeIrradiance(probe, {-1, 0, 0}, sky).g, 0.0f, 0.05f * kPi * kSkyRadiance);
  });
}

TEST_F(ProbeCache, raysThatLeaveTheVoxelsSeeTheHostsSkyMapWhereItGivesOne) {
  // The wall of the test above, under a sky map (FrameDesc::skyRadianceMap, 64×32 rgba16f) twice as bright as the SH2
  // sky towards +X and black towards −X: the probe's rays see the map, so E(+X) = 2π·L (π·L from the SH2 sky), and
  // E(−X) = 0. Were the map read the wrong way round, the wall would hide its bright half. Where the rays found the sky
  // stays half the sphere about +X.
  create(probeTestSettings());
  constexpr uint32_t kWidth = 64, kHeight = 32;
  gpu::Image map(device(), {"test sky map", VK_FORMAT_R16G16B16A16_SFLOAT, kWidth, kHeight, 1, 1,
                            VK_IMAGE_USAGE_SAMPLED_BIT});
  std::vector<uint16_t> texels;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const glm::vec3 direction =
          shader::skyMapDirection((glm::vec2(x, y) + 0.5f) / glm::vec2(float(kWidth), float(kHeight)));
      const float radiance = direction.x > 0.0f ? 2.0f * kSkyRadiance : 0.0f;
      for (float channel : {radiance, radiance, radiance, 1.0f}) texels.push_back(glm::packHalf1x16(channel));
    }
  gpu::uploadImage(device(), map, std::as_bytes(std::span(texels)));
  skyMap_ = &map;
  writeScene(blackWallBesideTheProbe());
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    const shader::Sh2Rgb radiance = radianceSh(probe);
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {1, 0, 0}), 2.0f * kPi * kSkyRadiance, 0.1f * kPi * kSkyRadiance);
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {-1, 0, 0}), 0.0f, 0.05f * kPi * kSkyRadiance);
    const glm::vec4 visibility = shader::probeSkyVisibilitySh(probe);
    EXPECT_NEAR(visibility.x / shader::kSh2Band0Basis, 2.0f * kPi, 0.03f * 4.0f * kPi);
  });
  skyMap_ = nullptr;
}

// Unknown is not sky (SPEC §6.4): the wall of the test above, but the camera sees only a surface half a metre in
// front of it, so that no view has observed the space around the probe. Its rays that meet the wall are known (and
// black); those that meet nothing crossed unobserved space and stand for the mean of the known rays, all of which met
// the wall: no sky light (the same scene watched the other way round gives E(+X) = π·L, above), and half of its rays known.
void ProbeCache::createBesideTheBlackWallAmidUnobservedSpace() {
  Settings settings = probeTestSettings();
  settings.skyOnlyThroughObservedSpace = true;
  // Reversed-Z with an infinite far plane: depth = near / distance, a surface 0.5 m away at the 0.1 m near plane.
  create(settings, kCameraPosition, 0.1f / 0.5f);
  writeScene(blackWallBesideTheProbe());
}

void ProbeCache::observeAlongMinusX(glm::vec2 z, glm::vec2 y, float depth) {
  // The view's eye on the volume's +X face (x = 16) at z = 8; its right is −Z, so z ∈ [z.x, z.y] is the view's
  // x ∈ [8 − z.y, 8 − z.x].
  const glm::vec3 eye(16.0f, 0.0f, 8.0f);
  const glm::mat4 viewProjection =
      renderer::reversedZOrthographicProjection(8.0f - z.y, 8.0f - z.x, y.x, y.y, 0.0f, 32.0f) *
      glm::lookAtRH(eye, eye - glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  observerDepth_.emplace(device(), gpu::ImageDesc{"observer depth", VK_FORMAT_R32_SFLOAT, kFrameSize, kFrameSize, 1, 1,
                                                  VK_IMAGE_USAGE_SAMPLED_BIT});
  const std::vector<float> pixels(kFrameSize * kFrameSize, depth);
  gpu::uploadImage(device(), *observerDepth_, std::as_bytes(std::span(pixels)));
  ExtraView observer;
  std::copy(glm::value_ptr(viewProjection), glm::value_ptr(viewProjection) + 16, observer.camera.viewProjection.begin());
  observer.camera.width = observer.camera.height = kFrameSize;
  observer.depth.view = observerDepth_->view();
  extraViews_ = {observer};
}

TEST_F(ProbeCache, aProbeAmidSpaceNoViewHasObservedGetsNoSkyLightAndKnowsHalfItsRays) {
  createBesideTheBlackWallAmidUnobservedSpace();
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    const shader::Sh2Rgb radiance = radianceSh(probe);
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {1, 0, 0}), 0.0f, 0.02f * kPi * kSkyRadiance);
    // Nor does the sky read apart: its unknown rays found no sky.
    EXPECT_NEAR(shader::probeSkyVisibilitySh(probe).x / shader::kSh2Band0Basis, 0.0f, 0.02f * 4.0f * kPi);
    // The wall covers half the sphere but for the strips past its edges (1.4 %); 8-bit known fraction, 32 updates.
    EXPECT_NEAR(shader::probeKnownFraction(probe), 0.5f, 0.05f);
  });
}

// The scene of the test above with the wall sunlit: it sends out R = 1.5·L, of which D = L is direct light (the sun's
// view gave it). A ray into space no view has observed stands for the known rays' light less the surfaces' direct
// part: no view of a light saw a surface lit there. So E = π·(R − D) facing away from the wall and π·R facing it (SH2 holds each
// half-space exactly; the strips past the wall's edges, 1.4 %, are within the tolerance).
TEST_F(ProbeCache, aRayIntoSpaceNoViewHasObservedStandsForTheSurfacesLightLessItsDirectPart) {
  createBesideTheBlackWallAmidUnobservedSpace();
  std::vector<TestBrick> sunlitWall = blackWallBesideTheProbe();
  for (TestBrick& brick : sunlitWall) {
    brick.radiance = glm::vec3(1.5f * kSkyRadiance);
    brick.directRadiance = glm::vec3(kSkyRadiance);
  }
  writeScene(sunlitWall);
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    const glm::vec4 green = radianceSh(probe).g;
    EXPECT_NEAR(shader::sh2Irradiance(green, {1, 0, 0}), kPi * 0.5f * kSkyRadiance, 0.05f * kPi * kSkyRadiance);
    EXPECT_NEAR(shader::sh2Irradiance(green, {-1, 0, 0}), kPi * 1.5f * kSkyRadiance, 0.05f * kPi * kSkyRadiance);
  });
}

// The black wall beside the probe, and a view that only observes the half of the volume beyond the probe (z > 4): the
// probe's rays that pass the wall there find the sky (a quarter of the sphere), those that pass it on the near side
// (z < 4) cross unobserved space. SPEC §6.4: the estimate is formed over the rays that found something known, so an
// unknown ray stands for the mean of the known ones: the surfaces' light, and the sky as often as the known rays of its
// half of the sphere (above or below the horizon) found it — in either half a third of them — so the probe holds the
// sky in a third of its unknown quarter: Ω = π + π/3 of sky, and a mean radiance of L/3 over the sphere (L/4 if the
// unknown rays took the wall's black, 1/2 if they took the sky).
// The strips past the wall's edges (1.4 %) are within the bounds.
TEST_F(ProbeCache, aRayIntoSpaceNoViewHasObservedStandsForTheMeanOfTheKnownRaysTheSkyIncluded) {
  createBesideTheBlackWallAmidUnobservedSpace();
  observeAlongMinusX({4.0f, kVolumeZ.y}, kVolumeY, 0.0f);
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    EXPECT_NEAR(sphereMean(radianceSh(probe).g) / kSkyRadiance, 1.0f / 3.0f, 0.03f);
    EXPECT_NEAR(shader::probeSkyVisibilitySh(probe).x / shader::kSh2Band0Basis, 4.0f * kPi / 3.0f, 0.03f * 4.0f * kPi);
    EXPECT_NEAR(shader::probeKnownFraction(probe), 0.75f, 0.05f);  // 8-bit known fraction
  });
}

// The same, with the view observing only the space above the probe (y > 0): its rays past the wall find the sky
// above the horizon and cross unobserved space below it. An unknown ray takes the sky as often as the known rays of
// its own half of the sphere found it: below the horizon those all met the black wall, so the probe holds the sky in
// its upper +X quarter alone: Ω = π and a mean radiance of L/4 (with the whole sphere's share, 4π/3 and L/3 as above).
TEST_F(ProbeCache, aRayIntoSpaceNoViewHasObservedBelowTheHorizonTakesNoSkyFoundAboveIt) {
  createBesideTheBlackWallAmidUnobservedSpace();
  observeAlongMinusX(kVolumeZ, {0.0f, kVolumeY.y}, 0.0f);
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    EXPECT_NEAR(sphereMean(radianceSh(probe).g) / kSkyRadiance, 0.25f, 0.03f);
    EXPECT_NEAR(shader::probeSkyVisibilitySh(probe).x / shader::kSh2Band0Basis, kPi, 0.03f * 4.0f * kPi);
    EXPECT_NEAR(shader::probeKnownFraction(probe), 0.75f, 0.05f);  // 8-bit known fraction
  });
}

// The scene of the test above, and a view that only observes (ExtraView without colour, SPEC §6.4): orthographic,
// looking along −X over the whole volume, nothing drawn in it. Every brick cell it looks through is observed, so
// the probe's rays that pass the wall see the sky again — E(+X) = π·L, as in the scene watched without observed
// space — and nearly all its rays are known. Given a surface to show instead, it still writes no voxel.
TEST_F(ProbeCache, aViewThatOnlyObservesMakesTheSkyKnownWithoutWritingVoxels) {
  createBesideTheBlackWallAmidUnobservedSpace();
  runFrames(1);
  const uint32_t bricksBefore = context_->stats().bricksLive;  // the wall's, and the one the camera sees

  observeAlongMinusX(kVolumeZ, kVolumeY, 0.0f);  // the volume's whole cross-section
  runUpdates(32);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t) {
    EXPECT_NEAR(shader::sh2Irradiance(radianceSh(probe).g, {1, 0, 0}), kPi * kSkyRadiance, 0.05f * kPi * kSkyRadiance);
    EXPECT_GT(shader::probeKnownFraction(probe), 0.95f);  // 8-bit known fraction
  });
  EXPECT_EQ(context_->stats().bricksLive, bricksBefore);

  // A plane across the volume at x = 0 (halfway along the view's depth range): a view that injected would allocate
  // its bricks.
  observeAlongMinusX(kVolumeZ, kVolumeY, 0.5f);
  runFrames(4);
  EXPECT_EQ(context_->stats().bricksLive, bricksBefore);
  extraViews_.clear();
}

TEST_P(ProbeCacheReservoirs, theHistoryCountGrowsByOnePerUpdateToItsCapAndAlphaIsOneOverCountPlusOne) {
  Settings settings = settingsWithReservoirsAsParameter();
  settings.probeHistoryCap = 4;
  settings.probeChangeThreshold = 0.0f;  // the plain blend (change detection is tested below)
  create(settings);
  // Inside the closed box every ray sees the walls' radiance A, so every update's L00 is exactly 4π·Y00·A: the
  // blend must keep it (half floats: 2^-11 relative per store).
  const float wallA = 1.0f, wallB = 3.0f;
  writeScene(closedBox(glm::vec3(wallA)));
  for (uint32_t update = 1; update <= 6; ++update) {
    runUpdates(1);
    const shader::Probe probe = probeAt(readProbes(), 0, glm::vec3(kProbe));
    SCOPED_TRACE("update " + std::to_string(update));
    EXPECT_EQ(historyCount(probe), std::min(update, settings.probeHistoryCap));
    // Without reservoirs the next 32 of the 1024 directions; with them each stratum's next 3 (of its 128; the counter
    // runs modulo 3·128).
    const uint32_t candidates = settings.raysPerProbe / shader::kProbeStrata - 1;
    EXPECT_EQ(shader::probeNextDirection(probe.state),
              settings.probeReservoirs ? update * candidates % (candidates * shader::kProbeStratumDirectionCount)
                                       : update * settings.raysPerProbe % shader::kProbeRayDirectionCount);
    EXPECT_NEAR(sphereMean(radianceSh(probe).r), wallA, 2e-3f * wallA);
  }
  // The walls change to B once m is at its cap: one update moves the probe by α = 1/(cap+1) of the step. With
  // reservoirs the update's estimate itself has only moved part of the way: each stratum's reservoir stands for
  // min(M cap, c·m) candidates of A besides this update's c candidates of B (probe_trace.comp).
  writeScene(closedBox(glm::vec3(wallB)));
  runUpdates(1);
  const shader::Probe probe = probeAt(readProbes(), 0, glm::vec3(kProbe));
  const float candidates = float(settings.raysPerProbe / shader::kProbeStrata - 1);
  const float reused = std::min(float(settings.probeReservoirHistoryCap), candidates * float(settings.probeHistoryCap));
  const float estimateStep = settings.probeReservoirs ? candidates / (candidates + reused) : 1.0f;
  const float expected = wallA + estimateStep * (wallB - wallA) / float(settings.probeHistoryCap + 1);
  EXPECT_NEAR(sphereMean(radianceSh(probe).r), expected, 2e-3f * expected);
  EXPECT_EQ(historyCount(probe), settings.probeHistoryCap);
}

// Less lag (SPEC §6.2): the walls of the closed box brighten 4× once the probe's history is at its cap of 32. The
// trimmed mean of the next update is 4× its history's (d = 0.6) against a usual deviation of nothing (the floor,
// 5 %): the history shrinks to nothing and the probe takes the new light at once. Without change detection one update
// moves it by 1/33 of the step, and four updates by 1 − (32/33)^4 = 11.6 %.
TEST_F(ProbeChangeDetection, aProbeWhoseSurroundingsBrightenFollowsWithinAnUpdateAndWithoutItOnlyByItsBlend) {
  constexpr float kBefore = 0.25f, kAfter = 1.0f;
  for (const bool detection : {true, false}) {
    SCOPED_TRACE(detection ? "change detection on" : "change detection off");
    const Settings settings = settleInClosedBox(detection, kBefore);
    ASSERT_EQ(historyCount(probeAt(readProbes(), 0, glm::vec3(kProbe))), settings.probeHistoryCap);
    writeScene(closedBox(glm::vec3(kAfter)));
    runUpdates(1);
    shader::Probe probe = probeAt(readProbes(), 0, glm::vec3(kProbe));
    const float afterOne = sphereMean(radianceSh(probe).r);
    if (detection) {
      EXPECT_NEAR(afterOne, kAfter, 2e-3f * kAfter);
      EXPECT_EQ(historyCount(probe), 1u) << "the history shrank to nothing, then counted this update";
    } else {
      EXPECT_NEAR(afterOne, kBefore + (kAfter - kBefore) / 33.0f, 2e-3f * kAfter);
      EXPECT_EQ(historyCount(probe), settings.probeHistoryCap);
    }
    runUpdates(3);
    probe = probeAt(readProbes(), 0, glm::vec3(kProbe));
    const float expected = detection ? kAfter : kBefore + (kAfter - kBefore) * (1.0f - std::pow(32.0f / 33.0f, 4.0f));
    EXPECT_NEAR(sphereMean(radianceSh(probe).r), expected, 2e-3f * kAfter);
  }
}

// The ray budget goes to the probes that change (SPEC §6.2, Settings::settledProbeInterval): settled at its cap in a
// still box, the probe is traced on every other update of its level; once its walls brighten it is traced on its
// next turn, takes the new light at once (change detection) and is traced on every update from then on, until its
// history is at the cap again. Its traces are counted by its direction counter, which moves on 32 a trace.
TEST_F(ProbeChangeDetection, aSettledProbeIsTracedEveryOtherUpdateAndEveryUpdateOnceItFollowsAChange) {
  constexpr float kBefore = 0.25f, kAfter = 1.0f;
  Settings settings = probeTestSettings();
  settings.settledProbeInterval = 2;
  create(settings);
  writeScene(closedBox(glm::vec3(kBefore)));
  runUpdates(40);
  const auto probe = [&] { return probeAt(readProbes(), 0, glm::vec3(kProbe)); };
  const auto direction = [&] { return shader::probeNextDirection(probe().state); };
  const auto tracesSince = [&](uint32_t before) {
    return (direction() + shader::kProbeRayDirectionCount - before) % shader::kProbeRayDirectionCount /
           settings.raysPerProbe;
  };
  ASSERT_EQ(historyCount(probe()), settings.probeHistoryCap);
  uint32_t before = direction();
  runUpdates(8);
  EXPECT_EQ(tracesSince(before), 4u) << "settled: every other update";
  EXPECT_NEAR(sphereMean(radianceSh(probe()).r), kBefore, 2e-3f * kBefore);

  writeScene(closedBox(glm::vec3(kAfter)));
  before = direction();
  runUpdates(2);  // its turn comes in one of these two
  EXPECT_EQ(tracesSince(before), 1u);
  EXPECT_NEAR(sphereMean(radianceSh(probe()).r), kAfter, 2e-3f * kAfter) << "followed at once";
  before = direction();
  runUpdates(8);
  EXPECT_EQ(tracesSince(before), 8u) << "following a change: every update";
  EXPECT_LT(historyCount(probe()), settings.probeHistoryCap);
}

// Light that grows over many updates, as the bounces after a light switched on come in round the voxel → probe loop:
// the walls of the closed box brighten by 10 % per update. No single update strays from the history by twice the
// noise floor at first: the first four stray by 0.9, 1.9, 2.8 and 3.5 floors, and less the allowance of one floor
// each their sum passes four floors at the 4th; the probe then follows with a history of at most 1
// (kProbeChangeRecoveryHistory), the drift starting it again at the 8th. Worked through by hand for these exact walls
// (every ray sees the walls, so every trimmed mean is their radiance), the rules give after 12 updates 0.92 of the
// walls' radiance, the single-update rule alone 0.69 and the plain blend 0.42 (the GPU agrees: docs/QUALITY.md, "What
// the scenario tests' bounds rest on"); the bounds lie between.
TEST_F(ProbeChangeDetection, aProbeWhoseSurroundingsBrightenStepByStepKeepsUpWithThem) {
  constexpr float kStart = 0.25f, kGrowth = 1.1f;
  constexpr uint32_t kSteps = 12;
  for (const bool detection : {true, false}) {
    SCOPED_TRACE(detection ? "change detection on" : "change detection off");
    settleInClosedBox(detection, kStart);
    float walls = kStart;
    for (uint32_t step = 0; step < kSteps; ++step) {
      walls *= kGrowth;
      writeScene(closedBox(glm::vec3(walls)));
      runUpdates(1);
    }
    const float followed = sphereMean(radianceSh(probeAt(readProbes(), 0, glm::vec3(kProbe))).r) / walls;
    std::printf("a probe in walls brightening 10 %% per update: %.3f of their radiance after %u updates\n", followed,
                kSteps);
    if (detection)
      EXPECT_GT(followed, 0.85f);
    else
      EXPECT_LT(followed, 0.5f);
  }
}

// The other side of change detection: a probe whose updates are noisy by nature keeps its history. In the closed
// box one voxel of a wall glows 200× as bright as the walls: 0.25 m wide and 0.9 m away, it fills about 0.5 % of the
// sphere, so an update's 32 rays find it about every sixth update, and the update's mean is then 7× the walls'. The
// trimmed mean leaves out the brightest eighth of the rays and does not see it, so the history count stays at its cap
// while the history itself moves with those hits.
TEST_F(ProbeChangeDetection, aProbeThatARareBrightVoxelMakesNoisyKeepsItsHistory) {
  Settings settings = probeTestSettings();
  create(settings);
  std::vector<TestBrick> box = closedBox(glm::vec3(0.05f));
  // The low corner brick, (−1, −1, 3): its voxel (0, 1, 1) lies on the inner face of the box's −X wall.
  box[0].brightMask = uint64_t(1) << (0 + 4 * 1 + 16 * 1);
  box[0].brightRadiance = glm::vec3(10.0f);
  writeScene(box);
  runUpdates(40);
  uint32_t lowestCount = settings.probeHistoryCap;
  float lowestMean = 1e30f, highestMean = 0.0f;
  for (uint32_t update = 0; update < 64; ++update) {
    runUpdates(1);
    const shader::Probe probe = probeAt(readProbes(), 0, glm::vec3(kProbe));
    lowestCount = std::min(lowestCount, historyCount(probe));
    lowestMean = std::min(lowestMean, sphereMean(radianceSh(probe).r));
    highestMean = std::max(highestMean, sphereMean(radianceSh(probe).r));
  }
  EXPECT_EQ(lowestCount, settings.probeHistoryCap);
  EXPECT_GT(highestMean, 1.1f * lowestMean) << "the bright voxel does make the probe noisy";
}

TEST_F(ProbeCache, placementTracesOnlyProbesNearVoxelsAndNoMoreThanTheBudget) {
  Settings settings = probeTestSettings();
  create(settings);
  runFrames(2);  // an empty scene: nothing to place
  EXPECT_EQ(context_->stats().probesUpdatedLastFrame, 0u);

  // One brick: level 0 keeps the 8 probes at its corners (the cell of one spacing holding it), in view.
  writeScene({{{0, -3, 4}, kFullBrick, glm::vec3(0.0f), {0.0f, 1.0f, 0.0f}}});
  runFrames((3 - frameIndex_ % 3) % 3);  // the next frame to run updates level 0
  runFrames(1);
  Stats stats = context_->stats();
  EXPECT_EQ(stats.probeLevelUpdatedLastFrame, 0u);
  EXPECT_EQ(stats.probesUpdatedLastFrame, 8u);
  std::vector<shader::Probe> probes = readProbes();
  uint32_t traced = 0;
  for (uint32_t slot = 0; slot < probesPerLevel(); ++slot) traced += wasTraced(probes[slot]) ? 1u : 0u;
  EXPECT_EQ(traced, 8u);
  for (int corner = 0; corner < 8; ++corner)
    EXPECT_TRUE(wasTraced(probeAt(probes, 0, glm::vec3(corner & 1, -3 + (corner >> 1 & 1), 4 + (corner >> 2)))));

  // A wall near the camera with a budget of 5: exactly 5 listed and traced.
  settings.probeBudget = 5;
  create(settings);
  std::vector<TestBrick> wall;
  for (int y = -2; y < 2; ++y)
    for (int x = -2; x < 2; ++x) wall.push_back({{x, y, 4}, kFullBrick, glm::vec3(0.0f), {0.0f, 0.0f, 1.0f}});
  writeScene(wall);
  runFrames((3 - frameIndex_ % 3) % 3);
  runFrames(1);
  stats = context_->stats();
  EXPECT_EQ(stats.probeLevelUpdatedLastFrame, 0u);
  EXPECT_EQ(stats.probesUpdatedLastFrame, 5u);
  probes = readProbes();
  traced = 0;
  for (uint32_t slot = 0; slot < probesPerLevel(); ++slot) traced += wasTraced(probes[slot]) ? 1u : 0u;
  EXPECT_EQ(traced, 5u);
}

// ---------------------------------------------------------------------------------------------------------------------
// Second slice: new probes start from the coarser level; virtual offset, invalid probes and dilation.

uint32_t placement(const shader::Probe& probe) { return shader::probePlacement(probe.state); }
// The virtual offset of a probe of a level with `spacing`, metres.
glm::vec3 offsetOf(const shader::Probe& probe, float spacing) {
  return glm::vec3(shader::unpackProbeOffset(shader::probeOffsetCode(probe.state))) * spacing /
         shader::kProbeOffsetStepsPerSpacing;
}
// The least of the normal-dot SH along the 26 neighbour directions: negative when the probe sees back faces.
float leastNormalDot(const shader::Probe& probe) {
  float least = 1e30f;
  for (uint32_t i = 0; i < shader::kProbeNeighbourCount; ++i)
    least = std::min(least, glm::dot(normalDotSh(probe),
                                     shader::sh2Basis(glm::normalize(glm::vec3(shader::probeNeighbourOffset(i))))));
  return least;
}

TEST_F(ProbeCache, aProbeThatScrollsInStartsFromTheCoarserLevelAndProbesThatStayKeepTheirValuesBitForBit) {
  // From z = 13.5 m level 0 spans probes z 5..20 and does not hold kProbe (z 4); levels 1 and 2 do. Inside the closed
  // box every ray sees the walls, so every level's kProbe holds exactly the walls' radiance A. Then the walls change
  // to B and the camera moves back one spacing, so that the next frame (level 0's) scrolls kProbe in: its first trace
  // sees B, and it starts from level 1's A (the levels nest: kProbe coincides with a level-1 probe, whose weight is 1)
  // as one earlier update, so it holds (A + B)/2 — not B, as it would starting afresh, nor B/2 starting from zero.
  const glm::vec3 before(2.5f, 0.5f, 13.5f), after(2.5f, 0.5f, 12.5f);
  create(probeTestSettings(), before);
  const float wallA = 1.0f, wallB = 3.0f;
  writeScene(closedBox(glm::vec3(wallA)));
  runUpdates(2);
  runFrames((3 - frameIndex_ % 3) % 3);  // the next frame updates level 0
  const std::vector<shader::Probe> probesBefore = readProbes();
  const shader::Probe coarser = probeAt(probesBefore, 1, glm::vec3(kProbe));
  ASSERT_TRUE(isActive(coarser) && historyCount(coarser) > 0);
  ASSERT_NEAR(sphereMean(radianceSh(coarser).r), wallA, 2e-3f * wallA);
  const glm::ivec3 levelZeroOrigin = glm::ivec3(glm::floor(before)) - probeGrid() / 2;
  ASSERT_GT(levelZeroOrigin.z, kProbe.z) << "kProbe must be new to level 0";

  writeScene(closedBox(glm::vec3(wallB)));
  moveCamera(after);
  runFrames(1);
  const std::vector<shader::Probe> probesAfter = readProbes();
  const shader::Probe scrolledIn = probeAt(probesAfter, 0, glm::vec3(kProbe));
  EXPECT_TRUE(isActive(scrolledIn));
  EXPECT_EQ(historyCount(scrolledIn), 1u);
  // Two half-float stores (level 1's value, then the blend): 2^-11 relative each.
  const float expected = 0.5f * (wallA + wallB);
  EXPECT_NEAR(sphereMean(radianceSh(scrolledIn).r), expected, 2e-3f * expected);

  // Only the probes traced this frame change: levels 1 and 2 and every unlisted probe of level 0 keep every bit.
  const std::vector<uint32_t> list = gpu::readBufferAs<uint32_t>(device(), gi::probeVolumeOf(*context_).list());
  const uint32_t listed = list[3];
  ASSERT_GT(listed, 0u);
  std::vector<bool> traced(probesAfter.size(), false);
  for (uint32_t i = 0; i < listed; ++i) traced[list[shader::kIndirectListHeaderWords + i]] = true;
  uint32_t unchanged = 0;
  for (size_t i = 0; i < probesAfter.size(); ++i) {
    if (traced[i]) continue;
    ASSERT_EQ(std::memcmp(&probesAfter[i], &probesBefore[i], sizeof(shader::Probe)), 0) << "probe " << i;
    ++unchanged;
  }
  EXPECT_EQ(unchanged, probesAfter.size() - listed);
}

// The closed wall of `wallTest`: one voxel layer at x ∈ [0, 0.25) m facing −X, spanning the volume (y −8..8 m,
// z −8..24 m). kProbe, at x = 0, lies inside its voxels.
std::vector<TestBrick> wallThroughTheProbe() {
  std::vector<TestBrick> wall;
  for (int z = -8; z < 24; ++z)
    for (int y = -8; y < 8; ++y) wall.push_back({{0, y, z}, 0x1111'1111'1111'1111ull, glm::vec3(0.0f), {-1, 0, 0}});
  return wall;
}

TEST_F(ProbeCache, aProbeInsideAWallMovesOutInFrontOfItWithinHalfASpacingAndThenSeesNoBackFaces) {
  // Traced from inside an occupied voxel, every ray stops at distance 0 and half of them see a back face. The
  // nearest back face is along −X (all distances tie at 0; the normal-dot is least there), so the probe moves along
  // −X out of the voxel, and its following traces see the black wall from the front and the sky behind it.
  create(probeTestSettings());
  writeScene(wallThroughTheProbe());
  runUpdates(4);
  forEachLevelsProbeAtKProbe([&](const shader::Probe& probe, uint32_t level) {
    const glm::vec3 offset = offsetOf(probe, spacing(level));
    EXPECT_LT(offset.x, 0.0f);  // in front of the wall's voxels, which start at x = 0
    EXPECT_GT(offset.x, -0.5f * spacing(level));
    EXPECT_EQ(offset.y, 0.0f);
    EXPECT_EQ(offset.z, 0.0f);
    EXPECT_GE(historyCount(probe), 1u);  // traced since it moved
    EXPECT_GE(leastNormalDot(probe), 0.0f);
    // Half misses (+1), half front faces (cos, mean 1/2): 3/4. From inside the voxel it was 0.
    EXPECT_NEAR(sphereMean(normalDotSh(probe)), 0.75f, 0.1f);
    EXPECT_NEAR(sphereMean(radianceSh(probe).g) / kSkyRadiance, 0.5f, 0.1f);  // the sky again; 0 from inside
  });
}

TEST_F(ProbeCache, everyListedProbeInsideAWallMovesOutNotOnlyAWorkgroupsWorth) {
  // Level 0's 128 probes at x = 0 (y −4..3, z 2..17) lie inside the wall's voxels, and ProbePlacement lists them with
  // their neighbours at x = ±1: hundreds of probes, more than a workgroup of ProbeRelocate's threads. Each of them that
  // has been traced has moved out in front of the wall, as kProbe does in the test above.
  create(probeTestSettings());
  writeScene(wallThroughTheProbe());
  runUpdates(4);
  const std::vector<shader::Probe> probes = readProbes();
  uint32_t traced = 0;
  for (int z = 2; z <= 17; ++z)
    for (int y = -4; y <= 3; ++y) {
      const glm::ivec3 coordinate(0, y, z);
      const shader::Probe& probe = probes[shader::probeSlotIndex(coordinate, probeGrid())];  // level 0 comes first
      if (!shader::probeHoldsCoordinate(probe, coordinate) || historyCount(probe) == 0u) continue;
      ++traced;
      EXPECT_LT(offsetOf(probe, spacing(0)).x, 0.0f) << "probe (0, " << y << ", " << z << ")";
    }
  EXPECT_GT(traced, shader::kProbeListGroupSize);
}

// A solid block of 2×2×2 full bricks around kProbe (±1 m), radiance `radiance`, all its voxels facing up.
std::vector<TestBrick> solidBlock(glm::vec3 radiance) {
  std::vector<TestBrick> bricks;
  for (int corner = 0; corner < 8; ++corner)
    bricks.push_back({kProbe - 1 + glm::ivec3(corner & 1, (corner >> 1) & 1, corner >> 2), kFullBrick, radiance,
                      {0.0f, 1.0f, 0.0f}});
  return bricks;
}

TEST_F(ProbeCache, aProbeInsideABlockItCannotLeaveWithinHalfASpacingIsInvalidAndOneThatCanMovesOut) {
  // kProbe is 1 m from every face of the block. Levels 0 and 1 may move it at most 7/16 and 7/8 m per axis: still
  // inside, so it is invalid (and keeps no offset). Level 2 may move it 1.75 m: it leaves through the top (the back
  // faces it sees from inside the upward-facing voxels are above it) and stays out.
  create(probeTestSettings());
  writeScene(solidBlock(glm::vec3(0.5f)));
  runUpdates(3);
  const std::vector<shader::Probe> probes = readProbes();
  for (uint32_t level = 0; level < 2; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    const shader::Probe probe = probeAt(probes, level, glm::vec3(kProbe));
    EXPECT_EQ(placement(probe), shader::kProbeStateInvalid);
    EXPECT_EQ(offsetOf(probe, spacing(level)), glm::vec3(0.0f));
  }
  const shader::Probe escaped = probeAt(probes, 2, glm::vec3(kProbe));
  ASSERT_TRUE(isActive(escaped));
  const glm::vec3 offset = offsetOf(escaped, spacing(2));
  EXPECT_EQ(offset.x, 0.0f);
  EXPECT_GE(offset.y, 1.0f);  // above the block's top
  EXPECT_LT(offset.y, 0.5f * spacing(2));
  EXPECT_EQ(offset.z, 0.0f);
  EXPECT_GE(leastNormalDot(escaped), 0.0f);
}

TEST_F(ProbeCache, anInvalidProbeTakesTheMeanRadianceOfItsUsableNeighbours) {
  // Level 0's kProbe is invalid inside the block (previous test); its neighbours above the block and beside it see
  // the sky and the block's top. After the frame that updated level 0, its radiance is their mean, channel by channel
  // and coefficient by coefficient — not what it traced inside (the block's faces, black behind them).
  create(probeTestSettings());
  writeScene(solidBlock(glm::vec3(0.5f)));
  runUpdates(3);
  const std::vector<shader::Probe> probes = readProbes();
  const shader::Probe invalid = probeAt(probes, 0, glm::vec3(kProbe));
  ASSERT_EQ(placement(invalid), shader::kProbeStateInvalid);
  shader::Sh2Rgb mean{};
  uint32_t usable = 0;
  for (uint32_t i = 0; i < shader::kProbeNeighbourCount; ++i) {
    const glm::ivec3 coordinate = kProbe + shader::probeNeighbourOffset(i);
    const shader::Probe& neighbour = probes[shader::probeSlotIndex(coordinate, probeGrid())];
    if (!shader::probeIsUsable(neighbour, coordinate)) continue;
    mean = shader::sh2Add(mean, radianceSh(neighbour));
    ++usable;
  }
  // At least the 9 above the block's top (they see its front faces and the sky).
  ASSERT_GE(usable, 9u);
  const shader::Sh2Rgb filled = radianceSh(invalid);
  for (int channel = 0; channel < 3; ++channel) {
    const glm::vec4 expected = (channel == 0 ? mean.r : channel == 1 ? mean.g : mean.b) / float(usable);
    const glm::vec4 actual = channel == 0 ? filled.r : channel == 1 ? filled.g : filled.b;
    EXPECT_GT(expected.x, 0.0f);
    // One half-float store of a mean of half floats: 2^-11 relative, and half's spacing near zero.
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(actual[i], expected[i], 1e-3f * std::abs(expected[i]) + 1e-4f) << "channel " << channel << " " << i;
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// The work the passes count (Stats::work, FrameDesc::countWork).

// Every count of a frame that did not count its work is 0.
void expectNoWorkCounted(const WorkCounts& work) {
  EXPECT_FALSE(work.counted);
  const uint32_t counts[] = {work.hizBuild.texels,
                             work.observedSpace.rays,
                             work.observedSpace.cells,
                             work.sceneVoxelization.voxels,
                             work.sceneVoxelization.voxelsInView,
                             work.extraViewVoxelization.voxels,
                             work.extraViewVoxelization.voxelsInView,
                             work.voxelRelight.voxels,
                             work.voxelRelight.visibility.rays,
                             work.voxelRelight.visibility.reads,
                             work.probePlacement.probes,
                             work.probePlacement.reads,
                             work.probeTrace.probes,
                             work.probeTrace.rays.rays,
                             work.probeTrace.rays.reads,
                             work.probeTrace.seedVisibility.rays,
                             work.probeTrace.seedVisibility.reads,
                             work.probeRelocate.rays,
                             work.probeRelocate.reads,
                             work.finalGather.tiles,
                             work.finalGather.visibility.rays,
                             work.finalGather.visibility.reads,
                             work.temporalUpsample.pixels};
  for (size_t i = 0; i < std::size(counts); ++i) EXPECT_EQ(counts[i], 0u) << "count " << i;
}

TEST_F(ProbeCache, probeTraceCountsRaysPerProbeForEachProbeAndASeedRayForEachUsableCoarserProbeApart) {
  // One brick. Frame 1 updates level 1, whose coarser level has never been traced: its new probes start from nothing.
  // Frame 2 (level 2) does not count. Frame 3 updates level 0, all of whose probes are new: each tests its visibility
  // to every coarser probe around it with a trilinear weight, usable (traced at frame 1, not moved since) and more than
  // half a voxel away — a count taken here from level 1's probes as frame 3 finds them. 16 rays per probe, not the
  // workgroup's 32 threads.
  Settings settings = probeTestSettings();
  settings.raysPerProbe = 16;
  create(settings);  // frame 0, level 0: nothing to trace yet
  writeScene({{{0, -3, 4}, kFullBrick, glm::vec3(0.5f), {0.0f, 1.0f, 0.0f}}});
  countWork_ = true;
  runFrames(1);
  Stats stats = context_->stats();
  ASSERT_TRUE(stats.work.counted);
  ASSERT_EQ(stats.probeLevelUpdatedLastFrame, 1u);
  ASSERT_GT(stats.probesUpdatedLastFrame, 0u);
  EXPECT_EQ(stats.work.probeTrace.probes, stats.probesUpdatedLastFrame);
  EXPECT_EQ(stats.work.probeTrace.rays.rays, stats.probesUpdatedLastFrame * settings.raysPerProbe);
  EXPECT_GE(stats.work.probeTrace.rays.reads, stats.work.probeTrace.rays.rays);  // each starts in the volume
  EXPECT_EQ(stats.work.probeTrace.seedVisibility.rays, 0u);
  EXPECT_GE(stats.work.probePlacement.probes, stats.probesUpdatedLastFrame);
  EXPECT_GE(stats.work.probePlacement.reads, stats.probesUpdatedLastFrame);

  // Frame 2 does not count: its passes leave the counters as frame 1 left them, and Stats reports none.
  const auto counters = [&] {
    return gpu::readBufferAs<uint32_t>(device(), gi::voxelSceneOf(*context_).workCounters());
  };
  const std::vector<uint32_t> countedByFrame1 = counters();
  countWork_ = false;
  runFrames(1);
  ASSERT_GT(context_->stats().probesUpdatedLastFrame, 0u);
  EXPECT_EQ(counters(), countedByFrame1) << "a pass counted its work on a frame that does not count";
  expectNoWorkCounted(context_->stats().work);

  const std::vector<shader::Probe> probes = readProbes();
  countWork_ = true;
  runFrames(1);
  stats = context_->stats();
  ASSERT_EQ(stats.probeLevelUpdatedLastFrame, 0u);
  const gi::ProbeVolume& volume = gi::probeVolumeOf(*context_);
  const std::vector<uint32_t> list = gpu::readBufferAs<uint32_t>(device(), volume.list());
  const uint32_t listed = list[3];
  ASSERT_EQ(listed, stats.probesUpdatedLastFrame);
  const glm::ivec3 origin = volume.levelOrigin(0, kCameraPosition);
  uint32_t seeds = 0;
  for (uint32_t i = 0; i < listed; ++i) {
    const glm::ivec3 probe = shader::probeWorldCoordinate(list[shader::kIndirectListHeaderWords + i], origin,
                                                          probeGrid());
    ASSERT_FALSE(wasTraced(probes[shader::probeSlotIndex(probe, probeGrid())])) << "a level-0 probe is not new";
    const glm::vec3 position = shader::probeWorldPosition(probe, spacing(0), 0u);
    const glm::vec3 fraction = glm::vec3(probe & 1) * 0.5f;
    for (int corner = 0; corner < shader::kProbeCellCorners; ++corner) {
      const shader::ProbeCellCorner around = shader::probeCellCorner(probe >> 1, fraction, corner);
      const shader::Probe& coarser = probes[probesPerLevel() + shader::probeSlotIndex(around.probe, probeGrid())];
      if (around.weight == 0.0f || !shader::probeIsUsable(coarser, around.probe)) continue;
      const glm::vec3 coarserPosition = shader::probeWorldPosition(around.probe, spacing(1), coarser.state);
      if (glm::distance(coarserPosition, position) > 0.5f * settings.voxelSize) ++seeds;
    }
  }
  ASSERT_GT(seeds, 0u);
  EXPECT_EQ(stats.work.probeTrace.seedVisibility.rays, seeds);
  EXPECT_GE(stats.work.probeTrace.seedVisibility.reads, seeds);
  EXPECT_EQ(stats.work.probeTrace.probes, listed);
  EXPECT_EQ(stats.work.probeTrace.rays.rays, listed * settings.raysPerProbe);
}

TEST_F(ProbeCache, voxelRelightCountsEveryRelitVoxelAViewHasSeenSinceTheLitFrameAndItsVisibilityRays) {
  // The relight test's two bricks: the top layer of one relit, of the other given all its light; and a third whose
  // voxels are relit but were lit by the camera's lit frame last (no extra view since), which VoxelRelight leaves to
  // it. The count must be the voxels of the first alone, as the voxels read back say: occupied, relit, seen by an
  // extra view since.
  create(probeTestSettings());
  constexpr uint64_t kTopLayer = 0xf000'f000'f000'f000ull;
  TestBrick relit{{0, -3, 4}, kTopLayer, glm::vec3(0.0f), {0.0f, 1.0f, 0.0f}};
  relit.albedo = glm::vec3(0.5f);
  relit.directRadiance = glm::vec3(0.5f);
  const TestBrick given{{2, -3, 4}, kTopLayer, glm::vec3(kSkyRadiance), {0.0f, 1.0f, 0.0f}};
  TestBrick litByTheCamera = relit;
  litByTheCamera.coordinate = {-2, -3, 4};
  writeScene({relit, given, litByTheCamera});
  // The third brick's voxels as the camera's lit frame leaves them: no extra view since.
  const gi::VoxelScene& scene = gi::voxelSceneOf(*context_);
  std::vector<shader::Voxel> voxels = gpu::readBufferAs<shader::Voxel>(device(), scene.voxels());
  for (uint32_t voxel = 0; voxel < shader::kVoxelsPerBrick; ++voxel)
    voxels[2 * shader::kVoxelsPerBrick + voxel].surfaceAndLastHit &= ~(3u << shader::kVoxelExtraViewsShift);
  gpu::uploadBuffer(device(), scene.voxels(), std::as_bytes(std::span(voxels)));
  runUpdates(1);  // probes around them
  countWork_ = true;
  runFrames(1);
  const Stats stats = context_->stats();

  uint32_t relightable = 0;
  for (const auto& [coordinate, voxel] : testing::readOccupiedVoxels(device(), *context_))
    if ((voxel.albedo & shader::kVoxelRelit) != 0u && shader::voxelExtraViewsSinceLitFrame(voxel) != 0u) ++relightable;
  EXPECT_EQ(relightable, 16u);
  EXPECT_EQ(stats.work.voxelRelight.voxels, relightable);
  // Each gathers from the 8 probes around it at one level (a coarser one where none is usable): at least one usable
  // probe traced (the heaviest alone where they agree, kGatherAgreement), at most 8 at each of 3 levels, every probe
  // in the volume and so read from.
  EXPECT_GE(stats.work.voxelRelight.visibility.rays, relightable);
  EXPECT_LE(stats.work.voxelRelight.visibility.rays, relightable * 8 * shader::kProbeLevels);
  EXPECT_GE(stats.work.voxelRelight.visibility.reads, stats.work.voxelRelight.visibility.rays);
  EXPECT_EQ(stats.work.finalGather.tiles, 0u);  // the frames show nothing
}

// ---------------------------------------------------------------------------------------------------------------------
// Stability (SPEC §4.5): the dark room, lit only through a 1×1 m skylight (the sun patch on its floor and the sky),
// rendered by the host renderer with GI: few of a probe's rays find the light, the case the talk's reservoirs are for.

// What the level-0 probes of the dark room do over a run of updates after warming up.
struct DarkRoomProbes {
  double variation = 0.0;      // mean over updates, probes and normals of |E_t − E_{t−1}|, over the mean E
  double meanIrradiance = 0.0;  // mean E over the same updates, probes and normals, W/m² (luminance)
  uint32_t probes = 0;         // probes measured
  uint64_t raysTraced = 0;     // by every level, over the whole run
};

// Level 0's probes inside the room (interior x, z ∈ [−4, 4] m, y ∈ [0, 4] m), usable at every measured update; E is
// the luminance of the SH irradiance along the six axes. The first `warmUpdates` updates of level 0 let the voxels
// (the lit frame's multi-bounce loop) and the probes' histories (m at its cap) converge; the next `measuredUpdates`
// are measured.
DarkRoomProbes measureDarkRoomProbes(bool reservoirs, uint32_t warmUpdates, uint32_t measuredUpdates) {
  const auto scene = renderer::makeBuiltinScene("dark-room");
  renderer::RendererSettings settings;
  settings.width = 96;
  settings.height = 64;
  // High tier's probes and rays, around the 8.5 m room: a 32×16×32 m voxel volume, 16×8×16 probes per level.
  Settings gi = settingsForTier(QualityTier::High);
  gi.volumeBricks = {32, 16, 32};
  gi.brickPoolCapacity = 4096;
  gi.probeGrid = {16, 8, 16};
  gi.probeReservoirs = reservoirs;
  settings.gi = gi;
  // The camera alone, and the sky as SH2: with the views beyond it the reservoirs' mean drifts from the plain
  // estimate's here (docs/QUALITY.md, "The views on by default"), and with the sky map the skylight's bright sky near
  // the sun sets off a shared recovery that the reservoirs' probes follow noisily ("The sky map and the reflective
  // shadow map on by default"). The reservoirs stay off by default until both are understood.
  settings.extraViews = {.sunViewSize = 0, .surroundViewSize = 0, .overheadViewSize = 0, .skyMap = false};
  renderer::Renderer renderer(testing::gpuTestDevice(), *scene, settings);
  const renderer::AnimatedState view = renderer::evaluateAnimation(*scene, scene->cameras[0], 0.0f);
  const gi::ProbeVolume& volume = gi::probeVolumeOf(*renderer.giContext());
  const glm::ivec3 dimensions(gi.probeGrid[0], gi.probeGrid[1], gi.probeGrid[2]);
  const glm::ivec3 origin = volume.levelOrigin(0, view.camera.position);

  DarkRoomProbes result;
  std::vector<std::vector<float>> irradiance;  // per measured update: per level-0 slot, E along the 6 axes
  std::vector<bool> usableThroughout(volume.probesPerLevel(), true);
  for (uint32_t updates = 0; updates < warmUpdates + measuredUpdates;) {
    renderer.render(view);
    const Stats stats = *renderer.giStats();
    result.raysTraced += uint64_t(stats.probesUpdatedLastFrame) * gi.raysPerProbe;
    if (stats.probeLevelUpdatedLastFrame != 0) continue;
    if (++updates <= warmUpdates) continue;
    const std::vector<shader::Probe> probes = gpu::readBufferAs<shader::Probe>(testing::gpuTestDevice(), volume.probes());
    std::vector<float>& values = irradiance.emplace_back(size_t(volume.probesPerLevel()) * 6, 0.0f);
    for (uint32_t slot = 0; slot < volume.probesPerLevel(); ++slot) {
      const glm::ivec3 coordinate = shader::probeWorldCoordinate(slot, origin, dimensions);
      const glm::vec3 position(coordinate);  // level 0: 1 m spacing
      const bool inRoom = glm::all(glm::greaterThanEqual(position, glm::vec3(-4.0f, 0.0f, -4.0f))) &&
                          glm::all(glm::lessThanEqual(position, glm::vec3(4.0f, 4.0f, 4.0f)));
      if (!inRoom || !shader::probeIsUsable(probes[slot], coordinate)) {
        usableThroughout[slot] = false;
        continue;
      }
      const shader::Sh2Rgb radiance = shader::probeRadianceSh(probes[slot]);
      for (int axis = 0; axis < 6; ++axis) {
        glm::vec3 normal(0.0f);
        normal[axis / 2] = axis % 2 ? 1.0f : -1.0f;
        values[slot * 6 + axis] =
            shader::probeSampleLuminance(glm::max(shader::sh2Irradiance(radiance, normal), glm::vec3(0.0f)));
      }
    }
  }
  double change = 0.0, sum = 0.0;
  uint64_t changes = 0, values = 0;
  for (uint32_t slot = 0; slot < volume.probesPerLevel(); ++slot) {
    if (!usableThroughout[slot]) continue;
    ++result.probes;
    for (uint32_t update = 0; update < measuredUpdates; ++update)
      for (int axis = 0; axis < 6; ++axis) {
        const float value = irradiance[update][slot * 6 + axis];
        sum += value;
        ++values;
        if (update == 0) continue;
        change += std::abs(value - irradiance[update - 1][slot * 6 + axis]);
        ++changes;
      }
  }
  result.meanIrradiance = values ? sum / double(values) : 0.0;
  result.variation = changes && sum > 0.0 ? (change / double(changes)) / result.meanIrradiance : 0.0;
  return result;
}

class ProbeStability : public testing::GpuTest {};

// SPEC §4.5's stability, as the issue asks: reservoirs on at least halve the probes' frame-to-frame variation in the
// dark room and keep their mean within 3 % (what it measures: docs/QUALITY.md, "Probe stability"). The whole run is
// deterministic on one driver; the margin is for another's rounding. 1.5 M rays.
TEST_F(ProbeStability, inTheDarkRoomReservoirsHalveTheFrameToFrameVariationOfProbeIrradianceAndKeepItsMean) {
  constexpr uint32_t kWarmUpdates = 40, kMeasuredUpdates = 16;
  const DarkRoomProbes off = measureDarkRoomProbes(false, kWarmUpdates, kMeasuredUpdates);
  const DarkRoomProbes on = measureDarkRoomProbes(true, kWarmUpdates, kMeasuredUpdates);
  std::printf("dark room, level-0 probes: variation |E_t - E_t-1| / mean E: reservoirs off %.4f (%u probes), on %.4f "
              "(%u probes), ratio %.2f; mean E off %.4f, on %.4f (%+.2f %%); rays traced %llu + %llu\n",
              off.variation, off.probes, on.variation, on.probes, off.variation / on.variation, off.meanIrradiance,
              on.meanIrradiance, 100.0 * (on.meanIrradiance / off.meanIrradiance - 1.0),
              static_cast<unsigned long long>(off.raysTraced), static_cast<unsigned long long>(on.raysTraced));
  RecordProperty("variationOff", std::to_string(off.variation));
  RecordProperty("variationOn", std::to_string(on.variation));
  RecordProperty("meanOff", std::to_string(off.meanIrradiance));
  RecordProperty("meanOn", std::to_string(on.meanIrradiance));
  ASSERT_GE(off.probes, 50u);
  ASSERT_GE(on.probes, 50u);
  ASSERT_GT(off.meanIrradiance, 0.0);
  EXPECT_GE(off.variation, 2.0 * on.variation);
  EXPECT_LT(std::abs(on.meanIrradiance / off.meanIrradiance - 1.0), 0.03);
}

TEST(ProbeCacheSettings, reservoirSettingsOutOfRangeAreRejectedWithTheFieldNamed) {
  const auto rejection = [](const Settings& settings) {
    auto result = Context::create(testing::gpuTestContextDesc(settings, 64));
    EXPECT_FALSE(result.ok());
    if (result.ok()) return std::string();
    EXPECT_EQ(result.error().status, Status::InvalidDescription);
    return result.error().message;
  };
  Settings settings = probeTestSettings();
  settings.probeReservoirs = true;
  settings.raysPerProbe = 8;  // one ray per stratum: no room for a candidate beside the reservoir's ray
  EXPECT_NE(rejection(settings).find("raysPerProbe"), std::string::npos);
  settings = probeTestSettings();
  settings.probeReservoirHistoryCap = 253;
  EXPECT_NE(rejection(settings).find("probeReservoirHistoryCap"), std::string::npos);
  settings.probeReservoirHistoryCap = 0;
  EXPECT_NE(rejection(settings).find("probeReservoirHistoryCap"), std::string::npos);
  settings = probeTestSettings();
  settings.probeSampleClamp = 0.5f;
  EXPECT_NE(rejection(settings).find("probeSampleClamp"), std::string::npos);
  // Without reservoirs 8 rays are fine.
  settings = probeTestSettings();
  settings.probeReservoirs = false;
  settings.raysPerProbe = 8;
  EXPECT_TRUE(Context::create(testing::gpuTestContextDesc(settings, 64)).ok());
}

TEST(ProbeCacheMemory, theHighTierProbeVolumeFitsItsShareOfTheMemoryBudget) {
  gpu::OwnedDevice& device = testing::gpuTestDevice();
  // Small frames and extra views: the Hi-Z pyramid grows with their resolution and counts with the screen-size
  // targets (the final gather's 10 MB of SPEC §5), not with the 30 MB of GI data.
  ContextDesc desc;
  desc.maxWidth = desc.maxHeight = desc.maxExtraViewSize = 64;
  desc.instance = device.instance();
  desc.physicalDevice = device.physicalDevice();
  desc.device = device.device();
  desc.settings = settingsForTier(QualityTier::High);
  desc.settings.probeReservoirs = true;  // the budget must hold with level 0's reservoirs
  auto context = Context::create(desc);
  ASSERT_TRUE(context.ok()) << context.error().message;
  const Stats stats = context.value()->stats();
  uint64_t probeBytes = 0, reservoirBytes = 0, changeBytes = 0;
  for (const auto& resource : stats.memory) {
    if (resource.name.rfind("ssvgi probe", 0) == 0) probeBytes += resource.bytes;
    if (resource.name == "ssvgi probe reservoirs") reservoirBytes = resource.bytes;
    if (resource.name == "ssvgi probe change statistics") changeBytes = resource.bytes;
  }
  std::printf("GI memory at high tier: %.2f MiB in all, probes %.2f MiB (reservoirs %.2f MiB)\n",
              double(stats.totalBytes) / 1048576.0, double(probeBytes) / 1048576.0,
              double(reservoirBytes) / 1048576.0);
  RecordProperty("totalBytes", std::to_string(stats.totalBytes));
  RecordProperty("probeBytes", std::to_string(probeBytes));
  // 3 levels × 48·24·48 probes × 48 bytes = 7.96 MB, level 0's 8 reservoirs of 4 bytes per probe = 1.77 MB, the
  // change statistics' 4 bytes per probe of every level = 0.66 MB, plus the list and the per-frame uploads.
  EXPECT_EQ(reservoirBytes, 48u * 24 * 48 * shader::kProbeStrata * 4);
  EXPECT_EQ(changeBytes, 3u * 48 * 24 * 48 * 4);
  EXPECT_GT(probeBytes, 10'377'000u);
  EXPECT_LE(probeBytes, 10'477'000u);
  // SPEC §5: all GI data ≤ 30 MB (the talk's table counts MB of 2^20 bytes) with the reservoirs; issue 16: ≤ 24 MB
  // with the defaults, which differ only by the reservoirs' buffer (4 bytes when they are off).
  EXPECT_LE(stats.totalBytes, 30u * 1024 * 1024);
  EXPECT_LE(stats.totalBytes - reservoirBytes + 4u, 24u * 1024 * 1024);
}

}  // namespace
}  // namespace ssvgi
