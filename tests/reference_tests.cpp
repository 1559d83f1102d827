// The reference path tracer against analytic values and against the host renderer: the white furnace, a plane under
// a uniform and under the analytic sky, a rectangular emitter over a floor, direct light and the surface points
// themselves compared with the renderer's, emitter sampling against paths alone, and determinism for a seed.
#include "builtin_scenes.h"
#include "gpu_test_device.h"
#include "path_tracer.h"
#include "renderer.h"
#include "scene_geometry.h"
#include "sky.h"

#include "shared/path_tracer_interface.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

namespace ssvgi {
namespace {

using renderer::FloatImage;
using renderer::Scene;

float channel(const FloatImage& image, uint32_t pixel, uint32_t c) { return image.pixels[size_t(pixel) * image.channels + c]; }
uint32_t pixelCount(const FloatImage& image) { return image.width * image.height; }

renderer::Camera camera(glm::vec3 position, glm::vec3 target, float verticalFovDegrees) {
  renderer::Camera view;
  view.position = position;
  view.target = target;
  view.verticalFov = glm::radians(verticalFovDegrees);
  return view;
}

// A 20×20 m slab of albedo 0.8 whose top face is the plane y = 0, seen from (0, 6, 6); nothing else unless added.
// The slab's sides and bottom lie below the top face, so they hide no sky from it: its every point sees the whole
// upper hemisphere.
Scene planeScene() {
  Scene scene;
  scene.name = "test plane";
  scene.materials.push_back({"white", glm::vec3(0.8f)});
  renderer::MeshBuilder builder;
  builder.addBox(glm::vec3(-10.0f, -0.1f, -10.0f), glm::vec3(10.0f, 0.0f, 10.0f));
  scene.meshes.push_back(std::move(builder).build("plane", 0));
  scene.instances.push_back({0, glm::mat4(1.0f)});
  scene.cameras.push_back(camera({0.0f, 6.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 60.0f));
  return scene;
}

class Reference : public testing::GpuTest {
 protected:
  reference::PathTracer& trace(const Scene& scene, uint32_t width, uint32_t height, uint32_t samples,
                               reference::PathTracerSettings settings = {}) {
    settings.width = width;
    settings.height = height;
    tracer_.emplace(device(), scene, renderer::evaluateAnimation(scene, scene.cameras[0], 0.0f), settings);
    tracer_->trace(samples);
    return *tracer_;
  }
  // The host renderer's frame of the scene from its first camera.
  renderer::Renderer& render(const Scene& scene, uint32_t width, uint32_t height) {
    renderer::RendererSettings settings;
    settings.width = width;
    settings.height = height;
    renderer_.emplace(device(), scene, settings);
    renderer_->render(renderer::evaluateAnimation(scene, scene.cameras[0], 0.0f));
    return *renderer_;
  }

  // The red albedo of each pixel where the renderer sees a surface in a 64 × 48 view, after checking that the path
  // tracer's first hits show the albedo the G-buffer does there, each channel within `tolerance`.
  std::vector<float> albedoSeenAlike(const Scene& scene, float tolerance) {
    constexpr uint32_t kWidth = 64, kHeight = 48;
    renderer::Renderer& renderer = render(scene, kWidth, kHeight);
    const FloatImage albedo = trace(scene, kWidth, kHeight, 1).albedo();
    const FloatImage expected = renderer.albedo();
    const FloatImage distance = renderer.viewDistance();
    std::vector<float> reds;
    for (uint32_t pixel = 0; pixel < kWidth * kHeight; ++pixel) {
      if (channel(distance, pixel, 0) <= 0.0f) continue;
      for (uint32_t c = 0; c < 3; ++c) {
        if (std::abs(channel(albedo, pixel, c) - channel(expected, pixel, c)) > tolerance) {
          ADD_FAILURE() << "pixel " << pixel << " channel " << c << ": " << channel(albedo, pixel, c) << " traced, "
                        << channel(expected, pixel, c) << " rendered";
          return reds;
        }
      }
      reds.push_back(channel(expected, pixel, 0));
    }
    return reds;
  }
  static constexpr uint32_t kAlbedoViewPixels = 64 * 48;

  std::optional<renderer::Renderer> renderer_;
  std::optional<reference::PathTracer> tracer_;
};

// A closed sphere of albedo a emitting Le everywhere on its inside, seen from its centre: the radiance is the same
// everywhere, L = Le + a·L, so every pixel converges to Le / (1 − a) (SPEC §2's furnace check).
Scene furnaceScene(float albedo, glm::vec3 emission) {
  Scene scene;
  scene.name = "furnace";
  scene.materials.push_back({"furnace", glm::vec3(albedo), renderer::kNoTexture, emission});
  renderer::MeshBuilder builder;
  builder.addSphere(glm::vec3(0.0f), 1.0f, 12, 24);
  scene.meshes.push_back(std::move(builder).build("sphere", 0));
  scene.instances.push_back({0, glm::mat4(1.0f)});
  scene.cameras.push_back(camera({0.0f, 0.0f, 0.0f}, {0.3f, 0.2f, -1.0f}, 70.0f));
  return scene;
}

TEST_F(Reference, whiteFurnaceConvergesToEmissionOverOneMinusAlbedo) {
  // Paths alone: with Russian roulette from the 4th vertex a sample of the incoming radiance has a standard deviation
  // of about 0.3 of its mean for a = 0.5, so 64 samples give ~2 % per pixel (a 10 % bound is 5 σ) and ~0.06 % over
  // the image. Emitter sampling must meet the same bounds: next to a shared edge of two of the sphere's facets its
  // estimate alone goes as 1/d² (unbounded variance: 6 of the 1024 pixels kept a firefly at seed 0), which multiple
  // importance sampling leaves to the paths' hits (the worst pixel over six seeds: QUALITY.md, "References").
  // The default 32 bounces truncate the series by a^34: nothing.
  const float albedo = 0.5f;
  const glm::vec3 emission(1.0f, 0.5f, 0.25f);
  const glm::vec3 expected = emission / (1.0f - albedo);
  for (const bool sampleEmitters : {false, true}) {
    reference::PathTracerSettings settings;
    settings.sampleEmitters = sampleEmitters;
    const FloatImage radiance = trace(furnaceScene(albedo, emission), 32, 32, 64, settings).finalRadiance();
    glm::dvec3 sum(0.0);
    for (uint32_t pixel = 0; pixel < pixelCount(radiance); ++pixel) {
      for (uint32_t c = 0; c < 3; ++c) {
        ASSERT_NEAR(channel(radiance, pixel, c), expected[c], 0.1f * expected[c])
            << "pixel " << pixel << ", emitter sampling " << sampleEmitters;
        sum[c] += channel(radiance, pixel, c);
      }
    }
    const glm::dvec3 mean = sum / double(pixelCount(radiance));
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(mean[c], expected[c], 0.02 * expected[c]) << "channel " << c << ", emitter sampling " << sampleEmitters;
  }
}

TEST_F(Reference, bounceCapKeepsExactlyTheLightReflectedThatOftenOrLess) {
  // Below the 4th vertex there is no roulette, so in the furnace every path is the same: with at most 2 reflections
  // the incoming radiance is exactly Le(1 + a + a²), and the pixel Le + a·Le(1 + a + a²), with no noise at all.
  // Emitter sampling is off: its estimate of the emitted light reaching a vertex varies with the point chosen on the
  // sphere's facets, so only paths that pick up emission where they hit it are noise-free here.
  const float albedo = 0.5f;
  const glm::vec3 emission(1.0f, 0.5f, 0.25f);
  reference::PathTracerSettings settings;
  settings.maxBounces = 2;
  settings.sampleEmitters = false;
  const FloatImage radiance = trace(furnaceScene(albedo, emission), 16, 16, 4, settings).finalRadiance();
  const glm::vec3 expected = emission * (1.0f + albedo * (1.0f + albedo + albedo * albedo));
  for (uint32_t pixel = 0; pixel < pixelCount(radiance); ++pixel)
    for (uint32_t c = 0; c < 3; ++c)
      ASSERT_NEAR(channel(radiance, pixel, c), expected[c], 1e-4f * expected[c]) << "pixel " << pixel;
}

TEST_F(Reference, planeUnderAUniformSkyReceivesPiTimesItsRadiance) {
  // Every cosine-sampled ray from the top face leaves the scene and sees exactly L, so each sample is π·L: the
  // estimate has no noise at all, and 1 % only allows for float rounding.
  Scene scene = planeScene();
  const glm::vec3 sky(0.5f, 1.0f, 2.0f);
  scene.sky = {renderer::SkyKind::Uniform, sky, 1.0f};
  auto& tracer = trace(scene, 48, 32, 4);
  const FloatImage indirect = tracer.indirectIrradiance();
  const FloatImage direct = tracer.directIrradiance();
  const FloatImage radiance = tracer.finalRadiance();
  const FloatImage distance = tracer.viewDistance();
  uint32_t surface = 0, background = 0;
  for (uint32_t pixel = 0; pixel < pixelCount(indirect); ++pixel) {
    for (uint32_t c = 0; c < 3; ++c) {
      if (channel(distance, pixel, 0) > 0.0f) {
        ASSERT_NEAR(channel(indirect, pixel, c), glm::pi<float>() * sky[c], 0.01f * glm::pi<float>() * sky[c]);
        ASSERT_EQ(channel(direct, pixel, c), 0.0f);
        ASSERT_NEAR(channel(radiance, pixel, c), 0.8f * sky[c], 0.01f * 0.8f * sky[c]);  // albedo/π · π·L
      } else {
        ASSERT_EQ(channel(radiance, pixel, c), sky[c]);  // past the slab's edge the camera sees the sky itself
      }
    }
    (channel(distance, pixel, 0) > 0.0f ? surface : background) += 1;
  }
  EXPECT_GT(surface, pixelCount(indirect) / 2);
  EXPECT_GT(background, 0u);
}

TEST_F(Reference, planeUnderTheAnalyticSkyReceivesItsCosineWeightedIntegral) {
  // The analytic sky depends on direction only, so every point of the top face has the same E = ∫ L(ω) cos θ dω.
  // Oracle: the same sky function on the CPU, integrated by cosine-weighted quadrature on a 512×512 grid.
  Scene scene = planeScene();
  scene.sun = {false, renderer::sunDirection(40.0f, 30.0f), glm::vec3(0.0f)};  // shapes the sky; no delta light
  scene.sky = {renderer::SkyKind::Default, glm::vec3(0.0f), 1.0f};
  const shader::SkyParameters sky = renderer::makeSkyParameters(scene.sky, scene.sun);
  constexpr int kGrid = 512;
  glm::dvec3 expected(0.0);
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const glm::vec2 cell((float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid);
      expected += glm::dvec3(shader::evaluateSky(sky, shader::cosineSampleHemisphere(cell, glm::vec3(0, 1, 0))));
    }
  expected *= glm::pi<double>() / (kGrid * kGrid);

  // One sample is π·L(ω) for a cosine-distributed ω; the circumsolar peak gives it a relative standard deviation of
  // 1.3 (red; less in green and blue), so 48×32 pixels × 256 samples leave σ = 0.21 % on the mean: 1 % is 4.8 σ.
  auto& tracer = trace(scene, 48, 32, 256);
  const FloatImage indirect = tracer.indirectIrradiance();
  const FloatImage distance = tracer.viewDistance();
  glm::dvec3 sum(0.0);
  uint32_t surface = 0;
  for (uint32_t pixel = 0; pixel < pixelCount(indirect); ++pixel) {
    if (channel(distance, pixel, 0) <= 0.0f) continue;
    for (uint32_t c = 0; c < 3; ++c) sum[c] += channel(indirect, pixel, c);
    ++surface;
  }
  ASSERT_GT(surface, 200u);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] / surface, expected[c], 0.01 * expected[c]) << "channel " << c;
}

TEST_F(Reference, directLightAndSurfacePointsMatchTheRenderer) {
  // A point light and a spot light over the plane, no occluder: the renderer's shadow maps then change nothing, and
  // both must give the same E_direct per pixel from the same light model (SPEC §3). Primary rays use the renderer's
  // matrices and pixel centres, so both see the same surface points: same depth, normal and albedo (the G-buffer
  // stores albedo and normal in half floats).
  Scene scene = planeScene();
  scene.lights.push_back({"point", renderer::LightType::Point, {1.0f, 2.0f, 0.5f}, {0, -1, 0}, glm::vec3(10.0f, 8.0f, 6.0f)});
  renderer::LocalLight spot{"spot", renderer::LightType::Spot, {-2.0f, 3.0f, -1.0f}, glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)),
                            glm::vec3(20.0f)};
  spot.innerConeAngle = glm::radians(15.0f);
  spot.outerConeAngle = glm::radians(35.0f);
  spot.range = 6.0f;
  scene.lights.push_back(spot);
  constexpr uint32_t kWidth = 64, kHeight = 48;
  renderer::Renderer& renderer = render(scene, kWidth, kHeight);
  auto& tracer = trace(scene, kWidth, kHeight, 1);

  const FloatImage direct = tracer.directIrradiance(), expectedDirect = renderer.directIrradiance();
  const FloatImage distance = tracer.viewDistance(), expectedDistance = renderer.viewDistance();
  const FloatImage normal = tracer.normal(), expectedNormal = renderer.normal();
  const FloatImage albedo = tracer.albedo(), expectedAlbedo = renderer.albedo();
  uint32_t lit = 0;
  for (uint32_t pixel = 0; pixel < kWidth * kHeight; ++pixel) {
    ASSERT_NEAR(channel(distance, pixel, 0), channel(expectedDistance, pixel, 0),
                1e-4f * channel(expectedDistance, pixel, 0)) << "pixel " << pixel;
    if (channel(expectedDistance, pixel, 0) <= 0.0f) continue;
    for (uint32_t c = 0; c < 3; ++c) {
      const float expected = channel(expectedDirect, pixel, c);
      ASSERT_NEAR(channel(direct, pixel, c), expected, 0.01f * expected) << "pixel " << pixel << " channel " << c;
      ASSERT_NEAR(channel(normal, pixel, c), channel(expectedNormal, pixel, c), 1e-3f) << "pixel " << pixel;
      ASSERT_NEAR(channel(albedo, pixel, c), channel(expectedAlbedo, pixel, c), 1e-3f) << "pixel " << pixel;
    }
    lit += channel(expectedDirect, pixel, 0) > 0.1f;
  }
  EXPECT_GT(lit, kWidth * kHeight / 3);
}

TEST_F(Reference, texturedAlbedoMatchesTheRenderersSampler) {
  // A 4×4 sRGB texture repeated 2.5 times across each face of the slab: the path tracer's bilinear filtering of the
  // packed texels (sRGB decoded first, repeat addressing) must give the albedo the G-buffer's hardware sampler gives.
  // Tolerance: the sampler's fixed-point filter weights (8 bits on lavapipe) and the G-buffer's half floats.
  Scene scene = planeScene();
  renderer::Texture texture{"checker", 4, 4, {}};
  for (uint32_t texel = 0; texel < 16; ++texel) {
    const auto value = [&](uint32_t salt) { return static_cast<uint8_t>((texel * 37u + salt * 91u) % 256u); };
    texture.rgba.insert(texture.rgba.end(), {value(1), value(2), value(3), 255});
  }
  scene.textures.push_back(texture);
  scene.materials[0].baseColorTexture = 0;
  for (renderer::Vertex& vertex : scene.meshes[0].vertices) vertex.uv = vertex.uv * 2.5f - 0.3f;
  EXPECT_GT(albedoSeenAlike(scene, 0.01f).size(), kAlbedoViewPixels / 2);
}

TEST_F(Reference, vertexColoursMultiplyTheAlbedoAlikeInTheRendererAndThePathTracer) {
  // The slab's vertices coloured by where they lie, from (0, 0.25, 0.3) to (1, 0.75, 0.3) across it: both interpolate
  // them over each triangle (perspective-correct, barycentric) and multiply the base colour, so the albedo each pixel
  // shows agrees to the G-buffer's half floats (2·10⁻³). And the colours matter: many pixels differ from the white
  // slab's 0.8 by more than that.
  Scene scene = planeScene();
  for (renderer::Vertex& vertex : scene.meshes[0].vertices)
    vertex.color = glm::vec3(0.5f + 0.05f * vertex.position.x, 0.5f + 0.025f * vertex.position.z, 0.3f);
  const std::vector<float> reds = albedoSeenAlike(scene, 2e-3f);
  const auto coloured = std::count_if(reds.begin(), reds.end(), [](float red) { return std::abs(red - 0.8f) > 0.05f; });
  EXPECT_GT(coloured, kAlbedoViewPixels / 2);
}

bool sameBits(const FloatImage& a, const FloatImage& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

// Settings whose dispatches stay short even for a tiny image. On lavapipe a dispatch that gives each pixel thousands
// of samples silently loses some of them (measured: the middle pixel of the 9 × 9 view below got 3 % less light at
// 4096 samples per pixel in 0.25 s dispatches than in short ones, and half at 16384, while short dispatches match a
// CPU replay of the same random numbers); most likely llvmpipe's cap of 65535 loop iterations per invocation.
reference::PathTracerSettings shortDispatches() {
  reference::PathTracerSettings settings;
  settings.secondsPerDispatch = 0.005;
  return settings;
}

// A horizontal rectangle x ∈ [−halfWidth, halfWidth], z ∈ [−halfDepth, halfDepth] at `height`: two triangles with no
// thickness, whose front (counter-clockwise) face looks down or up.
renderer::Mesh horizontalRectangle(float height, float halfWidth, float halfDepth, bool facingDown, uint32_t material) {
  const glm::vec3 normal(0.0f, facingDown ? -1.0f : 1.0f, 0.0f);
  renderer::Mesh mesh{"rectangle", {}, {}, material};
  for (const glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
    mesh.vertices.push_back({glm::vec3(corner.x * halfWidth, height, corner.y * halfDepth), normal, corner});
  // (−,−), (+,−), (+,+) is clockwise seen from above: it faces down.
  mesh.indices = facingDown ? std::vector<uint32_t>{0, 1, 2, 0, 2, 3} : std::vector<uint32_t>{0, 2, 1, 0, 3, 2};
  return mesh;
}

// The form factor from a point to a parallel rectangle at distance h whose corner lies straight above it, the
// rectangle's sides a and b (Howell, "A Catalog of Radiation Heat Transfer Configuration Factors", B-3):
// F = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h.
double cornerFormFactor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double rootX = std::sqrt(1.0 + x * x), rootY = std::sqrt(1.0 + y * y);
  return (x / rootX * std::atan(y / rootX) + y / rootY * std::atan(x / rootY)) / (2.0 * glm::pi<double>());
}

// The plane under a 6×6 m rectangle 1 m up whose texture cuts it out in a checker of 1.5 m squares (glTF's MASK:
// Material::alphaCutoff), lit by the sun from high up: the camera sees the plane through the holes, and the sun lights
// it through them.
Scene cutOutScene(float alphaCutoff) {
  Scene scene = planeScene();
  renderer::Texture checker{"checker", 8, 8, {}};
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 8; ++x)
      checker.rgba.insert(checker.rgba.end(), {200, 180, 160, static_cast<uint8_t>(((x / 4 + y / 4) % 2) * 255)});
  scene.textures.push_back(checker);
  scene.materials.push_back({"leaves", glm::vec3(0.6f), 0});
  scene.materials[1].alphaCutoff = alphaCutoff;
  scene.meshes.push_back(horizontalRectangle(1.0f, 3.0f, 3.0f, false, 1));
  scene.instances.push_back({1, glm::mat4(1.0f)});
  scene.sun.enabled = true;
  scene.sun.direction = renderer::sunDirection(30.0f, 70.0f);
  scene.sun.illuminance = glm::vec3(5.0f);
  return scene;
}

TEST_F(Reference, surfacesCutOutByTheirTextureAreLeftOutAlikeByTheRendererItsShadowsAndThePathTracer) {
  // Where the texture's alpha is below the cutoff there is no surface: the G-buffer shows what lies behind, the sun's
  // shadow map casts no shadow, and the path tracer's rays pass. The two must agree on what each pixel sees and on
  // its direct light, but for the pixels on the edges of the holes (bilinear alpha crossing the cutoff, and the
  // shadow map's filtered edges): at most 4 % of the pixels. And the holes must matter: against the same rectangle
  // drawn opaque, over 10 % of the pixels see or are lit differently.
  constexpr uint32_t kWidth = 96, kHeight = 72;
  const auto rendered = [&](const Scene& scene) {
    renderer::Renderer& renderer = render(scene, kWidth, kHeight);
    return std::make_pair(renderer.viewDistance(), renderer.directIrradiance());
  };
  const Scene scene = cutOutScene(0.5f);
  const auto [distance, direct] = rendered(scene);
  const auto [opaqueDistance, opaqueDirect] = rendered(cutOutScene(0.0f));
  auto& tracer = trace(scene, kWidth, kHeight, 1);
  const FloatImage tracedDistance = tracer.viewDistance(), tracedDirect = tracer.directIrradiance();

  uint32_t disagree = 0, cutOut = 0;
  for (uint32_t pixel = 0; pixel < kWidth * kHeight; ++pixel) {
    const float seen = channel(distance, pixel, 0), light = channel(direct, pixel, 0);
    const bool sameSurface = std::abs(channel(tracedDistance, pixel, 0) - seen) <= 1e-3f * seen;
    const bool sameLight = std::abs(channel(tracedDirect, pixel, 0) - light) <= 0.05f * 5.0f;
    disagree += !(sameSurface && sameLight);
    cutOut += std::abs(channel(opaqueDistance, pixel, 0) - seen) > 1e-3f * seen ||
              std::abs(channel(opaqueDirect, pixel, 0) - light) > 0.05f * 5.0f;
  }
  EXPECT_LE(disagree, kWidth * kHeight * 4 / 100);
  EXPECT_GE(cutOut, kWidth * kHeight / 10);
}

TEST_F(Reference, rectangularEmitterGivesThePointBelowItsCentrePiTimesRadianceTimesFormFactor) {
  // A 1 × 0.6 m rectangle of radiance L, 1 m over a black floor (nothing reflects, no sky): at the point below its
  // centre E_indirect = π·L·F, F the sum of the four corner rectangles' form factors. The view is 9 × 9 pixels
  // centred on that point, so the middle pixel's centre sees it exactly. Emitter sampling picks points uniformly over
  // the rectangle (its two triangles by area), where the integrand cos θ cos θ_e / d² = h²/d⁴ has a relative standard
  // deviation of 0.14: 4096 samples leave σ = 0.21 %, and 1.5 % is 7 σ. The emitter seen from behind must give the
  // same: its emission is two-sided.
  constexpr float kHeight = 1.0f, kHalfWidth = 0.5f, kHalfDepth = 0.3f;
  const glm::vec3 radiance(15.0f, 10.0f, 5.0f);
  const double formFactor = 4.0 * cornerFormFactor(kHalfWidth, kHalfDepth, kHeight);
  for (const bool facingDown : {true, false}) {
    Scene scene = planeScene();
    scene.materials[0].baseColor = glm::vec3(0.0f);
    scene.materials.push_back({"panel", glm::vec3(0.0f), renderer::kNoTexture, radiance});
    scene.meshes.push_back(horizontalRectangle(kHeight, kHalfWidth, kHalfDepth, facingDown, 1));
    scene.instances.push_back({1, glm::mat4(1.0f)});
    const FloatImage indirect = trace(scene, 9, 9, 4096, shortDispatches()).indirectIrradiance();
    const uint32_t centre = 4 * 9 + 4;
    for (uint32_t c = 0; c < 3; ++c) {
      const double expected = glm::pi<double>() * radiance[c] * formFactor;
      EXPECT_NEAR(channel(indirect, centre, c), expected, 0.015 * expected)
          << (facingDown ? "facing the floor" : "seen from behind") << ", channel " << c;
    }
  }
}

// A 64 × 1 texture black in its left half and white in its right: on horizontalRectangle's texture coordinates (u from
// −1 to 1 across x) it is white where x lies in [−w/2, 0) or [w/2, w) of a half-width w.
renderer::Texture halfWhiteTexture() {
  renderer::Texture texture{"half white", 64, 1, {}};
  for (uint32_t x = 0; x < 64; ++x) {
    const uint8_t value = x < 32 ? 0 : 255;
    texture.rgba.insert(texture.rgba.end(), {value, value, value, 255});
  }
  return texture;
}

// A black plane under a 1 × 0.6 m panel 1 m up, facing down: `panel` is its material, `texture` the scene's one
// texture.
constexpr float kPanelHeight = 1.0f, kPanelHalfWidth = 0.5f, kPanelHalfDepth = 0.3f;
Scene blackPlaneUnderAPanel(const renderer::Material& panel, renderer::Texture texture) {
  Scene scene = planeScene();
  scene.materials[0].baseColor = glm::vec3(0.0f);
  scene.textures.push_back(std::move(texture));
  scene.materials.push_back(panel);
  scene.meshes.push_back(horizontalRectangle(kPanelHeight, kPanelHalfWidth, kPanelHalfDepth, true, 1));
  scene.instances.push_back({1, glm::mat4(1.0f)});
  return scene;
}

// The irradiance the middle pixel of a 3 × 3 trace of the panel scene sees, against π·L·2·F: what half the panel
// emitting L gives the point below its centre (2 % allowed; each test says why).
void expectHalfThePanelsIrradiance(const FloatImage& indirect, const glm::vec3& radiance) {
  const double formFactor = 2.0 * cornerFormFactor(kPanelHalfWidth, kPanelHalfDepth, kPanelHeight);
  for (uint32_t c = 0; c < 3; ++c) {
    const double expected = glm::pi<double>() * radiance[c] * formFactor;
    EXPECT_NEAR(channel(indirect, 4, c), expected, 0.02 * expected) << "channel " << c;
  }
}

TEST_F(Reference, anEmissionTextureScalesTheEmissionWhereverTheRendererAndThePathsMeetIt) {
  // The emitter of the test above with the half-white texture as its emission texture, over a black floor: the white
  // strips, each a difference of corner rectangles, give the point below its centre E = π·L·2·F(w, d, h) — half the
  // whole panel's — with the bilinear ramps at the texel edges (a texel of 64 each) symmetric about the step, so no
  // error of their own. Half the emitter samples fall on black, which takes the relative standard deviation of a
  // sample to about 1: 65,536 samples leave σ = 0.4 %, and 2 % is 5 σ.
  const glm::vec3 radiance(15.0f, 10.0f, 5.0f);
  Scene scene =
      blackPlaneUnderAPanel({"panel", glm::vec3(0.0f), renderer::kNoTexture, radiance, 0}, halfWhiteTexture());
  expectHalfThePanelsIrradiance(trace(scene, 3, 3, 65536, shortDispatches()).indirectIrradiance(), radiance);

  // Seen from the camera, the renderer's G-buffer and the path tracer's first hits show the same emission (the
  // floor and the panel reflect nothing): within the hardware sampler's 8-bit filter weights, 1 % of L. From closer,
  // so that the panel fills much of the view.
  scene.cameras[0] = camera({0.0f, 2.5f, 1.5f}, {0.0f, 1.0f, 0.0f}, 60.0f);
  constexpr uint32_t kWidth = 48, kHeightPixels = 36;
  const FloatImage shown = render(scene, kWidth, kHeightPixels).finalRadiance();
  const FloatImage traced = trace(scene, kWidth, kHeightPixels, 1).finalRadiance();
  uint32_t bright = 0;
  for (uint32_t pixel = 0; pixel < kWidth * kHeightPixels; ++pixel) {
    for (uint32_t c = 0; c < 3; ++c)
      ASSERT_NEAR(channel(traced, pixel, c), channel(shown, pixel, c), 0.01f * radiance[c]) << "pixel " << pixel;
    bright += channel(shown, pixel, 0) > 0.9f * radiance[0];
  }
  EXPECT_GT(bright, 20u);  // the white strips are in view
}

TEST_F(Reference, anEmitterItsTextureCutsOutInPlacesEmitsOnlyWhereItIs) {
  // The panel of the test above emitting L all over, cut out by its base colour texture's alpha where that test's
  // emission texture was black: the same E, π·L·2·F, from next-event estimation and the paths' hits alike (2 %).
  const glm::vec3 radiance(15.0f, 10.0f, 5.0f);
  renderer::Texture holes = halfWhiteTexture();
  for (size_t texel = 0; texel < 32; ++texel) holes.rgba[4 * texel + 3] = 0;
  renderer::Material panel{"panel", glm::vec3(0.0f), 0, radiance};
  panel.alphaCutoff = 0.5f;
  const Scene scene = blackPlaneUnderAPanel(panel, std::move(holes));
  expectHalfThePanelsIrradiance(trace(scene, 3, 3, 65536, shortDispatches()).indirectIrradiance(), radiance);
}

// A closed 2 × 2 × 2 m room of albedo 0.7 (x, z ∈ [−1, 1], y ∈ [0, 2]) lit only by a 0.6 × 0.4 m panel of radiance
// (15, 12, 8). By default it hangs 0.4 m below the ceiling, a rectangle with no thickness, its front face down and its
// back lighting the ceiling; the camera stands inside and sees the floor, the back wall and the panel. With
// `panelOnCeiling` it is a 2 cm thick box whose top touches the ceiling, as the cornell scene's, and the camera looks
// up at the ceiling around it: next to the box's sides the emitters' light at a ceiling point goes as 1/d².
Scene emitterRoomScene(bool panelOnCeiling = false) {
  Scene scene;
  scene.name = "emitter room";
  scene.materials.push_back({"wall", glm::vec3(0.7f)});
  scene.materials.push_back({"panel", glm::vec3(0.0f), renderer::kNoTexture, glm::vec3(15.0f, 12.0f, 8.0f)});
  renderer::MeshBuilder walls;
  constexpr float kWall = 0.1f;
  walls.addBox(glm::vec3(-1.0f - kWall, -kWall, -1.0f - kWall), glm::vec3(1.0f + kWall, 0.0f, 1.0f + kWall));
  walls.addBox(glm::vec3(-1.0f - kWall, 2.0f, -1.0f - kWall), glm::vec3(1.0f + kWall, 2.0f + kWall, 1.0f + kWall));
  walls.addBox(glm::vec3(-1.0f - kWall, 0.0f, -1.0f - kWall), glm::vec3(-1.0f, 2.0f, 1.0f + kWall));
  walls.addBox(glm::vec3(1.0f, 0.0f, -1.0f - kWall), glm::vec3(1.0f + kWall, 2.0f, 1.0f + kWall));
  walls.addBox(glm::vec3(-1.0f, 0.0f, -1.0f - kWall), glm::vec3(1.0f, 2.0f, -1.0f));
  walls.addBox(glm::vec3(-1.0f, 0.0f, 1.0f), glm::vec3(1.0f, 2.0f, 1.0f + kWall));
  scene.meshes.push_back(std::move(walls).build("walls", 0));
  if (panelOnCeiling) {
    renderer::MeshBuilder panel;
    panel.addBox(glm::vec3(-0.3f, 1.98f, -0.2f), glm::vec3(0.3f, 2.0f, 0.2f));
    scene.meshes.push_back(std::move(panel).build("panel", 1));
  } else {
    scene.meshes.push_back(horizontalRectangle(1.6f, 0.3f, 0.2f, true, 1));
  }
  scene.instances.push_back({0, glm::mat4(1.0f)});
  scene.instances.push_back({1, glm::mat4(1.0f)});
  if (panelOnCeiling) {
    scene.cameras.push_back(camera({0.0f, 0.6f, 0.9f}, {0.0f, 2.0f, -0.1f}, 60.0f));
  } else {
    scene.cameras.push_back(camera({0.0f, 1.0f, 0.9f}, {0.0f, 0.8f, -1.0f}, 75.0f));
  }
  return scene;
}

// E_indirect of a scene traced with two seeds at the same samples per pixel, as one value per pixel (the mean of the
// colour channels, which share their paths and so their noise).
struct IndirectNoise {
  double mean = 0.0;                 // over both seeds and every pixel
  double rmsSeedDifference = 0.0;    // √(mean over pixels of (seed 1 − seed 2)²): √2 × a pixel's standard deviation
  double standardErrorOfMean = 0.0;  // of `mean`: pixels and seeds have independent noise
};

IndirectNoise indirectNoise(gpu::OwnedDevice& device, const Scene& scene, reference::PathTracerSettings settings,
                            uint32_t samples) {
  const renderer::AnimatedState state = renderer::evaluateAnimation(scene, scene.cameras[0], 0.0f);
  std::vector<FloatImage> images;
  for (const uint32_t seed : {1u, 2u}) {
    settings.seed = seed;
    reference::PathTracer tracer(device, scene, state, settings);
    tracer.trace(samples);
    images.push_back(tracer.indirectIrradiance());
  }
  const auto value = [](const FloatImage& image, uint32_t pixel) {
    return (channel(image, pixel, 0) + channel(image, pixel, 1) + channel(image, pixel, 2)) / 3.0;
  };
  const uint32_t pixels = pixelCount(images[0]);
  double sum = 0.0, squaredDifferences = 0.0;
  for (uint32_t pixel = 0; pixel < pixels; ++pixel) {
    sum += value(images[0], pixel) + value(images[1], pixel);
    squaredDifferences += std::pow(value(images[0], pixel) - value(images[1], pixel), 2.0);
  }
  IndirectNoise noise;
  noise.mean = sum / (2.0 * pixels);
  noise.rmsSeedDifference = std::sqrt(squaredDifferences / pixels);
  noise.standardErrorOfMean = noise.rmsSeedDifference / std::sqrt(2.0) / std::sqrt(2.0 * pixels);
  return noise;
}

// Both estimators are unbiased, so their image means of E_indirect differ only by noise: 5 standard errors of the
// difference, each taken from the spread between two seeds. Emitter sampling must also leave less noise per pixel at
// the same samples per pixel: its RMS seed difference at most `noiseFraction` of the paths' alone (the measured
// figures, with their margins, are in QUALITY.md's "References").
void expectEmitterSamplingAgreesWithPathsAloneWithLessNoise(gpu::OwnedDevice& device, const Scene& scene,
                                                           double noiseFraction) {
  reference::PathTracerSettings settings = shortDispatches();
  settings.width = 24;
  settings.height = 24;
  const IndirectNoise sampled = indirectNoise(device, scene, settings, 64);
  settings.sampleEmitters = false;
  const IndirectNoise pathsAlone = indirectNoise(device, scene, settings, 64);
  const double standardError = std::hypot(sampled.standardErrorOfMean, pathsAlone.standardErrorOfMean);
  EXPECT_NEAR(sampled.mean, pathsAlone.mean, 5.0 * standardError);
  EXPECT_LT(sampled.rmsSeedDifference, noiseFraction * pathsAlone.rmsSeedDifference);
}

TEST_F(Reference, emitterSamplingAgreesWithPathsAloneWithLessNoise) {
  expectEmitterSamplingAgreesWithPathsAloneWithLessNoise(device(), emitterRoomScene(), 0.5);
}

// Next to where the panel's sides meet the ceiling, the emitter estimate alone goes as 1/d², whose variance has no
// bound: fireflies that paths alone, which find the panel by hitting it, do not have (that estimate fails this bound).
// Multiple importance sampling hands that region to the paths' hits.
TEST_F(Reference, emitterSamplingNextToAnEmitterTouchingTheCeilingIsNoNoisierThanPathsAlone) {
  expectEmitterSamplingAgreesWithPathsAloneWithLessNoise(device(), emitterRoomScene(true), 0.6);
}

TEST_F(Reference, sceneWithoutEmittersTracesAsWithEmitterSamplingOff) {
  // The plane under a uniform sky with a box on it and a point light: no triangle emits, so the emitter table is empty
  // (its buffer holds one unused entry) and the paths, which bounce between the box and the plane, must be exactly
  // those traced without emitter sampling.
  Scene scene = planeScene();
  renderer::MeshBuilder box;
  box.addBox(glm::vec3(-1.0f, 0.0f, -1.0f), glm::vec3(1.0f, 2.0f, 1.0f));
  scene.meshes.push_back(std::move(box).build("box", 0));
  scene.instances.push_back({1, glm::mat4(1.0f)});
  scene.sky = {renderer::SkyKind::Uniform, glm::vec3(0.5f, 1.0f, 2.0f), 1.0f};
  scene.lights.push_back({"point", renderer::LightType::Point, {1.0f, 2.0f, 0.5f}, {0, -1, 0}, glm::vec3(10.0f)});
  const FloatImage sampled = trace(scene, 16, 16, 8).indirectIrradiance();
  reference::PathTracerSettings settings;
  settings.sampleEmitters = false;
  const FloatImage pathsAlone = trace(scene, 16, 16, 8, settings).indirectIrradiance();
  EXPECT_TRUE(sameBits(sampled, pathsAlone));
}

TEST_F(Reference, sameSeedGivesBitIdenticalImagesWhateverTheBatchesAndAnotherSeedDoesNot) {
  Scene scene = *renderer::makeBuiltinScene("cornell");
  reference::PathTracerSettings settings;
  settings.width = 24;
  settings.height = 24;
  settings.seed = 7;
  const renderer::AnimatedState state = renderer::evaluateAnimation(scene, scene.cameras[0], 0.0f);
  reference::PathTracer once(device(), scene, state, settings);
  once.trace(12);
  reference::PathTracer inParts(device(), scene, state, settings);
  inParts.trace(5);
  inParts.trace(7);
  settings.seed = 8;
  reference::PathTracer otherSeed(device(), scene, state, settings);
  otherSeed.trace(12);

  EXPECT_TRUE(sameBits(once.indirectIrradiance(), inParts.indirectIrradiance()));
  EXPECT_TRUE(sameBits(once.finalRadiance(), inParts.finalRadiance()));
  EXPECT_FALSE(sameBits(once.indirectIrradiance(), otherSeed.indirectIrradiance()));
  EXPECT_TRUE(sameBits(once.directIrradiance(), otherSeed.directIrradiance())) << "direct light is not random";
}

}  // namespace
}  // namespace ssvgi
