// The probe radiance cache (SPEC §4.5), first slice: the discretisation of the 1024-direction set on the CPU; then
// ProbePlacement and ProbeTrace through the public API on voxel scenes written straight into the context's voxel scene
// (the frames themselves inject nothing: their depth is empty and there is no lit frame), checked against analytic
// irradiance: a furnace, a closed box, a wall hiding half the sky, the history count and α, the budget, the memory.
#include "camera.h"
#include "gi/context_internals.h"
#include "gi/voxels/build_octree.h"
#include "gpu/resources.h"
#include "gpu_test_device.h"
#include "shared/probe_interface.h"
#include "ssvgi/ssvgi.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
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

TEST(ProbeDirections, aSlotRecognisesItsProbeAfterWrappingAndAStaleOneDoesNot) {
  const glm::ivec3 dimensions(16, 8, 16), origin(-21, -3, 5);
  for (uint32_t slot = 0; slot < uint32_t(dimensions.x * dimensions.y * dimensions.z); ++slot) {
    const glm::ivec3 probe = shader::probeWorldCoordinate(slot, origin, dimensions);
    ASSERT_TRUE(glm::all(glm::greaterThanEqual(probe, origin)) && glm::all(glm::lessThan(probe, origin + dimensions)));
    ASSERT_EQ(shader::probeSlotIndex(probe, dimensions), slot);
    ASSERT_NE(shader::probeCoordinateTag(probe), shader::probeCoordinateTag(probe + glm::ivec3(16, 0, 0)));
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// GPU: scenes of bricks under the probes.

constexpr uint32_t kFrameSize = 32;
// The camera looks along −Z at the scenes, which lie around kProbe: world (0, 0, 4) m, a probe of all three levels
// (coordinates (0, 0, 4), (0, 0, 2), (0, 0, 1)).
constexpr glm::vec3 kCameraPosition(2.5f, 0.5f, 10.5f);
constexpr glm::ivec3 kProbe(0, 0, 4);

Settings probeTestSettings() {
  Settings settings;
  settings.volumeBricks = {32, 16, 32};  // around the camera: bricks x −16..15, y −8..7, z −8..23
  settings.brickPoolCapacity = 1024;
  settings.probeGrid = {16, 8, 16};  // level 0 around the camera: probes x −6..9, y −4..3, z 2..17
  return settings;
}

// A brick of a test scene: every voxel of `mask` with the same radiance and normal.
struct TestBrick {
  glm::ivec3 coordinate;  // world brick coordinate
  uint64_t mask;
  glm::vec3 radiance;
  glm::vec3 normal;
};

constexpr uint64_t kFullBrick = ~uint64_t(0);

class ProbeCache : public testing::GpuTest {
 protected:
  void create(const Settings& settings) {
    settings_ = settings;
    ContextDesc desc;
    desc.instance = device().instance();
    desc.physicalDevice = device().physicalDevice();
    desc.device = device().device();
    desc.debugUtilsEnabled = true;
    desc.settings = settings;
    desc.maxWidth = desc.maxHeight = kFrameSize;
    auto result = Context::create(desc);
    ASSERT_TRUE(result.ok()) << result.error().message;
    context_ = std::move(result.value());

    // Nothing drawn (reversed-Z 0 is infinitely far): BrickAllocate finds no surface and the scene stays as written.
    depth_ = gpu::Image(device(), {"test depth", VK_FORMAT_R32_SFLOAT, kFrameSize, kFrameSize, 1, 1,
                                   VK_IMAGE_USAGE_SAMPLED_BIT});
    const std::vector<float> farAway(kFrameSize * kFrameSize, 0.0f);
    gpu::uploadImage(device(), depth_, std::as_bytes(std::span(farAway)));
    renderer::Camera camera;
    camera.position = kCameraPosition;
    camera.target = kCameraPosition - glm::vec3(0.0f, 0.0f, 1.0f);
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.verticalFov = glm::radians(90.0f);
    camera.nearPlane = 0.1f;
    const glm::mat4 viewProjection =
        renderer::reversedZInfiniteProjection(camera.verticalFov, 1.0f, camera.nearPlane) * renderer::viewMatrix(camera);
    std::copy(glm::value_ptr(viewProjection), glm::value_ptr(viewProjection) + 16, view_.viewProjection.begin());
    view_.position = {kCameraPosition.x, kCameraPosition.y, kCameraPosition.z};
    view_.width = view_.height = kFrameSize;
    runFrames(1);  // places the voxel volume and clears it
  }

  void runFrames(uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) {
      FrameDesc frame;
      frame.frameIndex = frameIndex_++;
      frame.camera = view_;
      frame.depth.view = depth_.view();
      frame.normal.view = depth_.view();  // nothing is drawn, so the gather never reads a normal
      frame.skyRadianceSh = uniformSkySh(kSkyRadiance);
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
      bricks.push_back({glm::ivec4(brick.coordinate, 1), glm::uvec4(uint32_t(brick.mask), uint32_t(brick.mask >> 32), 0, 0)});
      for (uint32_t voxel = 0; voxel < shader::kVoxelsPerBrick; ++voxel)
        voxelData.push_back({shader::packR11G11B10F(brick.radiance), shader::packOctahedralNormal(brick.normal)});
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
    EXPECT_EQ(probe.normalDotAndState.w, shader::probeCoordinateTag(coordinate)) << "level " << level;
    return probe;
  }

  std::unique_ptr<Context> context_;
  Settings settings_;
  gpu::Image depth_;
  View view_;
  uint32_t frameIndex_ = 0;
};

shader::Sh2Rgb radianceSh(const shader::Probe& probe) {
  return {shader::unpackSh2Half(glm::uvec2(probe.radianceRedGreen)),
          shader::unpackSh2Half(glm::uvec2(probe.radianceRedGreen.z, probe.radianceRedGreen.w)),
          shader::unpackSh2Half(glm::uvec2(probe.radianceBlueAndDistance))};
}
glm::vec4 distanceSh(const shader::Probe& probe) {
  return shader::unpackSh2Half(glm::uvec2(probe.radianceBlueAndDistance.z, probe.radianceBlueAndDistance.w));
}
glm::vec4 normalDotSh(const shader::Probe& probe) { return shader::unpackSh2Half(glm::uvec2(probe.normalDotAndState)); }
uint32_t historyCount(const shader::Probe& probe) { return shader::probeHistoryCount(probe.normalDotAndState.z); }
bool isActive(const shader::Probe& probe) {
  return shader::probePlacement(probe.normalDotAndState.z) == shader::kProbeStateActive;
}
// The Y coordinate of a probe from its tag's 10 bits (the scenes lie within ±512 probes of the world origin).
int tagY(uint32_t tag) {
  const int y = int((tag >> 10) & 0x3ffu);
  return y >= 512 ? y - 1024 : y;
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

TEST_F(ProbeCache, aProbeUnderAUniformSkyBesideAVoxelOfTheSameRadianceConvergesToPiTimesTheRadiance) {
  // Placement keeps only probes with a voxel within one spacing, so the sky test needs a voxel; it glows with the
  // sky's radiance and faces up, and the probes checked lie above it, so every ray — hit or miss — sees kSkyRadiance
  // (a furnace). After 32 updates each has traced all 1024 directions: E(n) = π·L to the CPU test's 1 %.
  create(probeTestSettings());
  const float brickTop = -2.0f;
  writeScene({{{0, -3, 4}, kFullBrick, glm::vec3(kSkyRadiance), {0.0f, 1.0f, 0.0f}}});
  runUpdates(32);
  const std::vector<shader::Probe> probes = readProbes();
  for (uint32_t level = 0; level < shader::kProbeLevels; ++level) {
    uint32_t checked = 0;
    for (uint32_t slot = 0; slot < probesPerLevel(); ++slot) {
      const shader::Probe& probe = probes[level * probesPerLevel() + slot];
      if (!isActive(probe)) continue;
      const int y = tagY(probe.normalDotAndState.w);
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

TEST_F(ProbeCache, aProbeInsideAClosedBoxOfBlackVoxelsSeesNoSky) {
  create(probeTestSettings());
  writeScene(closedBox(glm::vec3(0.0f)));
  runUpdates(2);
  const std::vector<shader::Probe> probes = readProbes();
  for (uint32_t level = 0; level < shader::kProbeLevels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    const shader::Probe probe = probeAt(probes, level, glm::vec3(kProbe));
    ASSERT_TRUE(isActive(probe));
    // Every ray hits a black wall: exactly zero. One sky ray leaking would add (4π/32)·Y00·L ≈ 0.11 to L00.
    const shader::Sh2Rgb radiance = radianceSh(probe);
    for (const glm::vec4& channel : {radiance.r, radiance.g, radiance.b})
      for (int i = 0; i < 4; ++i) EXPECT_EQ(channel[i], 0.0f);
    // The walls are 0.75 to 0.75·√3 m away, all seen from the front (their normals face the probe).
    EXPECT_GE(sphereMean(distanceSh(probe)), 0.75f);
    EXPECT_LE(sphereMean(distanceSh(probe)), 0.75f * std::sqrt(3.0f));
    EXPECT_GT(sphereMean(normalDotSh(probe)), 0.5f);
  }
}

TEST_F(ProbeCache, aProbeBesideALargeWallSeesHalfTheSky) {
  // A black voxel layer at x ∈ [−0.5, −0.25) m spanning the whole volume (y −8..8 m, z −8..24 m), facing +X, a
  // quarter metre from kProbe. The wall hides the −X half of the sky but for the strips past its edges: from 0.25 m
  // an 8 m half-width leaves about 1.4 % of the sphere, within the ±3 % allowed.
  create(probeTestSettings());
  std::vector<TestBrick> wall;
  for (int z = -8; z < 24; ++z)
    for (int y = -8; y < 8; ++y) wall.push_back({{-1, y, z}, 0x4444'4444'4444'4444ull, glm::vec3(0.0f), {1, 0, 0}});
  writeScene(wall);
  runUpdates(32);
  const std::vector<shader::Probe> probes = readProbes();
  for (uint32_t level = 0; level < shader::kProbeLevels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    const shader::Probe probe = probeAt(probes, level, glm::vec3(kProbe));
    ASSERT_TRUE(isActive(probe));
    const shader::Sh2Rgb radiance = radianceSh(probe);
    const float skyVisibility = sphereMean(radiance.g) / kSkyRadiance;
    EXPECT_NEAR(skyVisibility, 0.5f, 0.03f);
    // SH2 holds a half-space exactly: E = π·L facing away from the wall, 0 facing it (up to the edge strips).
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {1, 0, 0}), kPi * kSkyRadiance, 0.05f * kPi * kSkyRadiance);
    EXPECT_NEAR(shader::sh2Irradiance(radiance.g, {-1, 0, 0}), 0.0f, 0.05f * kPi * kSkyRadiance);
  }
}

TEST_F(ProbeCache, theHistoryCountGrowsByOnePerUpdateToItsCapAndAlphaIsOneOverCountPlusOne) {
  Settings settings = probeTestSettings();
  settings.probeHistoryCap = 4;
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
    EXPECT_EQ(shader::probeNextDirection(probe.normalDotAndState.z), update * 32 % 1024);
    EXPECT_NEAR(sphereMean(radianceSh(probe).r), wallA, 2e-3f * wallA);
  }
  // The walls change to B once m is at its cap: one update moves the probe by α = 1/(cap+1) of the step.
  writeScene(closedBox(glm::vec3(wallB)));
  runUpdates(1);
  const shader::Probe probe = probeAt(readProbes(), 0, glm::vec3(kProbe));
  const float expected = wallA + (wallB - wallA) / float(settings.probeHistoryCap + 1);
  EXPECT_NEAR(sphereMean(radianceSh(probe).r), expected, 2e-3f * expected);
  EXPECT_EQ(historyCount(probe), settings.probeHistoryCap);
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
  uint32_t active = 0;
  for (uint32_t slot = 0; slot < probesPerLevel(); ++slot) active += isActive(probes[slot]) ? 1u : 0u;
  EXPECT_EQ(active, 8u);
  for (int corner = 0; corner < 8; ++corner)
    EXPECT_TRUE(isActive(probeAt(probes, 0, glm::vec3(corner & 1, -3 + (corner >> 1 & 1), 4 + (corner >> 2)))));

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
  active = 0;
  for (uint32_t slot = 0; slot < probesPerLevel(); ++slot) active += isActive(probes[slot]) ? 1u : 0u;
  EXPECT_EQ(active, 5u);
}

TEST(ProbeCacheMemory, theHighTierProbeVolumeFitsItsShareOfTheMemoryBudget) {
  gpu::Device& device = testing::gpuTestDevice();
  // Small frames: the Hi-Z pyramid grows with the resolution and counts with the screen-size targets (the final
  // gather's 10 MB of SPEC §5), not with the 30 MB of GI data.
  ContextDesc desc;
  desc.maxWidth = desc.maxHeight = 64;
  desc.instance = device.instance();
  desc.physicalDevice = device.physicalDevice();
  desc.device = device.device();
  desc.settings = settingsForTier(QualityTier::High);
  auto context = Context::create(desc);
  ASSERT_TRUE(context.ok()) << context.error().message;
  const Stats stats = context.value()->stats();
  uint64_t probeBytes = 0;
  for (const auto& resource : stats.memory)
    if (resource.name.rfind("ssvgi probe", 0) == 0) probeBytes += resource.bytes;
  // 3 levels × 48·24·48 probes × 48 bytes = 7.96 MB, plus the list and the per-frame uploads.
  EXPECT_GT(probeBytes, 7'900'000u);
  EXPECT_LE(probeBytes, 8'500'000u);
  // SPEC §5: all GI data ≤ 30 MB (the talk's table counts MB of 2^20 bytes): voxel scene 21.6 + probes 7.6.
  EXPECT_LE(stats.totalBytes, 30u * 1024 * 1024);
}

}  // namespace
}  // namespace ssvgi
