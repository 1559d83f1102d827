// The views beyond the camera the renderer gives ssvgi (SPEC §6.3, renderer/extra_views.h): the sun's view fills a
// sunlit wall the camera never sees, in its sunlit colour; the capture around the camera fills a ceiling above and
// behind it; the views take turns within their budget; the sun's texel grid stays put as the camera moves.
#include "camera.h"
#include "gpu_test_device.h"
#include "renderer.h"
#include "scene_geometry.h"
#include "shared/gi_frame.h"
#include "shared/sampling.h"
#include "voxel_readback.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <map>

namespace ssvgi {
namespace {

using renderer::Scene;

constexpr float kVoxel = 0.25f;

// A scene of boxes, one material each, seen from `camera`.
Scene boxScene(const std::vector<std::pair<std::pair<glm::vec3, glm::vec3>, glm::vec3>>& boxes,
               const renderer::Camera& camera) {
  Scene scene;
  scene.name = "boxes";
  for (const auto& [corners, albedo] : boxes) {
    scene.materials.push_back({"box", albedo});
    renderer::MeshBuilder builder;
    builder.addBox(corners.first, corners.second);
    scene.meshes.push_back(std::move(builder).build("box", uint32_t(scene.materials.size() - 1)));
    scene.instances.push_back({uint32_t(scene.meshes.size() - 1), glm::mat4(1.0f)});
  }
  scene.cameras.push_back(camera);
  return scene;
}

// A 16 m voxel volume at 0.25 m, 16 m of 1 m probes.
Settings smallGi() {
  Settings settings;
  settings.volumeBricks = {16, 8, 16};
  settings.brickPoolCapacity = 2048;
  settings.probeGrid = {16, 8, 16};
  settings.probeBudget = 1024;
  return settings;
}

renderer::RendererSettings rendering(const renderer::ExtraViewSettings& views) {
  renderer::RendererSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.gi = smallGi();
  settings.extraViews = views;
  return settings;
}

void renderFrames(renderer::Renderer& renderer, const Scene& scene, uint32_t frames) {
  for (uint32_t frame = 0; frame < frames; ++frame)
    renderer.render(renderer::evaluateAnimation(scene, scene.cameras[0], 0.0f));
}

class ExtraViews : public testing::GpuTest {};

// A grey wall (its face the plane z = 4, facing −z) lit by the sun from the −z side, over a black floor, no sky; the
// camera at the origin looks the other way. The wall's voxels hold albedo/π · E_sun · cos θ (the black floor and sky
// bounce nothing back onto it) — if the sun's view gives them.
struct SunlitWallBehindTheCamera {
  static inline const glm::vec3 kAlbedo{0.8f, 0.6f, 0.4f};
  static constexpr float kIlluminance = 10.0f;
  Scene scene;
  glm::vec3 toSun = renderer::sunDirection(200.0f, 40.0f);
  SunlitWallBehindTheCamera() {
    renderer::Camera camera;
    camera.position = {0.0f, 1.6f, 0.0f};
    camera.target = {0.0f, 1.4f, -5.0f};
    scene = boxScene({{{{-4.0f, 0.0f, 4.0f}, {4.0f, 3.0f, 4.3f}}, kAlbedo},
                      {{{-8.0f, -0.2f, -8.0f}, {8.0f, 0.0f, 8.0f}}, glm::vec3(0.0f)}},
                     camera);
    scene.sun = {.enabled = true, .direction = toSun, .illuminance = glm::vec3(kIlluminance)};
  }
};

TEST_F(ExtraViews, theSunsViewFillsASunlitWallTheCameraNeverSeesInItsSunlitColour) {
  const SunlitWallBehindTheCamera wall;
  const glm::vec3 expected = SunlitWallBehindTheCamera::kAlbedo / glm::pi<float>() *
                             SunlitWallBehindTheCamera::kIlluminance * glm::dot(wall.toSun, glm::vec3(0, 0, -1));
  // Voxels of the wall's face away from its edges: x in [−3.5, 3.5), y in [0.25, 2.75); the face lies on a voxel
  // boundary, so it is held by the layer behind it (z index 16).
  auto wallVoxels = [](const auto& occupied, auto&& each) {
    uint32_t found = 0;
    for (int x = -14; x < 14; ++x)
      for (int y = 1; y < 11; ++y) {
        const auto voxel = occupied.find({x, y, 16});
        if (voxel == occupied.end()) continue;
        ++found;
        each(x, y, voxel->second);
      }
    return found;
  };
  {
    // 64 texels over the volume's 16 m footprint: a voxel each, and the wall, grazed by the sun, shows less than a
    // texel a voxel: the view's jitter from render to render lets every voxel's random points meet its own surface.
    // The sun's view every frame, nothing else, 16 times.
    renderer::Renderer renderer(device(), wall.scene,
                                rendering({.sunViewSize = 64, .surroundViewSize = 0, .lightViewSize = 0,
                                           .overheadViewSize = 0, .viewsPerFrame = 1}));
    renderFrames(renderer, wall.scene, 16);
    const auto occupied = testing::readOccupiedVoxels(device(), *renderer.giContext());
    const uint32_t found = wallVoxels(occupied, [&](int x, int y, const shader::Voxel& voxel) {
      // R11G11B10F: 1/64 relative in red and green, 1/32 in blue.
      const glm::vec3 radiance = shader::unpackR11G11B10F(voxel.radiance);
      EXPECT_NEAR(radiance.r, expected.r, expected.r / 64.0f) << "voxel " << x << "," << y;
      EXPECT_NEAR(radiance.g, expected.g, expected.g / 64.0f) << "voxel " << x << "," << y;
      EXPECT_NEAR(radiance.b, expected.b, expected.b / 32.0f) << "voxel " << x << "," << y;
      EXPECT_LT(shader::voxelNormal(voxel).z, -0.99f);
    });
    EXPECT_EQ(found, 28u * 10u) << "of the wall's voxels";
  }
  {
    // Without it, nothing the camera sees is near the wall.
    renderer::Renderer renderer(device(), wall.scene,
                                rendering({.sunViewSize = 0, .surroundViewSize = 0, .lightViewSize = 0,
                                           .overheadViewSize = 0}));
    renderFrames(renderer, wall.scene, 8);
    EXPECT_EQ(wallVoxels(testing::readOccupiedVoxels(device(), *renderer.giContext()), [](int, int, const auto&) {}), 0u);
  }
}

TEST_F(ExtraViews, aWallTheSunTurnsAwayFromLosesItsSunlightOnceTheSunsViewHasSeenIt) {
  // SPEC §6.1: the sunlit wall behind the camera, then the sun turned round to the wall's other side. The face the
  // camera never sees gets no sunlight any more. The sun lights this scene alone, so the renderer gives its view as a
  // reflective shadow map when asked (ExtraViewSettings::reflectiveShadowMaps), which sees that face hidden behind the
  // wall and takes its direct light: 0.75 of it kept per render, 16 renders. (A light's view never sees what its light
  // stopped reaching: without the flag, the face would keep its sunlight for good.)
  SunlitWallBehindTheCamera wall;
  renderer::Renderer renderer(device(), wall.scene,
                              rendering({.sunViewSize = 64, .surroundViewSize = 0, .lightViewSize = 0,
                                         .overheadViewSize = 0, .viewsPerFrame = 1, .reflectiveShadowMaps = true}));
  auto meanDirect = [&]() {
    const auto occupied = testing::readOccupiedVoxels(device(), *renderer.giContext());
    float sum = 0.0f;
    uint32_t found = 0;
    for (int x = -14; x < 14; ++x)
      for (int y = 1; y < 11; ++y)
        if (const auto voxel = occupied.find({x, y, 16}); voxel != occupied.end()) {
          sum += shader::unpackR11G11B10F(voxel->second.directRadiance).g;
          ++found;
        }
    EXPECT_EQ(found, 28u * 10u) << "of the wall's voxels";
    return found > 0 ? sum / float(found) : 0.0f;
  };
  renderFrames(renderer, wall.scene, 16);
  const float sunlit = meanDirect();
  EXPECT_NEAR(sunlit,
              SunlitWallBehindTheCamera::kAlbedo.g / glm::pi<float>() * SunlitWallBehindTheCamera::kIlluminance *
                  glm::dot(wall.toSun, glm::vec3(0, 0, -1)),
              sunlit / 64.0f);
  renderer::AnimatedState turned = renderer::evaluateAnimation(wall.scene, wall.scene.cameras[0], 0.0f);
  turned.sun.direction = renderer::sunDirection(20.0f, 40.0f);
  for (uint32_t frame = 0; frame < 16; ++frame) renderer.render(turned);
  const float afterTurning = meanDirect();
  std::printf("the wall's face: direct light %.4f lit by the sun, %.5f once it is turned away\n", sunlit,
              afterTurning);
  EXPECT_LT(afterTurning, 0.02f * sunlit);
}

TEST_F(ExtraViews, theCaptureAroundTheCameraFillsTheCeilingAboveAndBehindIt) {
  // A closed 8×3×8 m room; the camera near one end looks level along it (60°): it sees the ceiling only beyond
  // 1.5 / tan 30° = 2.6 m ahead, z < −0.6. The ceiling's face (y = 3, facing down) lies on a voxel boundary: its
  // voxels are the layer above it (y index 12). Checked: those within 45° of the camera's zenith, above and behind
  // it (x in [−1.5, 1.5), z in [0.5, 3.5)), which the capture's upward face sees at 2.3 to 3.3 cm per texel.
  renderer::Camera camera;
  camera.position = {0.0f, 1.5f, 2.0f};
  camera.target = {0.0f, 1.5f, -4.0f};
  const glm::vec3 white(0.7f);
  const Scene room = boxScene({{{{-4.2f, -0.2f, -4.2f}, {4.2f, 0.0f, 4.2f}}, white},
                               {{{-4.2f, 3.0f, -4.2f}, {4.2f, 3.2f, 4.2f}}, white},
                               {{{-4.2f, 0.0f, -4.2f}, {-4.0f, 3.0f, 4.2f}}, white},
                               {{{4.0f, 0.0f, -4.2f}, {4.2f, 3.0f, 4.2f}}, white},
                               {{{-4.0f, 0.0f, -4.2f}, {4.0f, 3.0f, -4.0f}}, white},
                               {{{-4.0f, 0.0f, 4.0f}, {4.0f, 3.0f, 4.2f}}, white}},
                              camera);
  auto ceilingVoxelsAboveAndBehind = [&](uint32_t surroundViewSize) {
    renderer::Renderer renderer(device(), room,
                                rendering({.sunViewSize = 0, .surroundViewSize = surroundViewSize,
                                           .overheadViewSize = 0, .viewsPerFrame = 2}));
    // Each face of the cube 6 times: each voxel has tested 6 random points of itself against the upward face (a
    // point above the ceiling's face, seen through it, lands up to 0.14 r nearer the zenith, r from it: in another
    // voxel, out there).
    renderFrames(renderer, room, 18);
    const auto occupied = testing::readOccupiedVoxels(device(), *renderer.giContext());
    uint32_t found = 0;
    for (int x = -6; x < 6; ++x)
      for (int z = 2; z < 14; ++z) found += occupied.count({x, 12, z}) == 1;
    return found;
  };
  EXPECT_EQ(ceilingVoxelsAboveAndBehind(64), 12u * 12u) << "of the ceiling's voxels above and behind the camera";
  EXPECT_EQ(ceilingVoxelsAboveAndBehind(0), 0u) << "the camera alone sees them";
}

// The view-projection of an extra view as a matrix.
glm::mat4 matrixOf(const ExtraView& view) { return glm::make_mat4(view.camera.viewProjection.data()); }
bool isOrthographic(const ExtraView& view) { return matrixOf(view)[3][3] == 1.0f && matrixOf(view)[2][3] == 0.0f; }

TEST_F(ExtraViews, takeTurnsWithinTheirBudgetSoThatEachIsGivenEquallyOften) {
  // The sun's view, six faces around the camera and a spot light's view: 8 views, 3 a frame. Over 8 frames (24
  // views) each is given exactly 3 times; never more than 3 a frame.
  SunlitWallBehindTheCamera wall;
  wall.scene.lights.push_back({.name = "spot", .type = renderer::LightType::Spot, .position = {0.0f, 2.5f, 0.0f},
                               .direction = {0.0f, -1.0f, 0.0f}});
  renderer::Renderer renderer(device(), wall.scene,
                              rendering({.sunViewSize = 32, .surroundViewSize = 16, .lightViewSize = 24,
                                         .overheadViewSize = 0, .viewsPerFrame = 3}));
  std::map<std::string, uint32_t> given;
  for (uint32_t frame = 0; frame < 8; ++frame) {
    renderFrames(renderer, wall.scene, 1);
    EXPECT_EQ(renderer.extraViews().size(), 3u);
    for (const ExtraView& view : renderer.extraViews()) {
      // Told apart by size, and the faces by where they look (the jitter moves them by less than a texel).
      std::string name = std::to_string(view.camera.width);
      if (view.camera.width == 16) {
        const glm::vec4 centre = glm::inverse(matrixOf(view)) * glm::vec4(0.0f, 0.0f, 0.5f, 1.0f);
        const glm::vec3 direction = glm::normalize(glm::vec3(centre) / centre.w - glm::vec3(0.0f, 1.6f, 0.0f));
        // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on " " + std::string&& here.
        name += ' ';
        for (int axis = 0; axis < 3; ++axis) name += std::to_string(int(std::round(direction[axis])));
      }
      ++given[name];
      EXPECT_EQ(isOrthographic(view), view.camera.width == 32) << name;
    }
  }
  EXPECT_EQ(given.size(), 8u);
  for (const auto& [name, count] : given) EXPECT_EQ(count, 3u) << name;
}

TEST_F(ExtraViews, theSunsTexelGridStaysFixedInTheWorldAsTheCameraMoves) {
  // The sun's view follows the camera in whole texels, and moves by a known fraction of a texel each render (its
  // jitter, shared/sampling.h's Halton points): a world point lands on the same spot within its texel whatever the
  // camera's position, once the jitter is taken out — the view does not shimmer as the camera moves.
  SunlitWallBehindTheCamera wall;
  renderer::Renderer renderer(device(), wall.scene,
                              rendering({.sunViewSize = 64, .surroundViewSize = 0, .lightViewSize = 0,
                                         .overheadViewSize = 0, .viewsPerFrame = 1}));
  const glm::vec3 point(1.3f, 0.7f, -2.9f);
  std::vector<glm::vec2> positionsInTexel;
  for (uint32_t render = 1; render <= 4; ++render) {
    renderer::Camera camera = wall.scene.cameras[0];
    camera.position += glm::vec3(0.37f, 0.11f, -0.53f) * float(render * render);
    camera.target += camera.position - wall.scene.cameras[0].position;
    renderer.render(renderer::evaluateAnimation(wall.scene, camera, 0.0f));
    ASSERT_EQ(renderer.extraViews().size(), 1u);
    const ExtraView& view = renderer.extraViews()[0];
    const glm::vec4 clip = matrixOf(view) * glm::vec4(point, 1.0f);
    const glm::vec2 pixel = shader::ssvgiNdcToPixel(glm::vec2(clip) / clip.w, glm::vec2(64.0f));
    // The jitter moves the image by (x right, y down) pixels.
    const glm::vec2 jitter = shader::halton23(render) - glm::vec2(0.5f);
    positionsInTexel.push_back(glm::fract(pixel - jitter));
  }
  for (const glm::vec2 position : positionsInTexel) {
    EXPECT_NEAR(position.x, positionsInTexel[0].x, 1e-3f);
    EXPECT_NEAR(position.y, positionsInTexel[0].y, 1e-3f);
  }
}

}  // namespace
}  // namespace ssvgi
