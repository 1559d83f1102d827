// The GI against the path-traced reference (SPEC §7): the reference's point-radiance kernel against analytic radiance
// first (a furnace, a half sky), then the Cornell box (E_indirect within 20 % of the reference's and the probes'
// irradiance within 15 % of the reference's at the same points, after convergence), then the scenes lit from off
// screen (SPEC §6.3): the gallery facing a sunlit wall behind the camera and the hall lit through its roof.
#include "builtin_scenes.h"
#include "gpu_test_device.h"
#include "path_tracer.h"
#include "point_radiance.h"
#include "renderer.h"
#include "reference_scenarios.h"
#include "scene_geometry.h"

#include <glm/gtc/constants.hpp>

#include <array>
#include <cstdio>
#include <vector>

namespace ssvgi {
namespace {

using renderer::Scene;
using shader::kPi;

constexpr float kBand0 = shader::kSh2Band0Basis;
constexpr float kBand1 = shader::kSh2Band1Basis;

Scene sceneOf(const char* name, const renderer::Material& material, renderer::MeshBuilder builder) {
  Scene scene;
  scene.name = name;
  scene.materials.push_back(material);
  scene.meshes.push_back(std::move(builder).build(name, 0));
  scene.instances.push_back({0, glm::mat4(1.0f)});
  scene.cameras.push_back({});
  return scene;
}

renderer::AnimatedState stillState(const Scene& scene) {
  return renderer::evaluateAnimation(scene, scene.cameras[0], 0.0f);
}

std::vector<glm::vec4> channels(const shader::Sh2Rgb& radiance) { return {radiance.r, radiance.g, radiance.b}; }

class PointRadiance : public testing::GpuTest {};

TEST_F(PointRadiance, insideAClosedEmissiveSphereEveryDirectionBringsTheSameRadiance) {
  // A closed sphere of albedo a emitting Le on its inside, with light reflected at most twice: every path is the same
  // (no roulette before the 4th vertex), so every direction brings exactly Le(1 + a + a²), wherever the point is.
  // Band 0 is then 4π·Y00·L and band 1 vanishes exactly, because the directions come in opposite pairs whose band-1
  // terms cancel: nothing here is random, 1e-4 only allows for float rounding. Sampling the emitters (a random point
  // on a random triangle) would make every path differ: the paths alone are the estimator with no noise here.
  const float albedo = 0.5f;
  const glm::vec3 emission(1.0f, 0.5f, 0.25f);
  renderer::MeshBuilder sphere;
  sphere.addSphere(glm::vec3(0.0f), 1.0f, 12, 24);
  const Scene scene = sceneOf("furnace", {"furnace", glm::vec3(albedo), renderer::kNoTexture, emission}, std::move(sphere));
  const std::vector<glm::vec3> points{{0.0f, 0.0f, 0.0f}, {0.5f, -0.3f, 0.2f}, {-0.2f, 0.6f, -0.4f}};
  reference::PointRadianceTracer tracer(device(), scene, stillState(scene), points,
                                       {.maxBounces = 2, .sampleEmitters = false});
  tracer.trace(1024);
  EXPECT_EQ(tracer.directionsPerPoint(), 1024u);
  const std::vector<shader::Sh2Rgb> radiance = tracer.radiance();
  ASSERT_EQ(radiance.size(), points.size());
  const glm::vec3 expected = emission * (1.0f + albedo + albedo * albedo);
  for (size_t point = 0; point < points.size(); ++point) {
    const std::vector<glm::vec4> sh = channels(radiance[point]);
    for (int c = 0; c < 3; ++c) {
      const float band0 = 4.0f * kPi * kBand0 * expected[c];
      EXPECT_NEAR(sh[c].x, band0, 1e-4f * band0) << "point " << point << " channel " << c;
      for (int m = 1; m < 4; ++m) EXPECT_NEAR(sh[c][m], 0.0f, 1e-4f * band0) << "point " << point << " channel " << c;
    }
    // SPEC §2's check: constant radiance L gives E = π·L for every normal.
    for (const glm::vec3 normal : {glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::normalize(glm::vec3(1, 1, -1))}) {
      const glm::vec3 irradiance = shader::sh2Irradiance(radiance[point], normal);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(irradiance[c], kPi * expected[c], 1e-4f * kPi * expected[c]);
    }
  }
}

// A black 200 m slab under a uniform sky, and points 1 cm above it.
Scene blackFloorUnderUniformSky(glm::vec3 sky) {
  renderer::MeshBuilder slab;
  slab.addBox(glm::vec3(-100.0f, -0.1f, -100.0f), glm::vec3(100.0f, 0.0f, 100.0f));
  Scene scene = sceneOf("black floor", {"black", glm::vec3(0.0f)}, std::move(slab));
  scene.sky = {renderer::SkyKind::Uniform, sky, 1.0f};
  return scene;
}
const std::vector<glm::vec3> kPointsAboveTheFloor{{0.0f, 0.01f, 0.0f}, {-5.0f, 0.01f, 3.0f}, {7.0f, 0.01f, -2.0f}};

TEST_F(PointRadiance, aboveABlackFloorUnderAUniformSkyTheUpperHalfHoldsTheSky) {
  // Points 1 cm above a black 200 m slab under a uniform sky L: the upper hemisphere brings L, the lower nothing (the
  // slab's edge, 100 m away, hides all but 1e-4 rad below the horizon). Analytically L00 = 2π·Y00·L, the y coefficient
  // L1,-1 = π·0.488603·L and the x and z ones 0 (SPEC §2's order: constant, y, z, x); E(up) = π·L, E(down) = 0,
  // E(sideways) = π·L/2. Band 0 is exact but for the pairs that both pass over the slab's edge (1.6 of 16384 pairs
  // expected; 1e-3 allows 16). Band 1 is random:
  // with N directions, the y coefficient has a standard deviation of 1.77·L/√(2N) and x, z 3.54·L/√(2N), i.e. E(up)
  // and E(down) 0.23 % and E(sideways) 0.45 % of π·L at N = 32768. The tolerances are 5 σ.
  const glm::vec3 sky(1.0f, 0.5f, 0.25f);
  const Scene scene = blackFloorUnderUniformSky(sky);
  const std::vector<glm::vec3>& points = kPointsAboveTheFloor;
  reference::PointRadianceTracer tracer(device(), scene, stillState(scene), points);
  tracer.trace(32768);
  const std::vector<shader::Sh2Rgb> radiance = tracer.radiance();
  for (size_t point = 0; point < points.size(); ++point) {
    const std::vector<glm::vec4> sh = channels(radiance[point]);
    const glm::vec3 up = shader::sh2Irradiance(radiance[point], {0, 1, 0});
    const glm::vec3 down = shader::sh2Irradiance(radiance[point], {0, -1, 0});
    for (int c = 0; c < 3; ++c) {
      const float band0 = 2.0f * kPi * kBand0 * sky[c];
      EXPECT_NEAR(sh[c].x, band0, 1e-3f * band0) << "point " << point << " channel " << c;
      EXPECT_NEAR(sh[c].y, kPi * kBand1 * sky[c], 0.035f * sky[c]) << "point " << point << " channel " << c;
      EXPECT_NEAR(up[c], kPi * sky[c], 0.012f * kPi * sky[c]) << "point " << point << " channel " << c;
      EXPECT_NEAR(down[c], 0.0f, 0.012f * kPi * sky[c]) << "point " << point << " channel " << c;
      for (const glm::vec3 sideways : {glm::vec3(1, 0, 0), glm::vec3(0, 0, -1)})
        EXPECT_NEAR(shader::sh2Irradiance(radiance[point], sideways)[c], 0.5f * kPi * sky[c], 0.023f * kPi * sky[c])
            << "point " << point << " channel " << c;
    }
  }
}

TEST_F(PointRadiance, aboveABlackFloorUnderAUniformSkyTheIrradianceItselfIsPiLUpHalfOfItSidewaysAndNoneDown) {
  // The exact E(n) the tracer sums beside the SH2, which holds E only to its first band (here exactly: a hemisphere of
  // sky is band 0 and 1 alone for irradiance, so the two agree; elsewhere they need not). Each antithetic pair has
  // one direction above the floor, u: E(up) sums L·|u_y|, whose relative standard deviation is 0.577/√P over P pairs,
  // and E(sideways) sums L·max(u_x, 0), 1.29/√P; E(down) is 0 but for the pairs over the slab's edge (as above).
  // With P = 65536 pairs: 0.23 % and 0.50 %; the tolerances are 5 σ.
  const glm::vec3 sky(1.0f, 0.5f, 0.25f);
  const Scene scene = blackFloorUnderUniformSky(sky);
  reference::PointRadianceTracer tracer(device(), scene, stillState(scene), kPointsAboveTheFloor);
  tracer.trace(131072);
  const std::vector<shader::PointRadianceSums> points = tracer.measurements();
  ASSERT_EQ(points.size(), kPointsAboveTheFloor.size());
  for (size_t point = 0; point < points.size(); ++point) {
    for (uint32_t axis = 0; axis < shader::kPointAxisNormals; ++axis) {
      const glm::vec3 normal = shader::pointAxisNormal(axis);
      const float share = normal.y > 0.0f ? 1.0f : (normal.y < 0.0f ? 0.0f : 0.5f);
      const float tolerance = normal.y > 0.0f ? 0.0115f : (normal.y < 0.0f ? 1e-3f : 0.025f);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(points[point].axisIrradiance[axis][c], share * kPi * sky[c], tolerance * kPi * sky[c])
            << "point " << point << " normal " << axis << " channel " << c;
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// The Cornell box against the reference, at a test size: the view `ssvgi scenario` measures at 640×360, at a quarter of
// its width and height (160×90: 40×22 blocks of 4×4 pixels), the GI at the high tier with the scene's detail scale and
// the light's views, as `ssvgi render` and `ssvgi scenario` run it.

bench::ScenarioView builtinView(const char* name) {
  bench::ScenarioView view{*renderer::makeBuiltinScene(name), {}};
  view.camera = view.scene.cameras.at(0);
  return view;
}

bench::ScenarioView cornell() { return builtinView("cornell"); }

bench::ScenarioRendering testRendering(const bench::ScenarioView& view) {
  return {160, 90, renderer::giSettingsFor(QualityTier::High, view.scene)};
}

class ReferenceScenario : public testing::GpuTest {};

// Cornell's detail scale: 0.125 m voxels, 0.5 m probes, the view converged once for both figures. What they have been
// and where their error lies: QUALITY.md ("GI quality", "Where the Cornell error comes from", "What the scenario
// tests' bounds rest on").
TEST_F(ReferenceScenario, cornellIndirectIrradianceIsWithinTwentyAndItsProbesWithinFifteenPercentOfTheReference) {
  const bench::ScenarioView view = cornell();
  bench::ConvergedView converged(device(), testRendering(view), view);
  EXPECT_TRUE(converged.convergence().converged);

  // 512 samples per pixel: a per-pixel noise of ~20 % (docs/QUALITY.md: 14 % at 1024), ~5 % after the 4×4 blocks,
  // small against the 20 % bound; the measurement reports it (referenceNoiseFloor) and the test requires it below 8 %.
  bench::IndirectErrorOptions options;
  options.referenceSamples = 512;
  const bench::IndirectErrorResult image = bench::measureIndirectError(device(), converged, options);
  std::printf("%s\n", bench::toJson(image).dump().c_str());
  EXPECT_LT(image.referenceNoiseFloor, 0.08);
  EXPECT_LT(image.comparison.relativeMeanAbsoluteError, 0.2);

  // The probes at least a voxel from every surface, 65536 directions each: the reference's noise floor is ~1 % (the
  // small, bright ceiling panel makes it noisy).
  const bench::ProbeIrradianceResult probes = bench::measureProbeIrradiance(device(), converged);
  nlohmann::json summary = bench::toJson(probes);
  summary.erase("probes");
  std::printf("%s\n", summary.dump().c_str());
  EXPECT_GE(probes.probes.size(), 4u);
  EXPECT_LT(probes.referenceNoiseFloor, 0.03);
  EXPECT_LT(probes.relativeMeanAbsoluteError, 0.15);
}

// ---------------------------------------------------------------------------------------------------------------------
// What lights the view is not on screen (SPEC §6.3, §7): the two built-in scenes whose light comes from surfaces the
// camera never sees, against the reference from a camera that stays still from the first frame, at 160×90 with the
// renderer's views beyond the camera (the sun's 256 px, the capture's 64 px, the overhead view's 256 px) and the
// probes' rays taking the sky only through space those views observed (SPEC §6.4), as it runs by default.

bench::IndirectErrorResult convergedIndirectError(gpu::OwnedDevice& device, const bench::ScenarioView& view,
                                                  const bench::ScenarioRendering& rendering, const char* scene) {
  bench::IndirectErrorOptions options;
  options.referenceSamples = 256;
  options.convergence.windowFrames = 32;
  const bench::IndirectErrorResult result = bench::measureIndirectError(device, rendering, view, options);
  std::printf("%s: %s\n", scene, bench::toJson(result).dump().c_str());
  return result;
}

// The bound for these scenes at the tests' size: relative MAE within 25 %, the mean within 0.8–1.25 of the
// reference's, converged, and the reference's own noise well below the bound.
void expectWithinTwentyFivePercent(const bench::IndirectErrorResult& result) {
  EXPECT_TRUE(result.convergence.converged);
  EXPECT_LT(result.referenceNoiseFloor, 0.08);
  EXPECT_LT(result.comparison.relativeMeanAbsoluteError, 0.25);
  EXPECT_GT(result.comparison.meanRatio, 0.8);
  EXPECT_LT(result.comparison.meanRatio, 1.25);
}

// Without the sun's view there is no indirect light in the view at all; the figures with it in QUALITY.md ("Views
// beyond the camera", "Unknown is not sky", "Where the views' scenes lose light").
TEST_F(ReferenceScenario, theGalleryLitByASunlitWallBehindTheCameraIsWithinTwentyFivePercentOfTheReference) {
  const bench::ScenarioView view = builtinView("gallery");
  expectWithinTwentyFivePercent(convergedIndirectError(device(), view, testRendering(view), "gallery"));
}

// Its light comes through the roof's openings: a probe ray that leaves through one finds the sky only once the
// overhead view has observed the space beyond the sun's view (QUALITY.md, "The sky beyond the sun's view").
TEST_F(ReferenceScenario, theHallLitThroughItsRoofIsWithinTwentyFivePercentOfTheReference) {
  const bench::ScenarioView view = builtinView("hall");
  expectWithinTwentyFivePercent(convergedIndirectError(device(), view, testRendering(view), "hall"));
}

// The courtyard from its camera 30 m up, looking down at the court: a voxel volume centred on the camera (48 m tall)
// ended 4 m above the ground, which got no voxels and no probes (33.8 %, ratio 0.67 at 160×90); the volume now stands
// where it holds what the camera sees (QUALITY.md, "The volume stands where the camera looks").
TEST_F(ReferenceScenario, theCourtyardSeenFromHighAboveIsWithinTwentyFivePercentOfTheReference) {
  bench::ScenarioView view = builtinView("courtyard");
  view.camera = view.scene.cameras.at(2);
  ASSERT_EQ(view.camera.name, "above");
  expectWithinTwentyFivePercent(convergedIndirectError(device(), view, testRendering(view), "courtyard from above"));
}

// A 6 × 3 m fence cut out by its texture in a checker of 0.75 m squares (glTF's MASK: the foliage, fences and grilles
// of scenes made elsewhere), sunlit, on a 10 × 10 m grey floor, without a sky: the floor in front of the fence gets the
// fence's light through the GI, and less of it than from a whole fence.
bench::ScenarioView sunlitFence() {
  bench::ScenarioView view{};
  Scene& scene = view.scene;
  scene.name = "sunlit fence";
  constexpr uint32_t kTexelsPerSquare = 4, kSquaresAcross = 8, kSquaresUp = 4;
  renderer::Texture checker{"checker", kSquaresAcross * kTexelsPerSquare, kSquaresUp * kTexelsPerSquare, {}};
  for (uint32_t y = 0; y < checker.height; ++y)
    for (uint32_t x = 0; x < checker.width; ++x) {
      const bool solid = (x / kTexelsPerSquare + y / kTexelsPerSquare) % 2 == 0;
      checker.rgba.insert(checker.rgba.end(), {180, 140, 90, static_cast<uint8_t>(solid ? 255 : 0)});
    }
  scene.textures.push_back(checker);
  scene.materials.push_back({"floor", glm::vec3(0.8f)});
  scene.materials.push_back({"fence", glm::vec3(1.0f), 0});
  scene.materials[1].alphaCutoff = 0.5f;
  const auto quad = [](const char* name, std::array<glm::vec3, 4> corners, glm::vec3 normal, uint32_t material) {
    // Corners counter-clockwise seen from the side the normal points to; uv spans the texture once.
    renderer::Mesh mesh{name, {}, {0, 1, 2, 0, 2, 3}, material};
    const std::array<glm::vec2, 4> uv{glm::vec2(0, 1), glm::vec2(1, 1), glm::vec2(1, 0), glm::vec2(0, 0)};
    for (size_t i = 0; i < 4; ++i) mesh.vertices.push_back({corners[i], normal, uv[i]});
    return mesh;
  };
  scene.meshes.push_back(quad("floor", {glm::vec3(-5, 0, 5), glm::vec3(5, 0, 5), glm::vec3(5, 0, -5), {-5, 0, -5}},
                              {0, 1, 0}, 0));
  scene.meshes.push_back(quad("fence", {glm::vec3(-3, 0, 0), glm::vec3(3, 0, 0), glm::vec3(3, 3, 0), {-3, 3, 0}},
                              {0, 0, 1}, 1));
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}};
  scene.sun.enabled = true;
  scene.sun.direction = renderer::sunDirection(41.0f, 48.0f);  // in front of the fence, to its right, high
  scene.sun.illuminance = glm::vec3(5.0f);
  scene.cameras.push_back({"front", glm::vec3(0.0f, 2.0f, 7.0f), glm::vec3(0.0f, 2.0f, 6.0f)});
  scene.cameras[0].verticalFov = 1.0f;
  view.camera = scene.cameras[0];
  return view;
}

// Frame after frame of a still view, from the 64th to the 160th, every 16th. The air at the corners of the holes that
// no view observed once ended the probes' rays there, standing for the mean light of the probes' surfaces — the sunlit
// floor's — while the views observed it bit by bit: the floor's light swung with it, out of these bounds on some of
// these frames (QUALITY.md, "What an unobserved voxel stands for").
TEST_F(ReferenceScenario, aSunlitFenceCutOutInSquaresStaysWithinTwentyFivePercentOfTheReferenceFrameAfterFrame) {
  const bench::ScenarioView view = sunlitFence();
  const bench::ScenarioRendering rendering = testRendering(view);
  reference::PathTracerSettings tracerSettings;
  tracerSettings.width = rendering.width;
  tracerSettings.height = rendering.height;
  reference::PathTracer tracer(device(), view.scene, stillState(view.scene), tracerSettings);
  tracer.trace(256);  // its noise, 2.5 % of the mean after the 4×4 blocks, is small against the bound
  const renderer::FloatImage referenceIndirect = tracer.indirectIrradiance();

  bench::ScenarioRenderer gi(device(), view.scene, rendering);
  gi.render(view.camera, 48);
  for (uint32_t frame = 64; frame <= 160; frame += 16) {
    gi.render(view.camera, 16);
    const reference::PixelMask mask = reference::maskFromDepth(gi.renderer().viewDistance());
    const reference::ImageComparison comparison =
        reference::compareImages(gi.renderer().indirectIrradiance(), referenceIndirect, &mask, 4);
    std::printf("sunlit fence, frame %u: relative MAE %.4f, mean ratio %.4f\n", frame,
                comparison.relativeMeanAbsoluteError, comparison.meanRatio);
    EXPECT_LT(comparison.relativeMeanAbsoluteError, 0.25) << "frame " << frame;
    EXPECT_GT(comparison.meanRatio, 0.8) << "frame " << frame;
    EXPECT_LT(comparison.meanRatio, 1.25) << "frame " << frame;
  }
}

// A tabletop 60 × 40 cm under a lamp, seen from half a metre: two coloured blocks 6–12 cm tall and a glowing card,
// whose light bounces off them onto the board. The tiers' 25 cm voxels, even at a quarter of them, are as large as the
// blocks; the scene's detail scale (0.125: 3 cm voxels, 12.5 cm probes) resolves them (at a quarter the test fails:
// QUALITY.md, "Tabletop scenes").
bench::ScenarioView tabletop() {
  bench::ScenarioView view{};
  Scene& scene = view.scene;
  scene.name = "tabletop";
  scene.materials = {{"board", glm::vec3(0.7f)},
                     {"green", glm::vec3(0.1f, 0.6f, 0.15f)},
                     {"blue", glm::vec3(0.1f, 0.2f, 0.7f)},
                     {"card", glm::vec3(0.0f), renderer::kNoTexture, glm::vec3(1.0f)}};
  const auto box = [&](glm::vec3 low, glm::vec3 high, uint32_t material) {
    renderer::MeshBuilder builder;
    builder.addBox(low, high);
    scene.meshes.push_back(std::move(builder).build(scene.materials[material].name, material));
    scene.instances.push_back({uint32_t(scene.meshes.size() - 1), glm::mat4(1.0f)});
  };
  box({-0.3f, -0.02f, -0.2f}, {0.3f, 0.0f, 0.2f}, 0);
  box({-0.15f, 0.0f, -0.08f}, {-0.05f, 0.12f, 0.02f}, 1);
  box({0.05f, 0.0f, -0.1f}, {0.12f, 0.06f, 0.0f}, 2);
  box({0.1f, 0.0f, 0.08f}, {0.16f, 0.08f, 0.09f}, 3);
  scene.lights.push_back({.name = "lamp", .position = {-0.1f, 0.35f, 0.1f}, .intensity = {2.0f, 1.8f, 1.6f}});
  scene.cameras.push_back({"table", glm::vec3(0.0f, 0.25f, 0.45f), glm::vec3(0.0f, 0.025f, -0.05f)});
  scene.cameras[0].verticalFov = 0.8f;
  scene.giDetailScale = renderer::giDetailScaleFor(renderer::worldBounds(scene), scene.cameras[0].position);
  view.camera = scene.cameras[0];
  return view;
}

TEST_F(ReferenceScenario, aTabletopUnderALampIsWithinTwentyFivePercentOfTheReference) {
  const bench::ScenarioView view = tabletop();
  EXPECT_EQ(view.scene.giDetailScale, 0.125f);
  expectWithinTwentyFivePercent(convergedIndirectError(device(), view, testRendering(view), "tabletop"));
}

// A closed room lit only by two emissive panels (SPEC §6.7): all of its light comes through the GI, most of it after
// several bounces off its white walls, so it converges slowly (about 900 frames); at 128×72 to keep the test short.
// The reference samples the panels directly (next-event estimation), so 256 samples leave it a noise floor of ~1 %.
// Figures and what limits them in QUALITY.md ("Emitters").
TEST_F(ReferenceScenario, aRoomLitOnlyByEmissivePanelsIsWithinTwentyFivePercentOfTheReference) {
  const bench::ScenarioView view = builtinView("panel-room");
  bench::ScenarioRendering rendering = testRendering(view);
  rendering.width = 128;
  rendering.height = 72;
  expectWithinTwentyFivePercent(convergedIndirectError(device(), view, rendering, "panel-room"));
}

}  // namespace
}  // namespace ssvgi
