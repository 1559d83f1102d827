// The scene model's math (sun direction, bounds, animation), the closed-solid mesh builder, and the built-in scenes'
// geometry, checked on the CPU with a small ray caster.
#include "builtin_scenes.h"
#include "scene.h"
#include "scene_geometry.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace ssvgi::renderer {
namespace {

constexpr float kTolerance = 1e-4f;

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = kTolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

Scene builtin(const std::string& name, const BuiltinSceneOptions& options = {}) {
  std::optional<Scene> scene = makeBuiltinScene(name, options);
  if (!scene) throw std::runtime_error("no built-in scene " + name);
  return std::move(*scene);
}

// ---- A small CPU ray caster over a scene's world-space triangles (Möller–Trumbore). ----

struct WorldTriangle {
  glm::vec3 a, b, c;
  uint32_t material;
};

std::vector<WorldTriangle> worldTriangles(const Scene& scene) {
  std::vector<WorldTriangle> triangles;
  for (const Instance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    const auto corner = [&](size_t i) {
      return glm::vec3(instance.transform * glm::vec4(mesh.vertices[mesh.indices[i]].position, 1.0f));
    };
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      triangles.push_back({corner(i), corner(i + 1), corner(i + 2), mesh.material});
    }
  }
  return triangles;
}

struct RayHit {
  float distance;
  uint32_t material;
};

// The nearest triangle hit by the ray within (0, maxDistance], from either side.
std::optional<RayHit> firstHit(const std::vector<WorldTriangle>& triangles, const glm::vec3& origin,
                               const glm::vec3& direction, float maxDistance) {
  std::optional<RayHit> nearest;
  for (const WorldTriangle& triangle : triangles) {
    const glm::vec3 edge1 = triangle.b - triangle.a;
    const glm::vec3 edge2 = triangle.c - triangle.a;
    const glm::vec3 p = glm::cross(direction, edge2);
    const float determinant = glm::dot(edge1, p);
    if (std::abs(determinant) < 1e-12f) continue;
    const glm::vec3 toOrigin = origin - triangle.a;
    const float u = glm::dot(toOrigin, p) / determinant;
    if (u < 0.0f || u > 1.0f) continue;
    const glm::vec3 q = glm::cross(toOrigin, edge1);
    const float v = glm::dot(direction, q) / determinant;
    if (v < 0.0f || u + v > 1.0f) continue;
    const float distance = glm::dot(edge2, q) / determinant;
    if (distance > 1e-5f && distance <= maxDistance && (!nearest || distance < nearest->distance)) {
      nearest = RayHit{distance, triangle.material};
    }
  }
  return nearest;
}

std::optional<RayHit> firstHitTowards(const std::vector<WorldTriangle>& triangles, const glm::vec3& from,
                                      const glm::vec3& to) {
  return firstHit(triangles, from, glm::normalize(to - from), glm::length(to - from));
}

const Mesh& meshNamed(const Scene& scene, const std::string& name) {
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.name == name) return mesh;
  }
  throw std::runtime_error("no mesh " + name);
}

Bounds meshBounds(const Mesh& mesh) {
  Bounds bounds{glm::vec3(1e30f), glm::vec3(-1e30f)};
  for (const Vertex& vertex : mesh.vertices) {
    bounds.min = glm::min(bounds.min, vertex.position);
    bounds.max = glm::max(bounds.max, vertex.position);
  }
  return bounds;
}

size_t triangleCount(const Scene& scene) {
  size_t count = 0;
  for (const Instance& instance : scene.instances) count += scene.meshes[instance.mesh].indices.size() / 3;
  return count;
}

// ---- Sun, bounds, animation ----

TEST(SceneSun, azimuthTurnsFromPlusZTowardsPlusXAndElevationLiftsTowardsPlusY) {
  expectNear(sunDirection(0.0f, 0.0f), {0.0f, 0.0f, 1.0f});
  expectNear(sunDirection(90.0f, 0.0f), {1.0f, 0.0f, 0.0f});
  expectNear(sunDirection(180.0f, 45.0f), {0.0f, std::sqrt(0.5f), -std::sqrt(0.5f)});
  expectNear(sunDirection(37.0f, 90.0f), {0.0f, 1.0f, 0.0f});
  const float elevation = glm::radians(55.0f);
  const float azimuth = glm::radians(30.0f);
  expectNear(sunDirection(30.0f, 55.0f),
             {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)});
}

TEST(SceneBounds, coverEveryInstanceTransformedVertex) {
  Scene scene;
  Mesh mesh;
  mesh.vertices = {{.position = {-1.0f, 0.0f, 0.0f}}, {.position = {1.0f, 2.0f, 0.5f}}};
  scene.meshes.push_back(mesh);
  scene.instances.push_back({0, glm::mat4(1.0f)});
  scene.instances.push_back({0, glm::translate(glm::mat4(1.0f), {10.0f, 0.0f, -3.0f})});
  const Bounds bounds = worldBounds(scene);
  expectNear(bounds.min, {-1.0f, 0.0f, -3.0f});
  expectNear(bounds.max, {11.0f, 2.0f, 0.5f});
}

// Scene::giDetailScale follows the middle of the bounds' three extents: at least three 1 m probe spacings across it,
// the scene's centre no further from the viewpoint than 32 spacings.
TEST(SceneDetail, halvesTheGiDetailUntilThreeProbeSpacingsSpanTheMiddleExtent) {
  const auto scaleFor = [](glm::vec3 extent) {
    return giDetailScaleFor({glm::vec3(-1.0f), glm::vec3(-1.0f) + extent}, glm::vec3(-1.0f) + 0.5f * extent);
  };
  EXPECT_EQ(scaleFor({5.0f, 3.0f, 5.0f}), 1.0f);     // a room
  EXPECT_EQ(scaleFor({3.0f, 3.0f, 3.0f}), 1.0f);     // just three spacings
  EXPECT_EQ(scaleFor({2.9f, 2.9f, 2.9f}), 0.5f);
  EXPECT_EQ(scaleFor({2.0f, 2.0f, 2.0f}), 0.5f);     // a Cornell box
  EXPECT_EQ(scaleFor({80.0f, 0.3f, 80.0f}), 1.0f);   // a wide, flat scene: its middle extent is 80 m
  EXPECT_EQ(scaleFor({0.5f, 40.0f, 2.0f}), 0.5f);    // a thin tall wall: 2 m
  EXPECT_EQ(scaleFor({1.2f, 1.2f, 1.2f}), 0.25f);
  EXPECT_EQ(scaleFor({0.6f, 0.15f, 0.4f}), 0.125f);  // a tabletop: its middle extent is 0.4 m
  EXPECT_EQ(scaleFor({0.1f, 0.1f, 0.1f}), 0.0625f);  // no finer than a sixteenth
}

TEST(SceneDetail, aScaleFineEnoughForTheSceneIsNotTakenWhereItsCentreLiesBeyondThirtyTwoSpacingsOfTheViewpoint) {
  const Bounds tabletop{glm::vec3(-0.3f, 0.0f, -0.2f), glm::vec3(0.3f, 0.15f, 0.2f)};
  const glm::vec3 centre = 0.5f * (tabletop.min + tabletop.max);
  EXPECT_EQ(giDetailScaleFor(tabletop, centre + glm::vec3(0.0f, 0.0f, 4.0f)), 0.125f);  // 32 spacings of 0.125 m
  EXPECT_EQ(giDetailScaleFor(tabletop, centre + glm::vec3(0.0f, 0.0f, 4.1f)), 0.25f);
  EXPECT_EQ(giDetailScaleFor(tabletop, centre + glm::vec3(0.0f, 6.0f, 6.0f)), 0.5f);   // 8.5 m: within 16 m, not 8
  const Bounds cornellBox{glm::vec3(-1.0f), glm::vec3(1.0f)};
  EXPECT_EQ(giDetailScaleFor(cornellBox, glm::vec3(0.0f, 0.0f, 20.0f)), 1.0f);  // beyond 16 m: the tiers' sizes
}

Scene sceneWithAnimation() {
  Scene scene;
  scene.instances.push_back({0, glm::translate(glm::mat4(1.0f), {1.0f, 2.0f, 3.0f})});
  scene.cameraPath = {{0.0f, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, -1.0f}},
                      {2.0f, {4.0f, 1.0f, 0.0f}, {4.0f, 1.0f, -1.0f}},
                      {4.0f, {4.0f, 1.0f, 8.0f}, {4.0f, 1.0f, 7.0f}}};
  scene.movingObject = MovingObject{.instance = 0, .offset = {0.0f, 0.0f, 6.0f}, .period = 4.0f};
  scene.sun = {.enabled = true, .direction = {0.0f, 1.0f, 0.0f}, .illuminance = {5.0f, 4.0f, 3.0f}};
  return scene;
}

Camera baseCamera() {
  return {.name = "base",
          .position = {9.0f, 9.0f, 9.0f},
          .target = {0.0f, 0.0f, 0.0f},
          .verticalFov = 0.5f,
          .nearPlane = 0.2f};
}

TEST(SceneAnimation, cameraStaysAtBaseCameraWithoutPath) {
  Scene scene = sceneWithAnimation();
  scene.cameraPath.clear();
  const Camera camera = evaluateAnimation(scene, baseCamera(), 3.0f).camera;
  expectNear(camera.position, baseCamera().position);
  expectNear(camera.target, baseCamera().target);
}

TEST(SceneAnimation, cameraMovesLinearlyBetweenKeysAndKeepsLens) {
  const Scene scene = sceneWithAnimation();
  const Camera atKey = evaluateAnimation(scene, baseCamera(), 2.0f).camera;
  expectNear(atKey.position, {4.0f, 1.0f, 0.0f});
  const Camera between = evaluateAnimation(scene, baseCamera(), 3.0f).camera;
  expectNear(between.position, {4.0f, 1.0f, 4.0f});
  expectNear(between.target, {4.0f, 1.0f, 3.0f});
  EXPECT_FLOAT_EQ(between.verticalFov, 0.5f);
  EXPECT_FLOAT_EQ(between.nearPlane, 0.2f);
}

TEST(SceneAnimation, cameraPathLoopsAfterLastKey) {
  const Scene scene = sceneWithAnimation();
  expectNear(evaluateAnimation(scene, baseCamera(), 4.5f).camera.position, {1.0f, 1.0f, 0.0f});
  expectNear(evaluateAnimation(scene, baseCamera(), 9.0f).camera.position,
             evaluateAnimation(scene, baseCamera(), 1.0f).camera.position);
}

TEST(SceneAnimation, movingObjectStartsAtRestAndReachesOffsetAtHalfPeriod) {
  const Scene scene = sceneWithAnimation();
  const auto positionAt = [&](float seconds) {
    const std::optional<glm::mat4> transform = evaluateAnimation(scene, baseCamera(), seconds).movingObjectTransform;
    EXPECT_TRUE(transform.has_value());
    return glm::vec3((*transform)[3]);
  };
  expectNear(positionAt(0.0f), {1.0f, 2.0f, 3.0f});
  expectNear(positionAt(1.0f), {1.0f, 2.0f, 6.0f});
  expectNear(positionAt(2.0f), {1.0f, 2.0f, 9.0f});
  expectNear(positionAt(4.0f), {1.0f, 2.0f, 3.0f});
  Scene still = scene;
  still.movingObject.reset();
  EXPECT_FALSE(evaluateAnimation(still, baseCamera(), 1.0f).movingObjectTransform.has_value());
}

TEST(SceneAnimation, sunFollowsCycleAndKeepsIlluminance) {
  Scene scene = sceneWithAnimation();
  scene.sunCycle = SunCycle{.azimuthDegrees = 10.0f,
                            .elevationDegrees = 40.0f,
                            .azimuthDegreesPerSecond = 5.0f,
                            .elevationDegreesPerSecond = 1.0f};
  const Sun sun = evaluateAnimation(scene, baseCamera(), 4.0f).sun;
  expectNear(sun.direction, sunDirection(30.0f, 44.0f));
  expectNear(sun.illuminance, {5.0f, 4.0f, 3.0f});
  EXPECT_TRUE(sun.enabled);
}

TEST(SceneAnimation, sunStaysPutWithoutCycle) {
  const Scene scene = sceneWithAnimation();
  expectNear(evaluateAnimation(scene, baseCamera(), 7.0f).sun.direction, {0.0f, 1.0f, 0.0f});
}

// ---- The closed-solid mesh builder ----

// Every triangle of a convex solid faces away from the solid's centre, and its vertex normals match its winding.
void expectOutwardFlatFaces(const Mesh& mesh, const glm::vec3& center) {
  ASSERT_FALSE(mesh.indices.empty());
  for (size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vertex& a = mesh.vertices[mesh.indices[i]];
    const Vertex& b = mesh.vertices[mesh.indices[i + 1]];
    const Vertex& c = mesh.vertices[mesh.indices[i + 2]];
    const glm::vec3 windingNormal = glm::normalize(glm::cross(b.position - a.position, c.position - a.position));
    const glm::vec3 centroid = (a.position + b.position + c.position) / 3.0f;
    EXPECT_GT(glm::dot(windingNormal, centroid - center), 0.0f) << "triangle " << i / 3;
    for (const Vertex* corner : {&a, &b, &c}) EXPECT_GT(glm::dot(corner->normal, windingNormal), 0.999f);
  }
}

TEST(SceneGeometry, boxFacesPointOutOfTheBoxForAnyPlacement) {
  const glm::vec3 center(1.0f, 2.0f, 3.0f);
  MeshBuilder builder;
  builder.addBox(center, {0.5f, 2.0f, 4.0f}, glm::radians(30.0f));
  const Mesh mesh = std::move(builder).build("box", 0);
  EXPECT_EQ(mesh.indices.size(), 36u);
  expectOutwardFlatFaces(mesh, center);

  MeshBuilder corners;
  corners.addBox(glm::vec3(-1.0f, 0.0f, 2.0f), glm::vec3(3.0f, 0.25f, 2.5f));
  const Bounds bounds = meshBounds(std::move(corners).build("slab", 0));
  expectNear(bounds.min, {-1.0f, 0.0f, 2.0f});
  expectNear(bounds.max, {3.0f, 0.25f, 2.5f});
}

TEST(SceneGeometry, cylinderAndSphereFacesPointOutward) {
  MeshBuilder cylinder;
  cylinder.addCylinder({0.0f, -1.0f, 0.0f}, 0.5f, 2.0f, 12);
  expectOutwardFlatFaces(std::move(cylinder).build("cylinder", 0), glm::vec3(0.0f));
  MeshBuilder sphere;
  sphere.addSphere({2.0f, 0.0f, 0.0f}, 0.7f, 8, 16);
  expectOutwardFlatFaces(std::move(sphere).build("sphere", 0), {2.0f, 0.0f, 0.0f});
}

// ---- Every built-in scene, with and without its options ----

TEST(BuiltinScenes, listsTheEightScenesAndNothingElse) {
  EXPECT_EQ(builtinSceneNames(),
            (std::vector<std::string>{"cornell", "two-rooms", "dark-room", "courtyard", "gallery", "hall",
                                      "panel-room", "plane-point-light"}));
  EXPECT_FALSE(makeBuiltinScene("sponza").has_value());
}

class BuiltinSceneTest : public testing::TestWithParam<std::tuple<std::string, bool>> {
 protected:
  BuiltinSceneOptions options() const {
    const bool withOptions = std::get<1>(GetParam());
    return {.movingObject = withOptions, .sunCycle = withOptions};
  }
  Scene scene() const { return builtin(std::get<0>(GetParam()), options()); }
};

TEST_P(BuiltinSceneTest, isWellFormed) {
  const Scene scene = this->scene();
  EXPECT_EQ(scene.name, std::get<0>(GetParam()));
  ASSERT_FALSE(scene.instances.empty());
  ASSERT_FALSE(scene.cameras.empty());
  for (const Instance& instance : scene.instances) ASSERT_LT(instance.mesh, scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) {
    SCOPED_TRACE(mesh.name);
    ASSERT_LT(mesh.material, scene.materials.size());
    ASSERT_FALSE(mesh.indices.empty());
    ASSERT_EQ(mesh.indices.size() % 3, 0u);
    for (const uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertices.size());
    // Closed solids with outward faces enclose a positive volume (divergence theorem).
    float signedVolume = 0.0f;
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
      const Vertex& a = mesh.vertices[mesh.indices[i]];
      const Vertex& b = mesh.vertices[mesh.indices[i + 1]];
      const Vertex& c = mesh.vertices[mesh.indices[i + 2]];
      const glm::vec3 areaVector = glm::cross(b.position - a.position, c.position - a.position);
      ASSERT_GT(glm::length(areaVector), 1e-6f) << "degenerate triangle " << i / 3;
      const glm::vec3 windingNormal = glm::normalize(areaVector);
      for (const Vertex* corner : {&a, &b, &c}) {
        ASSERT_NEAR(glm::length(corner->normal), 1.0f, kTolerance);
        ASSERT_GT(glm::dot(corner->normal, windingNormal), 0.999f) << "triangle " << i / 3;
      }
      signedVolume += glm::dot(a.position, glm::cross(b.position, c.position)) / 6.0f;
    }
    EXPECT_GT(signedVolume, 0.0f);
  }
  for (const Material& material : scene.materials) {
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(material.baseColor, glm::vec3(0.0f))) &&
                glm::all(glm::lessThanEqual(material.baseColor, glm::vec3(1.0f))))
        << material.name;
    EXPECT_EQ(material.baseColorTexture, kNoTexture);
  }
  for (const LocalLight& light : scene.lights) {
    EXPECT_TRUE(glm::all(glm::greaterThan(light.intensity, glm::vec3(0.0f)))) << light.name;
    EXPECT_NEAR(glm::length(light.direction), 1.0f, kTolerance);
    EXPECT_LE(light.innerConeAngle, light.outerConeAngle);
  }
  for (const Camera& camera : scene.cameras) {
    EXPECT_GT(glm::length(camera.target - camera.position), 0.1f) << camera.name;
    EXPECT_GT(camera.verticalFov, 0.1f);
    EXPECT_LT(camera.verticalFov, glm::pi<float>());
  }
  for (size_t i = 1; i < scene.cameraPath.size(); ++i)
    EXPECT_GT(scene.cameraPath[i].time, scene.cameraPath[i - 1].time);
  if (scene.sun.enabled) {
    EXPECT_NEAR(glm::length(scene.sun.direction), 1.0f, kTolerance);
  }
}

TEST_P(BuiltinSceneTest, optionsAddMovingObjectWithOwnMeshAndSunCycleWhereThereIsASun) {
  const Scene scene = this->scene();
  EXPECT_EQ(scene.movingObject.has_value(), options().movingObject);
  EXPECT_EQ(scene.sunCycle.has_value(), options().sunCycle && scene.sun.enabled);
  if (!scene.movingObject) return;
  ASSERT_LT(scene.movingObject->instance, scene.instances.size());
  const uint32_t movingMesh = scene.instances[scene.movingObject->instance].mesh;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    if (i != scene.movingObject->instance) {
      EXPECT_NE(scene.instances[i].mesh, movingMesh);
    }
  }
  EXPECT_GT(glm::length(scene.movingObject->offset), 0.5f);
  EXPECT_GT(scene.movingObject->period, 0.0f);
  const Bounds size = meshBounds(scene.meshes[movingMesh]);
  const float extent = glm::length(size.max - size.min) / std::sqrt(3.0f);
  EXPECT_GE(extent, 0.45f);
  EXPECT_LE(extent, 1.05f);
}

TEST_P(BuiltinSceneTest, mergesStaticGeometryIntoOneMeshPerMaterial) {
  const Scene scene = this->scene();
  std::vector<int> meshesPerMaterial(scene.materials.size(), 0);
  for (const Mesh& mesh : scene.meshes) ++meshesPerMaterial[mesh.material];
  for (size_t material = 0; material < scene.materials.size(); ++material) {
    EXPECT_LE(meshesPerMaterial[material], 1) << scene.materials[material].name;
  }
}

INSTANTIATE_TEST_SUITE_P(Builtin, BuiltinSceneTest,
                         testing::Combine(testing::ValuesIn(builtinSceneNames()), testing::Bool()),
                         [](const testing::TestParamInfo<BuiltinSceneTest::ParamType>& param) {
                           std::string name = std::get<0>(param.param) + (std::get<1>(param.param) ? "_options" : "");
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

// ---- Scene by scene ----

uint32_t materialIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (scene.materials[i].name == name) return static_cast<uint32_t>(i);
  }
  throw std::runtime_error("no material " + name);
}

TEST(BuiltinCornell, leftWallIsRedAndRightWallIsGreen) {
  const Scene scene = builtin("cornell");
  const auto triangles = worldTriangles(scene);
  // Above the tall box, so the ray sees the walls.
  const glm::vec3 middle(0.0f, 1.5f, 0.0f);
  const auto left = firstHit(triangles, middle, {-1.0f, 0.0f, 0.0f}, 10.0f);
  const auto right = firstHit(triangles, middle, {1.0f, 0.0f, 0.0f}, 10.0f);
  ASSERT_TRUE(left && right);
  EXPECT_NEAR(left->distance, 1.0f, kTolerance);
  EXPECT_NEAR(right->distance, 1.0f, kTolerance);
  expectNear(scene.materials[left->material].baseColor, {0.63f, 0.065f, 0.05f});
  expectNear(scene.materials[right->material].baseColor, {0.14f, 0.45f, 0.09f});
  EXPECT_EQ(scene.sky.kind, SkyKind::None);
  EXPECT_FALSE(scene.sun.enabled);
  EXPECT_EQ(scene.giDetailScale, 0.5f);  // a 2.2 m box: 0.125 m voxels and 0.5 m probes at every tier
}

TEST(BuiltinCornell, shadowedPointLightHangsJustBelowTheGlowingPanel) {
  const Scene scene = builtin("cornell");
  ASSERT_EQ(scene.lights.size(), 1u);
  const LocalLight& light = scene.lights[0];
  EXPECT_EQ(light.type, LightType::Point);
  EXPECT_TRUE(light.castsShadow);
  const auto above = firstHit(worldTriangles(scene), light.position, {0.0f, 1.0f, 0.0f}, 1.0f);
  ASSERT_TRUE(above.has_value());
  EXPECT_LT(above->distance, 0.2f);
  EXPECT_GT(glm::length(scene.materials[above->material].emission), 1.0f);
}

TEST(BuiltinTwoRooms, everySegmentFromTheLitRoomsLightsIntoTheDarkRoomIsBlocked) {
  const Scene scene = builtin("two-rooms", {.movingObject = true});
  const auto triangles = worldTriangles(scene);
  ASSERT_FALSE(scene.lights.empty());
  int segments = 0;
  for (const LocalLight& light : scene.lights) {
    ASSERT_LT(light.position.x, -0.125f) << light.name;
    // A grid over the dark room's interior x∈[0.125,6.125], y∈[0,3], z∈[−3,3], a little inside its walls.
    for (float x = 0.2f; x < 6.1f; x += 0.7f) {
      for (float y = 0.05f; y < 3.0f; y += 0.35f) {
        for (float z = -2.95f; z < 3.0f; z += 0.45f) {
          const glm::vec3 point(x, y, z);
          EXPECT_TRUE(firstHitTowards(triangles, light.position, point).has_value())
              << light.name << " reaches " << x << ", " << y << ", " << z;
          ++segments;
        }
      }
    }
  }
  EXPECT_GT(segments, 1000);
}

TEST(BuiltinTwoRooms, sharedWallAndDoorAreAQuarterMetreThick) {
  const Scene scene = builtin("two-rooms");
  const auto triangles = worldTriangles(scene);
  // Through the door, beside it and above it.
  for (const glm::vec2 yz :
       {glm::vec2(1.0f, 0.0f), glm::vec2(1.5f, 2.0f), glm::vec2(2.5f, 0.0f), glm::vec2(1.0f, -2.5f)}) {
    const auto fromLit = firstHit(triangles, {-1.0f, yz.x, yz.y}, {1.0f, 0.0f, 0.0f}, 2.0f);
    const auto fromDark = firstHit(triangles, {1.0f, yz.x, yz.y}, {-1.0f, 0.0f, 0.0f}, 2.0f);
    ASSERT_TRUE(fromLit && fromDark);
    const float thickness = (1.0f - fromDark->distance) - (-1.0f + fromLit->distance);
    EXPECT_NEAR(thickness, 0.25f, kTolerance) << "at y " << yz.x << ", z " << yz.y;
  }
  const auto door = firstHit(triangles, {-1.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 2.0f);
  EXPECT_EQ(scene.materials[door->material].name, "door");
}

TEST(BuiltinTwoRooms, firstCameraIsInTheLitRoomAndSecondLooksAtTheSharedWallFromTheDarkRoom) {
  const Scene scene = builtin("two-rooms");
  ASSERT_GE(scene.cameras.size(), 2u);
  EXPECT_LT(scene.cameras[0].position.x, -0.125f);
  EXPECT_GT(scene.cameras[1].position.x, 0.125f);
  const glm::vec3 view = scene.cameras[1].target - scene.cameras[1].position;
  const auto wall = firstHit(worldTriangles(scene), scene.cameras[1].position, glm::normalize(view), 20.0f);
  ASSERT_TRUE(wall.has_value());
  const glm::vec3 seen = scene.cameras[1].position + glm::normalize(view) * wall->distance;
  EXPECT_NEAR(seen.x, 0.125f, kTolerance);
  EXPECT_EQ(scene.sky.kind, SkyKind::None);
  EXPECT_FALSE(scene.sun.enabled);
}

TEST(BuiltinDarkRoom, sunLightsTheFloorOnlyThroughTheSkylight) {
  const Scene scene = builtin("dark-room");
  ASSERT_TRUE(scene.sun.enabled);
  EXPECT_EQ(scene.sky.kind, SkyKind::Default);
  const auto triangles = worldTriangles(scene);
  // Sample the floor (x, z ∈ [−4, 4]) on a 5 cm grid and add up the area the sun reaches.
  constexpr float step = 0.05f;
  float litArea = 0.0f;
  for (float x = -4.0f + 0.5f * step; x < 4.0f; x += step) {
    for (float z = -4.0f + 0.5f * step; z < 4.0f; z += step) {
      if (!firstHit(triangles, {x, 1e-3f, z}, scene.sun.direction, 1000.0f)) litArea += step * step;
    }
  }
  // A 1 m² skylight in a 0.25 m thick roof passes a little less than 1 m² of sunlight.
  EXPECT_GT(litArea, 0.6f);
  EXPECT_LT(litArea, 1.0f);
  const glm::vec3 camera = scene.cameras[0].position;
  EXPECT_TRUE(std::abs(camera.x) < 4.0f && camera.y > 0.0f && camera.y < 4.0f && std::abs(camera.z) < 4.0f);
}

TEST(BuiltinCourtyard, spansAtLeast120MetresWithFewerThan100kTriangles) {
  const Scene scene = builtin("courtyard", {.movingObject = true});
  const Bounds bounds = worldBounds(scene);
  EXPECT_GE(bounds.max.x - bounds.min.x, 120.0f);
  EXPECT_GE(bounds.max.z - bounds.min.z, 120.0f);
  EXPECT_LT(triangleCount(scene), 100000u);
  EXPECT_TRUE(scene.sun.enabled);
  EXPECT_EQ(scene.sky.kind, SkyKind::Default);
  EXPECT_GE(scene.cameraPath.size(), 3u);
}

TEST(BuiltinCourtyard, firstCameraStandsInTheOpenCourtAtEyeHeightLookingAlongIt) {
  const Scene scene = builtin("courtyard");
  const Camera& camera = scene.cameras[0];
  EXPECT_LT(std::abs(camera.position.x), 18.0f);
  EXPECT_LT(std::abs(camera.position.z), 8.0f);
  EXPECT_NEAR(camera.position.y, 1.7f, 0.1f);
  const glm::vec3 view = glm::normalize(camera.target - camera.position);
  EXPECT_GT(std::abs(view.x), 0.9f);
  // Open roof: straight up from the camera is sky.
  const auto triangles = worldTriangles(scene);
  EXPECT_FALSE(firstHit(triangles, camera.position, {0.0f, 1.0f, 0.0f}, 1000.0f).has_value());
  // And the sun reaches the middle of the court's floor north of the fountain.
  EXPECT_FALSE(firstHit(triangles, {0.0f, 0.01f, -5.0f}, scene.sun.direction, 1000.0f).has_value());
}

TEST(BuiltinCourtyard, colonnadesCarryBannersInFourColours) {
  const Scene scene = builtin("courtyard");
  for (const char* banner : {"banner red", "banner green", "banner blue", "banner yellow"}) {
    const Mesh& mesh = meshNamed(scene, banner);
    EXPECT_GE(mesh.indices.size(), 36u) << banner;
  }
  // Two storeys of columns: rays along the court's long side at both storeys' column height hit marble.
  const auto triangles = worldTriangles(scene);
  for (const float height : {2.0f, 8.5f}) {
    const auto hit = firstHit(triangles, {-16.0f, height, 8.0f}, {1.0f, 0.0f, 0.0f}, 10.0f);
    ASSERT_TRUE(hit.has_value()) << "at height " << height;
    EXPECT_EQ(hit->material, materialIndex(scene, "marble"));
  }
}

TEST(BuiltinPlanePointLight, geometryLightAndCameraAreAsDocumented) {
  const Scene scene = builtin("plane-point-light");
  const Bounds plane = meshBounds(meshNamed(scene, "plane"));
  expectNear(plane.min, {-10.0f, -0.1f, -10.0f});
  expectNear(plane.max, {10.0f, 0.0f, 10.0f});
  const Bounds occluder = meshBounds(meshNamed(scene, "occluder"));
  expectNear(occluder.min, {2.75f, 0.75f, -0.25f});
  expectNear(occluder.max, {3.25f, 1.25f, 0.25f});
  for (const Material& material : scene.materials) expectNear(material.baseColor, glm::vec3(0.8f));
  for (const Instance& instance : scene.instances) EXPECT_EQ(instance.transform, glm::mat4(1.0f));

  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.lights[0].type, LightType::Point);
  EXPECT_TRUE(scene.lights[0].castsShadow);
  expectNear(scene.lights[0].position, {0.0f, 2.0f, 0.0f});
  expectNear(scene.lights[0].intensity, glm::vec3(10.0f));
  EXPECT_EQ(scene.lights[0].range, 0.0f);
  EXPECT_EQ(scene.sky.kind, SkyKind::None);
  EXPECT_FALSE(scene.sun.enabled);

  ASSERT_EQ(scene.cameras.size(), 1u);
  expectNear(scene.cameras[0].position, {0.0f, 6.0f, 6.0f});
  expectNear(scene.cameras[0].target, glm::vec3(0.0f));
  EXPECT_NEAR(scene.cameras[0].verticalFov, glm::radians(60.0f), kTolerance);
}

TEST(BuiltinPlanePointLight, occluderShadowsThePlaneBehindIt) {
  const Scene scene = builtin("plane-point-light");
  const auto triangles = worldTriangles(scene);
  const glm::vec3 light = scene.lights[0].position;
  // (6, 0, 0) lies on the line from the light through the occluder's centre; (−6, 0, 0) mirrors it.
  const auto shadowed = firstHitTowards(triangles, light, {6.0f, 0.0f, 0.0f});
  ASSERT_TRUE(shadowed.has_value());
  EXPECT_EQ(shadowed->material, materialIndex(scene, "occluder"));
  const auto lit = firstHit(triangles, light, glm::normalize(glm::vec3(-6.0f, -2.0f, 0.0f)), 100.0f);
  ASSERT_TRUE(lit.has_value());
  EXPECT_EQ(lit->material, materialIndex(scene, "plane"));
  EXPECT_NEAR(lit->distance, std::sqrt(40.0f), kTolerance);
}

}  // namespace
}  // namespace ssvgi::renderer
