// The scenario metrics of SPEC §7 that need no reference (bench/scenarios.h), held to their thresholds at a test size:
// leak ratio in two-rooms, flicker in dark-room, lag after a light switch in cornell, and the recovery after a camera
// cut (a teleport, a 180° turn). The figures at 640×360 are in docs/QUALITY.md.
#include "builtin_scenes.h"
#include "gpu_test_device.h"
#include "renderer.h"
#include "scenario_rendering.h"
#include "scenarios.h"
#include "shared/probe_interface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace ssvgi {
namespace {

// 16:9 like the scenario commands' 640×360, five times smaller: 18×32 gather tiles.
constexpr uint32_t kTestWidth = 128, kTestHeight = 72;

bench::ScenarioRendering testRendering(const renderer::Scene& scene) {
  return {kTestWidth, kTestHeight, renderer::giSettingsFor(QualityTier::High, scene)};
}

bench::ScenarioView builtinView(const std::string& name, const std::string& camera = {}) {
  bench::ScenarioView view{*renderer::makeBuiltinScene(name), {}};
  view.camera = view.scene.cameras.front();
  for (const renderer::Camera& candidate : view.scene.cameras)
    if (candidate.name == camera) view.camera = candidate;
  return view;
}

class Scenario : public testing::GpuTest {};

constexpr double kLeakBound = 0.02;  // issue 6: the leak ratio in two-rooms below 2 %

TEST_F(Scenario, twoRoomsLeaksUnderTwoPercentOfTheLitRoomsIndirectLightIntoTheDarkRoom) {
  const renderer::Scene twoRooms = *renderer::makeBuiltinScene("two-rooms");
  const bench::LeakResult leak = bench::measureLeak(device(), testRendering(twoRooms), twoRooms);
  EXPECT_GT(leak.litRoomIrradiance, 0.0);
  EXPECT_GT(leak.darkRoomPixels, uint64_t{kTestWidth * kTestHeight / 2}) << "the dark view looks at the dark room";
  EXPECT_LT(leak.leakRatio, kLeakBound) << "lit " << leak.litRoomIrradiance << " W/m², dark " << leak.darkRoomIrradiance;
}

TEST_F(Scenario, withTheDoorRemovedTheDarkRoomReceivesTheLitRoomsLight) {
  // The leak figure's control: the same views and frames, with a real light path through the doorway. The dark room
  // then gets more than twice the bound (docs/QUALITY.md, "What the scenario tests' bounds rest on"), so the bound
  // above is not met by a setup that measures nothing.
  renderer::Scene openDoor = *renderer::makeBuiltinScene("two-rooms");
  std::erase_if(openDoor.instances, [&](const renderer::Instance& instance) {
    return openDoor.materials[openDoor.meshes[instance.mesh].material].name == "door";
  });
  const bench::LeakResult open = bench::measureLeak(device(), testRendering(openDoor), openDoor);
  EXPECT_GT(open.leakRatio, 2.0 * kLeakBound) << "lit " << open.litRoomIrradiance << " W/m², dark " << open.darkRoomIrradiance;
}

// The room is lit only by a small sun patch, which few of a probe's rays meet. The bound's figures: docs/QUALITY.md,
// "The views on by default" and "The temporal filter follows the probes". At the test size the room has settled by
// frame 96 (still darkening by 0.095 % a frame at frame 64, 0.053 % at 96); the drift bound checks that premise, since
// a view still settling would have its settling measured as flicker.
TEST_F(Scenario, convergedDarkRoomChangesUnderOnePercentFromFrameToFrame) {
  const bench::ScenarioView view = builtinView("dark-room");
  const bench::FlickerResult flicker =
      bench::measureFlicker(device(), testRendering(view.scene), view, {.convergenceFrames = 96});
  EXPECT_EQ(flicker.pixels, uint64_t{kTestWidth * kTestHeight}) << "a closed room fills the view";
  EXPECT_LT(std::abs(flicker.driftPerFrame), 0.001) << "the view has not settled";
  EXPECT_LT(flicker.finalImageFlicker, 0.01) << "indirect alone: " << flicker.indirectFlicker;
}

TEST_F(Scenario, cornellLightSwitchedOnArrivesSoonerWhenManyProbesSeeTheChange) {
  // The ceiling light of the Cornell box switched on after 64 frames lit by the panel alone: the indirect light
  // triples. Change detection (SPEC §6.2) lets the probes near the light take the first bounce at once; a change that
  // a share of the probes see at once (Settings::probeSharedChangeShare) also has every probe follow the bounces after
  // it quickly, whose steps no probe can tell from its own noise. Progress is measured against the run with the light
  // on all along, converged (LagOptions::settledRunFrames). Issue 14's target is the bound at 24 frames: 90 % of the
  // way (measured 98 %; 72 % without the shared change). A recovering probe takes each update whole, so the light
  // overshoots its end state a little while the later bounces come round (1.08 at 48 frames, 1.11 at most when the
  // rule came, docs/QUALITY.md, "A recovery takes each update whole, turned at random"; 1.14 at 48 frames by
  // 2026-12-06, 1.151 since FinalGather's visibility test watches observed space, "A sealed room").
  const bench::ScenarioView view = builtinView("cornell");
  bench::LagOptions options;
  options.framesAfterSwitch = 48;
  const auto measure = [&](float sharedChangeShare) {
    bench::ScenarioRendering rendering = testRendering(view.scene);
    rendering.gi.probeSharedChangeShare = sharedChangeShare;
    const bench::LagResult lag = bench::measureLag(device(), rendering, view, options);
    EXPECT_GT(lag.irradianceAfter, 1.5 * lag.irradianceBefore);
    EXPECT_EQ(lag.progress.size(), options.framesAfterSwitch);
    for (const double progress : lag.progress) EXPECT_TRUE(std::isfinite(progress));
    if (!options.knownIrradianceAfter) {
      EXPECT_LT(std::abs(lag.steadyDrift), 0.02) << "the run with the light on all along has settled";
    }
    return lag;
  };
  const bench::LagResult shared = measure(settingsForTier(QualityTier::High).probeSharedChangeShare);
  // The run with the light on all along sees no change, so the setting leaves it as it was: measured once.
  options.knownIrradianceAfter = shared.irradianceAfter;
  const bench::LagResult alone = measure(0.0f);
  const auto progressAt = [](const bench::LagResult& lag, size_t frame) { return lag.progress[frame - 1]; };
  std::printf("lag: %.1f %% / %.1f %% of the way 24 / 48 frames after the switch with the shared change, "
              "%.1f %% / %.1f %% with each probe on its own\n",
              100.0 * progressAt(shared, 24), 100.0 * progressAt(shared, 48), 100.0 * progressAt(alone, 24),
              100.0 * progressAt(alone, 48));
  EXPECT_GT(progressAt(shared, 24), 0.9);
  EXPECT_GT(progressAt(shared, 48), 0.9);
  EXPECT_GT(progressAt(shared, 24), progressAt(alone, 24) + 0.05);
  EXPECT_LT(progressAt(shared, 48), 1.2) << "and does not overshoot far";
}

TEST_F(Scenario, theLightDoesNotDependOnWhereTheBricksLieInThePool) {
  // VoxelRelight relights one in voxelRelightPeriod of the bricks a frame. Which ones must follow from the bricks
  // themselves: their place in the pool is the order in which BrickAllocate's threads happened to run, and a slice of
  // the pool made the GI differ from run to run — in the dark room by 9 % two frames in (docs/QUALITY.md, "The same
  // frames, the same light"). A pool a third smaller moves a third of its bricks to another slice; the bricks'
  // coordinates stay. Twelve frames: every voxel relit four times, each probe level updated four times.
  const bench::ScenarioView view = builtinView("dark-room");
  const bench::ScenarioRendering large = testRendering(view.scene);
  bench::ScenarioRendering smaller = large;
  smaller.gi.brickPoolCapacity = large.gi.brickPoolCapacity * 2 / 3;
  std::vector<std::vector<double>> light;
  for (const bench::ScenarioRendering& rendering : {large, smaller}) {
    bench::ScenarioRenderer room(device(), view.scene, rendering);
    room.render(view.camera, 12);
    const Stats stats = *room.renderer().giStats();
    ASSERT_EQ(stats.bricksDroppedTotal, 0u) << "both pools hold the room";
    EXPECT_GT(stats.bricksLive, smaller.gi.brickPoolCapacity / 3) << "the bricks fill more than a slice";
    light.push_back(bench::luminance(room.renderer().indirectIrradiance()));
  }
  double largestDifference = 0.0, mean = 0.0;
  for (size_t pixel = 0; pixel < light[0].size(); ++pixel) {
    largestDifference = std::max(largestDifference, std::abs(light[0][pixel] - light[1][pixel]));
    mean += light[0][pixel] / double(light[0].size());
  }
  EXPECT_GT(mean, 0.0);
  EXPECT_EQ(largestDifference, 0.0) << "mean E_indirect luminance " << mean;
}

// A closed 8 m room whose floor, ceiling and walls are each one plane, on the voxel grid, emitting radiance Le and
// reflecting `albedo`; no sun, no sky. Every ray from inside meets Le plus what the walls reflect: the indirect
// irradiance is exactly π·Le / (1 − albedo) wherever the camera looks.
renderer::Scene emittingPlanesRoom(float halfSize, float radiance, float albedo = 0.0f) {
  renderer::Scene room;
  room.name = "emitting planes";
  room.materials.push_back({"emitter", glm::vec3(albedo), renderer::kNoTexture, glm::vec3(radiance)});
  renderer::Mesh planes{.name = "planes"};
  const float h = halfSize;
  // Each plane: its inward normal, and two axes across it whose cross product is that normal (counter-clockwise).
  for (const glm::vec3 normal : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
                                 glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)}) {
    const glm::vec3 u = std::abs(normal.y) > 0.5f ? glm::vec3(0, 0, normal.y) : glm::vec3(0, 1, 0);
    const glm::vec3 v = glm::cross(normal, u);
    const glm::vec3 centre = -normal * h;
    const auto first = uint32_t(planes.vertices.size());
    for (const glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
      planes.vertices.push_back({centre + h * (corner.x * u + corner.y * v), normal});
    for (const uint32_t index : {0u, 1u, 2u, 0u, 2u, 3u}) planes.indices.push_back(first + index);
  }
  room.meshes.push_back(std::move(planes));
  room.instances.push_back({0, glm::mat4(1.0f)});
  return room;
}

TEST_F(Scenario, aClosedRoomOfEmittingPlanesOnTheVoxelGridGetsPiTimesTheirRadianceEverywhere) {
  // The ceiling is above the camera's view: only the capture around the camera sees it from inside, and the sun's
  // view (given with the sun off too) sees its other face from above. A plane's two faces on a voxel boundary once
  // landed in the two voxels beside it, the outer face in front of the inner one: the probes met its back, black, and
  // E was 0.84 π·Le on average, 0.51 at worst (docs/QUALITY.md, "A plane's two faces"). At 160×90 from this camera, a
  // tile sampling the left wall's foot once found no probe every sixteenth frame, and its 0 darkened the pixels
  // around it to 0.43 (docs/QUALITY.md, "A tile without probes"): every pixel of every frame from the 48th is held.
  constexpr float kHalfSize = 4.0f, kRadiance = 1.0f;
  bench::ScenarioView view{emittingPlanesRoom(kHalfSize, kRadiance), {}};
  view.camera.position = {0.3f, -1.5f, 2.5f};
  view.camera.target = {0.3f, -1.5f, -4.0f};
  view.camera.verticalFov = 1.2f;
  view.scene.cameras.push_back(view.camera);
  bench::ScenarioRendering rendering = testRendering(view.scene);
  rendering.width = 160;
  rendering.height = 90;
  ASSERT_EQ(std::fmod(kHalfSize, rendering.gi.voxelSize), 0.0f) << "the planes lie on voxel boundaries";
  bench::ScenarioRenderer room(device(), view.scene, rendering);
  const double exact = shader::kPi * kRadiance;
  constexpr uint32_t kFrames = 96, kHeldFrom = 48;
  uint32_t frame = 0;
  double lowestOfFrames = exact;
  std::vector<double> irradiance;
  room.render(view.camera, kFrames, [&] {
    if (++frame < kHeldFrom) return;
    irradiance = bench::luminance(room.renderer().indirectIrradiance());
    lowestOfFrames = std::min(lowestOfFrames, *std::min_element(irradiance.begin(), irradiance.end()));
  });
  std::sort(irradiance.begin(), irradiance.end());
  double sum = 0.0;
  for (const double e : irradiance) sum += e;
  std::printf("E / (pi Le), last frame: mean %.4f, lowest %.4f, highest %.4f; lowest of frames %u-%u: %.4f\n",
              sum / double(irradiance.size()) / exact, irradiance.front() / exact, irradiance.back() / exact,
              kHeldFrom, kFrames, lowestOfFrames / exact);
  EXPECT_NEAR(sum / double(irradiance.size()), exact, 0.02 * exact);
  EXPECT_GT(lowestOfFrames, 0.9 * exact);
  EXPECT_LT(irradiance.back(), 1.03 * exact);
}

// The same room reflecting 80 %: E = 5 π·Le, four fifths of it light that has come round the voxel → probe → voxel
// loop, and a tenth of it after the tenth bounce. Each bounce waits for the probes' history, a window of about 32
// updates; a drift many probes share (shared/probe_interface.h) shortens the window while their updates keep leaning
// toward more light, and the light comes round sooner.
TEST_F(Scenario, aClosedReflectingRoomReachesItsManyBouncesSoonerWhenManyProbesShareTheDrift) {
  constexpr float kHalfSize = 4.0f, kRadiance = 1.0f, kAlbedo = 0.8f;
  bench::ScenarioView view{emittingPlanesRoom(kHalfSize, kRadiance, kAlbedo), {}};
  view.camera.position = {0.3f, -1.5f, 2.5f};
  view.camera.target = {0.3f, -1.5f, -4.0f};
  view.camera.verticalFov = 1.2f;
  view.scene.cameras.push_back(view.camera);
  const double exact = shader::kPi * kRadiance / (1.0 - kAlbedo);
  constexpr uint32_t kFrames = 144;
  std::vector<double> reached;
  for (const float sharedChangeShare : {0.125f, 0.0f}) {
    bench::ScenarioRendering rendering = testRendering(view.scene);
    rendering.gi.probeSharedChangeShare = sharedChangeShare;
    bench::ScenarioRenderer room(device(), view.scene, rendering);
    room.render(view.camera, kFrames);
    const std::vector<double> irradiance = bench::luminance(room.renderer().indirectIrradiance());
    double sum = 0.0;
    for (const double e : irradiance) sum += e;
    reached.push_back(sum / double(irradiance.size()) / exact);
  }
  std::printf("E / (pi Le / (1 - albedo)) after %u frames: %.4f with the shared drift, %.4f without\n", kFrames,
              reached[0], reached[1]);
  // Measured 0.944 and 0.610 (docs/QUALITY.md, "A drift many probes share"): the bounds hold a third of that gap
  // and the light within a tenth of the exact value, not past it.
  EXPECT_GT(reached[0], reached[1] + 0.1);
  EXPECT_GT(reached[0], 0.9);
  EXPECT_LT(reached[0], 1.02);
}

TEST_F(Scenario, aStillRoomStartsNoSharedRecovery) {
  // The premise of the shared change (Settings::probeSharedChangeShare): in a still scene a change cuts the history of
  // only a probe in a hundred or so by chance, far below the share that starts a recovery in every probe (which
  // would make a still scene flicker). The dark room: a small sun patch that few of a probe's rays meet, the noisiest
  // of the still scenes. Its largest share was 2.1 % (docs/QUALITY.md, "A change many probes see at once").
  const bench::ScenarioView view = builtinView("dark-room");
  const bench::ScenarioRendering rendering = testRendering(view.scene);
  bench::ScenarioRenderer room(device(), view.scene, rendering);
  double largestShare = 0.0;
  uint32_t recoveries = 0, talliedFrames = 0;
  room.render(view.camera, 96, [&] {
    const Stats stats = *room.renderer().giStats();
    recoveries += stats.sharedChangeRecovery ? 1u : 0u;
    if (stats.probesWatchedForChange < shader::kProbeSharedChangeMinimumProbes) return;
    ++talliedFrames;
    largestShare = std::max(largestShare, double(stats.probesCutByChange) / stats.probesWatchedForChange);
  });
  std::printf("largest share of probes cut by a change in a frame: %.1f %%\n", 100.0 * largestShare);
  EXPECT_GT(talliedFrames, 48u) << "the probes have a history to tell a change by";
  EXPECT_EQ(recoveries, 0u);
  EXPECT_LT(largestShare, 0.5 * rendering.gi.probeSharedChangeShare);
}

TEST_F(Scenario, cornellLightSwitchedOffFadesWithChangeDetection) {
  // The same light switched off after 96 frames on: the indirect light falls to about a third. Change detection lets
  // the probes drop the light's bounces within a few updates instead of 1/33 of them per update; 80 % of the way 48
  // frames after the switch lies between the progress with it and without it (docs/QUALITY.md, "What the scenario
  // tests' bounds rest on"), and issue 14's target, 90 % of the way 24 frames after it, is the other bound (measured
  // 95 %). 96 frames, because the run with the light off all along, against which the progress is
  // measured, is still losing the light of its first frames after 112 (docs/QUALITY.md, "Air the views saw only
  // askew").
  const bench::ScenarioView view = builtinView("cornell");
  bench::LagOptions options;
  options.switchOff = true;
  options.convergenceFrames = 96;
  options.framesAfterSwitch = 48;
  const bench::LagResult lag = bench::measureLag(device(), testRendering(view.scene), view, options);
  EXPECT_LT(lag.irradianceAfter, 0.5 * lag.irradianceBefore);
  ASSERT_EQ(lag.progress.size(), options.framesAfterSwitch);
  for (const double progress : lag.progress) EXPECT_TRUE(std::isfinite(progress));
  EXPECT_LT(std::abs(lag.steadyDrift), 0.02) << "the run with the light off all along has settled";
  std::printf("switch-off: %.0f %% / %.0f %% of the way after 24 / %u frames\n", 100.0 * lag.progress[23],
              100.0 * lag.progress.back(), options.framesAfterSwitch);
  EXPECT_GT(lag.progress[23], 0.9) << "issue 14's target";
  EXPECT_GT(lag.progress.back(), 0.8);
  EXPECT_LT(lag.progress.back(), 1.05) << "and does not overshoot";
}

// Look away (SPEC §6.1): cornell's ceiling light is switched off while the camera looks out of the box for 16 frames;
// back at the view, its bounce light must go from the voxels and probes. It goes as light switched off goes, at the
// probes' pace: issue 14's 10 % within 24 frames is not reached (docs/QUALITY.md, "What the scenario tests' bounds
// rest on"). Half of the difference before looking away is the bound: light kept for good in voxels nobody relights
// would stay near it.
TEST_F(Scenario, cornellLightSwitchedOffWhileTheCameraLooksAwayFadesOnceItLooksBack) {
  const bench::ScenarioView view = builtinView("cornell");
  const bench::LookAwayResult lookAway = bench::measureLookAway(device(), testRendering(view.scene), view);
  ASSERT_FALSE(lookAway.differenceFromNeverOn.empty());
  EXPECT_GT(lookAway.differenceWithTheLightOn, 1.0) << "the light is most of the indirect light";
  for (const double difference : lookAway.differenceFromNeverOn) EXPECT_TRUE(std::isfinite(difference));
  EXPECT_LT(lookAway.differenceFromNeverOn.back(), 0.5 * lookAway.differenceWithTheLightOn);
}

// Recovered, as `ssvgi scenario cut` reports it: E_indirect within 10 % (relative mean absolute difference) of a run
// that sat at the new view all along.
constexpr double kRecoveryTolerance = 0.1;
// The cut changes the GI: on its frame E_indirect is at least this many times as far from that run as 32 frames
// later, so that there is a recovery to measure (QUALITY.md, "What an unobserved voxel stands for"). Not an absolute
// figure: what the first frame after a cut already knows of the new view is the better the less there is to recover.
constexpr double kCutChangeOverRecovered = 2.0;
// Recovered: after 32 frames, no further from the path-traced reference of the new view than that run, within 2 points
// of relative MAE (both runs averaged over their last 8 frames, the reference at 512 samples per pixel). Not "equal to
// that run": the run after the cut keeps the voxels and the observed space of the old view, and where they are still
// of use it stays apart from the other for good, nearer the reference (docs/QUALITY.md, "The views on by default").
constexpr double kReferenceTolerance = 0.02;

struct CameraCut {
  const char* name;
  renderer::Camera to;  // from the courtyard's "court" camera at (−15, 1.7, 0) looking east
};

class ScenarioCameraCut : public testing::GpuTest, public ::testing::WithParamInterface<CameraCut> {};

TEST_P(ScenarioCameraCut, staysFiniteAndWithin32FramesIsNoFurtherFromTheReferenceThanARunThatSatThere) {
  const bench::ScenarioView view = builtinView("courtyard", "court");
  bench::CameraCutOptions options;
  options.to = GetParam().to;
  options.to.verticalFov = view.camera.verticalFov;
  options.recoveryTolerance = kRecoveryTolerance;
  options.referenceSamples = 512;
  const bench::CameraCutResult cut = bench::measureCameraCut(device(), testRendering(view.scene), view, options);
  std::printf("%s: %s\n", GetParam().name, bench::toJson(cut).dump().c_str());
  EXPECT_TRUE(cut.allFinite);
  ASSERT_EQ(cut.differenceFromSettled.size(), options.framesAfter);
  EXPECT_GT(cut.differenceFromSettled.front(), kCutChangeOverRecovered * cut.differenceFromSettled.back())
      << "the cut changes the GI: there is a recovery";
  ASSERT_TRUE(cut.errorAfterCut && cut.errorSettled);
  EXPECT_LT(*cut.errorAfterCut, *cut.errorSettled + kReferenceTolerance)
      << "last difference from the run that sat there " << cut.differenceFromSettled.back();
}

INSTANTIATE_TEST_SUITE_P(
    Courtyard, ScenarioCameraCut,
    ::testing::Values(
        // 45 m up and across to a view of the whole building from outside: the clipmaps scroll by most of their size.
        CameraCut{"teleport", {.position = {0.0f, 30.0f, 35.0f}, .target = {0.0f, 3.0f, 0.0f}}},
        // On the spot, looking west instead of east: the history reprojects behind the camera.
        CameraCut{"halfTurn", {.position = {-15.0f, 1.7f, 0.0f}, .target = {-40.0f, 3.0f, 0.0f}}}),
    [](const ::testing::TestParamInfo<CameraCut>& cut) { return std::string(cut.param.name); });

}  // namespace
}  // namespace ssvgi
