#include "builtin_scenes.h"

#include "scene_geometry.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <initializer_list>
#include <utility>

namespace ssvgi::renderer {

namespace {

// A time-lapse day: with BuiltinSceneOptions::sunCycle the sun circles the sky once a minute at its elevation, so the
// light keeps entering the scenes' openings while every wall in turn falls into shadow.
constexpr float kSunCycleDegreesPerSecond = 6.0f;

// Collects a scene's materials, with all static geometry of one material merged into one mesh (one draw per
// material), and the moving object as a mesh and instance of its own.
class SceneAssembly {
 public:
  explicit SceneAssembly(std::string name) { scene_.name = std::move(name); }

  Scene& scene() { return scene_; }

  // A new material and the builder for its static geometry. The reference stays valid while more are added.
  MeshBuilder& material(std::string name, const glm::vec3& baseColor, const glm::vec3& emission = glm::vec3(0.0f)) {
    scene_.materials.push_back({.name = std::move(name), .baseColor = baseColor, .emission = emission});
    return staticGeometry_.emplace_back();
  }

  void addCamera(std::string name, const glm::vec3& position, const glm::vec3& target, float verticalFovDegrees) {
    scene_.cameras.push_back({.name = std::move(name),
                              .position = position,
                              .target = target,
                              .verticalFov = glm::radians(verticalFovDegrees)});
  }

  // A camera path visiting the poses (position, target) in order, `secondsPerLeg` apart, and returning to the first.
  void setCameraLoop(std::initializer_list<std::pair<glm::vec3, glm::vec3>> poses, float secondsPerLeg) {
    float time = 0.0f;
    for (const auto& [position, target] : poses) {
      scene_.cameraPath.push_back({.time = time, .position = position, .target = target});
      time += secondsPerLeg;
    }
    CameraKey closing = scene_.cameraPath.front();
    closing.time = time;
    scene_.cameraPath.push_back(closing);
  }

  void setSun(float azimuthDegrees, float elevationDegrees, const glm::vec3& illuminance,
              const BuiltinSceneOptions& options) {
    scene_.sun = {
        .enabled = true, .direction = sunDirection(azimuthDegrees, elevationDegrees), .illuminance = illuminance};
    if (options.sunCycle) {
      scene_.sunCycle = SunCycle{.azimuthDegrees = azimuthDegrees,
                                 .elevationDegrees = elevationDegrees,
                                 .azimuthDegreesPerSecond = kSunCycleDegreesPerSecond};
    }
  }

  // The moving object: `shape` is built around the origin and placed at `restPosition`; it travels to
  // restPosition + offset and back once per `period` seconds.
  void setMovingObject(MeshBuilder shape, const glm::vec3& baseColor, const glm::vec3& restPosition,
                       const glm::vec3& offset, float period) {
    scene_.materials.push_back({.name = "moving object", .baseColor = baseColor});
    staticGeometry_.emplace_back();  // stays empty: no static geometry uses this material
    movingMaterial_ = static_cast<uint32_t>(scene_.materials.size() - 1);
    movingShape_ = std::move(shape);
    movingPlacement_ = glm::translate(glm::mat4(1.0f), restPosition);
    movingMotion_ = MovingObject{.offset = offset, .period = period};
  }

  Scene finish() && {
    for (size_t material = 0; material < staticGeometry_.size(); ++material) {
      if (staticGeometry_[material].empty()) continue;
      addInstancedMesh(std::move(staticGeometry_[material]), static_cast<uint32_t>(material), glm::mat4(1.0f));
    }
    if (movingMotion_) {
      movingMotion_->instance = addInstancedMesh(std::move(movingShape_), movingMaterial_, movingPlacement_);
      scene_.movingObject = movingMotion_;
    }
    scene_.giDetailScale = giDetailScaleFor(worldBounds(scene_), scene_.cameras.at(0).position);
    return std::move(scene_);
  }

 private:
  uint32_t addInstancedMesh(MeshBuilder&& geometry, uint32_t material, const glm::mat4& transform) {
    scene_.meshes.push_back(std::move(geometry).build(scene_.materials[material].name, material));
    scene_.instances.push_back({.mesh = static_cast<uint32_t>(scene_.meshes.size() - 1), .transform = transform});
    return static_cast<uint32_t>(scene_.instances.size() - 1);
  }

  Scene scene_;
  std::deque<MeshBuilder> staticGeometry_;  // one per material, same index
  MeshBuilder movingShape_;
  uint32_t movingMaterial_ = 0;
  glm::mat4 movingPlacement_{1.0f};
  std::optional<MovingObject> movingMotion_;
};

MeshBuilder sphereShape(float radius) {
  MeshBuilder shape;
  shape.addSphere(glm::vec3(0.0f), radius, 12, 24);
  return shape;
}

MeshBuilder cubeShape(float size) {
  MeshBuilder shape;
  shape.addBox(glm::vec3(0.0f), glm::vec3(size), 0.0f);
  return shape;
}

// A horizontal slab from `low` to `high` with a rectangular opening through it (a skylight, an open court), built as
// four boxes around the opening so that its edges are closed walls too.
void addSlabWithOpening(MeshBuilder& builder, const glm::vec3& low, const glm::vec3& high, const glm::vec2& openingLow,
                        const glm::vec2& openingHigh) {
  builder.addBox(low, {openingLow.x, high.y, high.z});
  builder.addBox({openingHigh.x, low.y, low.z}, high);
  builder.addBox({openingLow.x, low.y, low.z}, {openingHigh.x, high.y, openingLow.y});
  builder.addBox({openingLow.x, low.y, openingHigh.y}, {openingHigh.x, high.y, high.z});
}

// The classic Cornell box scaled to a 2 m cube: interior x∈[−1,1], y∈[0,2], z∈[−1,1], open towards +z, 0.1 m walls.
// The ceiling panel glows, and a point light just below it gives direct light when emissive surfaces light others
// only through GI.
Scene makeCornell(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("cornell");
  MeshBuilder& white = assembly.material("white", {0.725f, 0.71f, 0.68f});
  MeshBuilder& red = assembly.material("red", {0.63f, 0.065f, 0.05f});
  MeshBuilder& green = assembly.material("green", {0.14f, 0.45f, 0.09f});
  // The ceiling light is one luminaire: an emissive panel, and a point light just below it standing in for the
  // illumination of the area light the renderer does not have. The panel reflects nothing (albedo 0): lit by that
  // point light 8 cm away it would glow with a 10 cm hot spot of ~120 W/(sr·m²), fourteen times its own emission —
  // light the luminaire does not give, and detail far below the GI's voxel (it alone made half of the probes' error
  // against the reference, docs/QUALITY.md).
  MeshBuilder& panel = assembly.material("light", {0.0f, 0.0f, 0.0f}, glm::vec3(17.0f, 12.0f, 4.0f) * 0.5f);

  constexpr float wall = 0.1f;
  white.addBox({-1.0f - wall, -wall, -1.0f - wall}, {1.0f + wall, 0.0f, 1.0f});        // floor
  white.addBox({-1.0f - wall, 2.0f, -1.0f - wall}, {1.0f + wall, 2.0f + wall, 1.0f});  // ceiling
  white.addBox({-1.0f, 0.0f, -1.0f - wall}, {1.0f, 2.0f, -1.0f});                      // back wall
  red.addBox({-1.0f - wall, 0.0f, -1.0f - wall}, {-1.0f, 2.0f, 1.0f});                 // left wall
  green.addBox({1.0f, 0.0f, -1.0f - wall}, {1.0f + wall, 2.0f, 1.0f});                 // right wall
  white.addBox({-0.335f, 0.6f, -0.29f}, {0.6f, 1.2f, 0.6f}, glm::radians(17.0f));      // tall box
  white.addBox({0.325f, 0.3f, 0.375f}, {0.6f, 0.6f, 0.6f}, glm::radians(-17.0f));      // short box
  panel.addBox({-0.25f, 1.98f, -0.2f}, {0.25f, 2.0f, 0.2f});

  assembly.scene().lights.push_back({.name = "ceiling", .position = {0.0f, 1.9f, 0.0f}, .intensity = glm::vec3(3.0f)});
  assembly.addCamera("front", {0.0f, 1.0f, 3.4f}, {0.0f, 1.0f, 0.0f}, 40.0f);
  assembly.setCameraLoop({{{0.0f, 1.0f, 3.4f}, {0.0f, 1.0f, 0.0f}},
                          {{0.6f, 1.3f, 3.0f}, {0.0f, 0.9f, 0.0f}},
                          {{-0.6f, 0.8f, 3.0f}, {0.0f, 1.1f, 0.0f}}},
                         4.0f);
  if (options.movingObject) {
    // Floats over both boxes from left to right.
    assembly.setMovingObject(sphereShape(0.25f), {0.2f, 0.3f, 0.8f}, {-0.6f, 1.5f, 0.3f}, {1.2f, 0.0f, 0.0f}, 4.0f);
  }
  return std::move(assembly).finish();
}

// Two closed rooms, interior 6×3×6 m each (y∈[0,3], z∈[−3,3]): the lit room x∈[−6.125,−0.125] and the dark room
// x∈[0.125,6.125], sharing a 0.25 m wall (x∈[−0.125,0.125]) whose 1×2.1 m doorway (z∈[−0.5,0.5]) is closed by a
// door filling it exactly. All other walls, the floor and the ceiling are 0.25 m thick too. The leak test: no light
// path leads from the lit room into the dark one.
Scene makeTwoRooms(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("two-rooms");
  MeshBuilder& white = assembly.material("white", {0.8f, 0.8f, 0.78f});
  MeshBuilder& door = assembly.material("door", {0.45f, 0.3f, 0.18f});
  MeshBuilder& red = assembly.material("red", {0.7f, 0.08f, 0.06f});
  MeshBuilder& blue = assembly.material("blue", {0.08f, 0.15f, 0.6f});
  MeshBuilder& yellow = assembly.material("yellow", {0.8f, 0.65f, 0.1f});
  MeshBuilder& green = assembly.material("green", {0.1f, 0.5f, 0.12f});

  constexpr float wall = 0.25f;
  constexpr float halfShared = wall / 2.0f;
  constexpr float outerX = 6.125f;  // inner face of the outer side walls
  constexpr float halfDepth = 3.0f;
  constexpr float height = 3.0f;
  constexpr float doorHalfWidth = 0.5f;
  constexpr float doorHeight = 2.1f;

  // Floor and ceiling, the lit and the dark room's end walls, the back and the front wall.
  white.addBox({-outerX - wall, -wall, -halfDepth - wall}, {outerX + wall, 0.0f, halfDepth + wall});
  white.addBox({-outerX - wall, height, -halfDepth - wall}, {outerX + wall, height + wall, halfDepth + wall});
  white.addBox({-outerX - wall, 0.0f, -halfDepth - wall}, {-outerX, height, halfDepth + wall});
  white.addBox({outerX, 0.0f, -halfDepth - wall}, {outerX + wall, height, halfDepth + wall});
  white.addBox({-outerX, 0.0f, -halfDepth - wall}, {outerX, height, -halfDepth});
  white.addBox({-outerX, 0.0f, halfDepth}, {outerX, height, halfDepth + wall});
  // The shared wall around its doorway, and the door.
  white.addBox({-halfShared, 0.0f, -halfDepth}, {halfShared, height, -doorHalfWidth});
  white.addBox({-halfShared, 0.0f, doorHalfWidth}, {halfShared, height, halfDepth});
  white.addBox({-halfShared, doorHeight, -doorHalfWidth}, {halfShared, height, doorHalfWidth});
  door.addBox({-halfShared, 0.0f, -doorHalfWidth}, {halfShared, doorHeight, doorHalfWidth});

  // Furniture in the lit room.
  red.addBox({-4.5f, 0.5f, -1.5f}, glm::vec3(1.0f), glm::radians(20.0f));
  blue.addBox({-2.0f, 0.75f, 1.8f}, {0.8f, 1.5f, 0.8f}, glm::radians(-10.0f));
  yellow.addCylinder({-1.5f, 0.0f, -2.0f}, 0.4f, 1.0f, 16);
  // And in the dark room, to receive whatever leaks.
  green.addBox({3.0f, 0.5f, -1.5f}, glm::vec3(1.0f), glm::radians(15.0f));
  white.addSphere({2.0f, 0.5f, 1.5f}, 0.5f, 12, 24);

  assembly.scene().lights.push_back(
      {.name = "ceiling", .position = {-3.125f, 2.6f, 0.0f}, .intensity = glm::vec3(15.0f)});
  // A spot on the door, so that the wall that must not leak is brightly lit.
  const glm::vec3 spotPosition(-5.0f, 2.6f, 2.0f);
  assembly.scene().lights.push_back({.name = "door spot",
                                     .type = LightType::Spot,
                                     .position = spotPosition,
                                     .direction = glm::normalize(glm::vec3(-halfShared, 1.0f, 0.0f) - spotPosition),
                                     .intensity = {40.0f, 36.0f, 30.0f},
                                     .innerConeAngle = glm::radians(20.0f),
                                     .outerConeAngle = glm::radians(30.0f)});

  assembly.addCamera("lit room", {-5.6f, 1.6f, 2.6f}, {-0.5f, 1.2f, -0.5f}, 60.0f);
  assembly.addCamera("dark room", {5.6f, 1.6f, 2.6f}, {halfShared, 1.2f, 0.0f}, 60.0f);
  assembly.setCameraLoop({{{-5.5f, 1.6f, 2.5f}, {-0.5f, 1.2f, -0.5f}},
                          {{-2.5f, 1.6f, 0.8f}, {-4.0f, 1.2f, -2.0f}},
                          {{-5.5f, 1.6f, -2.5f}, {-1.0f, 1.2f, 1.0f}}},
                         5.0f);
  if (options.movingObject) {
    // Slides across the lit room between the furniture.
    assembly.setMovingObject(cubeShape(0.6f), {0.9f, 0.5f, 0.2f}, {-4.5f, 0.3f, 0.5f}, {3.0f, 0.0f, 0.0f}, 6.0f);
  }
  return std::move(assembly).finish();
}

// A closed room, interior x∈[−4,4], y∈[0,4], z∈[−4,4] with 0.25 m walls, lit only by the sun and sky through a 1×1 m
// skylight (x∈[0.5,1.5], z∈[1,2]) in its roof. Outside: a 160×160 m ground plane 0.1 m below the room's floor.
Scene makeDarkRoom(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("dark-room");
  MeshBuilder& white = assembly.material("white", {0.75f, 0.75f, 0.72f});
  MeshBuilder& ground = assembly.material("ground", {0.35f, 0.33f, 0.28f});
  MeshBuilder& red = assembly.material("red", {0.7f, 0.08f, 0.06f});
  MeshBuilder& blue = assembly.material("blue", {0.08f, 0.15f, 0.6f});
  MeshBuilder& yellow = assembly.material("yellow", {0.8f, 0.65f, 0.1f});

  constexpr float wall = 0.25f;
  constexpr float half = 4.0f;
  constexpr float height = 4.0f;
  ground.addBox({-80.0f, -0.6f, -80.0f}, {80.0f, -0.1f, 80.0f});
  white.addBox({-half - wall, -0.1f, -half - wall}, {half + wall, 0.0f, half + wall});  // floor
  white.addBox({-half - wall, 0.0f, -half - wall}, {-half, height, half + wall});
  white.addBox({half, 0.0f, -half - wall}, {half + wall, height, half + wall});
  white.addBox({-half, 0.0f, -half - wall}, {half, height, -half});
  white.addBox({-half, 0.0f, half}, {half, height, half + wall});
  addSlabWithOpening(white, {-half - wall, height, -half - wall}, {half + wall, height + wall, half + wall},
                     {0.5f, 1.0f}, {1.5f, 2.0f});

  red.addBox({-2.0f, 0.5f, -2.0f}, glm::vec3(1.0f), glm::radians(10.0f));
  blue.addBox({2.5f, 1.0f, -2.5f}, {0.8f, 2.0f, 0.8f}, 0.0f);
  yellow.addCylinder({2.0f, 0.0f, 1.0f}, 0.35f, 1.2f, 16);

  // At 30° azimuth and 60° elevation the beam through the skylight lands near the middle of the floor.
  assembly.setSun(30.0f, 60.0f, {7.0f, 6.6f, 6.0f}, options);
  assembly.scene().sky.kind = SkyKind::Default;

  assembly.addCamera("inside", {-3.5f, 1.6f, 3.5f}, {0.0f, 0.8f, -1.0f}, 60.0f);
  assembly.setCameraLoop({{{-3.5f, 1.6f, 3.5f}, {0.0f, 0.8f, -1.0f}},
                          {{3.3f, 1.6f, 3.3f}, {-0.5f, 0.8f, -0.5f}},
                          {{3.3f, 2.5f, -3.3f}, {-0.5f, 0.5f, 0.5f}}},
                         6.0f);
  if (options.movingObject) {
    // Rolls through the sun patch on the floor.
    assembly.setMovingObject(sphereShape(0.4f), {0.9f, 0.9f, 0.9f}, {-1.5f, 0.4f, -0.5f}, {2.5f, 0.0f, 0.0f}, 6.0f);
  }
  return std::move(assembly).finish();
}

// The courtyard's layout. A Sponza-sized atrium: the open court x∈[−18,18], z∈[−8,8] is framed by a closed loop of
// columns 4 m apart on its edge, carrying arcades on two storeys; 4 m deep galleries run behind them, closed by the
// building's outer walls (inner faces x = ±22, z = ±12). The roof over the galleries stops at the court: the court is
// open to the sky.
constexpr float kCourtHalfX = 18.0f;
constexpr float kCourtHalfZ = 8.0f;
constexpr float kColumnSpacing = 4.0f;
constexpr float kGalleryDepth = 4.0f;
constexpr float kOuterWall = 0.5f;
constexpr float kArcadeThickness = 0.6f;
constexpr float kCapitalSize = 0.8f;  // width of a column's plinth and capital
constexpr float kBlockHeight = 0.3f;  // height of a plinth or capital
constexpr float kColumnRadius = 0.3f;
constexpr float kSlabThickness = 0.4f;
constexpr float kLedge = 0.5f;  // how far the slabs reach past the column line into the court

struct Storey {
  float floorY;     // top of the floor the columns stand on
  float ceilingY;   // underside of the slab above
  bool balustrade;  // a parapet between the columns (the upper gallery)
};

// The column centres around the court's edge in order, each bay running from one to the next (and the last back to
// the first).
std::vector<glm::vec2> courtColumnLine() {
  std::vector<glm::vec2> line;
  const auto walk = [&](glm::vec2 from, glm::vec2 step, int count) {
    for (int i = 0; i < count; ++i) line.push_back(from + step * static_cast<float>(i));
  };
  const int alongX = static_cast<int>(2.0f * kCourtHalfX / kColumnSpacing);
  const int alongZ = static_cast<int>(2.0f * kCourtHalfZ / kColumnSpacing);
  walk({-kCourtHalfX, -kCourtHalfZ}, {kColumnSpacing, 0.0f}, alongX);
  walk({kCourtHalfX, -kCourtHalfZ}, {0.0f, kColumnSpacing}, alongZ);
  walk({kCourtHalfX, kCourtHalfZ}, {-kColumnSpacing, 0.0f}, alongX);
  walk({-kCourtHalfX, kCourtHalfZ}, {0.0f, -kColumnSpacing}, alongZ);
  return line;
}

// A box spanning the bay from `along0` to `along1` metres past `start` in direction `along`, `thickness` across it,
// between heights `low` and `high`. Bays run along x or z, so the box stays axis-aligned.
void addBayBox(MeshBuilder& builder, const glm::vec2& start, const glm::vec2& along, float along0, float along1,
               float thickness, float low, float high) {
  const glm::vec2 across(-along.y, along.x);
  const glm::vec2 corner0 = start + along * along0 - across * (0.5f * thickness);
  const glm::vec2 corner1 = start + along * along1 + across * (0.5f * thickness);
  const glm::vec2 lowXZ = glm::min(corner0, corner1);
  const glm::vec2 highXZ = glm::max(corner0, corner1);
  builder.addBox({lowXZ.x, low, lowXZ.y}, {highXZ.x, high, highXZ.y});
}

// One storey of the arcade: a column (plinth, shaft, capital) at every point of the line and a round arch over every
// bay. The arch is the wall above the opening, cut into vertical strips one voxel (0.25 m) wide whose bottoms follow
// the semicircle, so it stays a set of closed boxes.
void addArcade(MeshBuilder& stone, MeshBuilder& marble, const std::vector<glm::vec2>& columnLine,
               const Storey& storey) {
  constexpr int stripsPerBay = 16;
  constexpr float archRadius = 0.5f * (kColumnSpacing - kCapitalSize);
  const float apexY = storey.ceilingY - 0.5f;
  const float springY = apexY - archRadius;
  for (size_t i = 0; i < columnLine.size(); ++i) {
    const glm::vec2 column = columnLine[i];
    const glm::vec2 along = glm::normalize(columnLine[(i + 1) % columnLine.size()] - column);

    const glm::vec3 base(column.x, storey.floorY, column.y);
    marble.addBox(base + glm::vec3(0.0f, 0.5f * kBlockHeight, 0.0f), {kCapitalSize, kBlockHeight, kCapitalSize}, 0.0f);
    marble.addCylinder(base + glm::vec3(0.0f, kBlockHeight, 0.0f), kColumnRadius,
                       springY - storey.floorY - 2.0f * kBlockHeight, 12);
    marble.addBox({column.x, springY - 0.5f * kBlockHeight, column.y}, {kCapitalSize, kBlockHeight, kCapitalSize},
                  0.0f);

    constexpr float stripWidth = kColumnSpacing / stripsPerBay;
    for (int strip = 0; strip < stripsPerBay; ++strip) {
      const float start = stripWidth * static_cast<float>(strip);
      const float fromMiddle = start + 0.5f * stripWidth - 0.5f * kColumnSpacing;
      const float rise = std::sqrt(std::max(0.0f, archRadius * archRadius - fromMiddle * fromMiddle));
      addBayBox(stone, column, along, start, start + stripWidth, kArcadeThickness, springY + rise, storey.ceilingY);
    }
    if (storey.balustrade) {
      addBayBox(stone, column, along, 0.5f * kCapitalSize, kColumnSpacing - 0.5f * kCapitalSize, 0.3f, storey.floorY,
                storey.floorY + 1.0f);
    }
  }
}

// The courtyard (the main scene): the atrium above, cloth banners in four colours hanging into the court from the
// upper balustrade, a fountain and planters in the court, and low blocks scattered over a 200×200 m ground plane
// around the building, so that a 128 m voxel range is filled. Sun and sky light it through the open roof.
Scene makeCourtyard(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("courtyard");
  MeshBuilder& ground = assembly.material("ground", {0.35f, 0.33f, 0.28f});
  MeshBuilder& paving = assembly.material("paving", {0.55f, 0.5f, 0.45f});
  MeshBuilder& stone = assembly.material("stone", {0.68f, 0.62f, 0.52f});
  MeshBuilder& marble = assembly.material("marble", {0.78f, 0.76f, 0.72f});
  MeshBuilder& plaster = assembly.material("plaster", {0.6f, 0.56f, 0.5f});
  MeshBuilder& terracotta = assembly.material("terracotta", {0.6f, 0.3f, 0.18f});
  MeshBuilder& foliage = assembly.material("foliage", {0.12f, 0.35f, 0.08f});
  const std::array<MeshBuilder*, 4> banners = {
      &assembly.material("banner red", {0.7f, 0.06f, 0.05f}),
      &assembly.material("banner green", {0.08f, 0.45f, 0.1f}),
      &assembly.material("banner blue", {0.06f, 0.12f, 0.55f}),
      &assembly.material("banner yellow", {0.8f, 0.62f, 0.08f}),
  };

  const Storey groundStorey{.floorY = 0.0f, .ceilingY = 6.0f, .balustrade = false};
  const Storey upperStorey{.floorY = groundStorey.ceilingY + kSlabThickness, .ceilingY = 12.0f, .balustrade = true};
  const float innerX = kCourtHalfX + kGalleryDepth;  // inner faces of the outer walls
  const float innerZ = kCourtHalfZ + kGalleryDepth;
  const float outerX = innerX + kOuterWall;
  const float outerZ = innerZ + kOuterWall;
  const glm::vec2 courtOpening(kCourtHalfX - kLedge, kCourtHalfZ - kLedge);

  ground.addBox({-100.0f, -1.0f, -100.0f}, {100.0f, -0.2f, 100.0f});
  paving.addBox({-outerX, -0.2f, -outerZ}, {outerX, 0.0f, outerZ});
  stone.addBox({-outerX, 0.0f, -outerZ}, {-innerX, upperStorey.ceilingY, outerZ});
  stone.addBox({innerX, 0.0f, -outerZ}, {outerX, upperStorey.ceilingY, outerZ});
  stone.addBox({-innerX, 0.0f, -outerZ}, {innerX, upperStorey.ceilingY, -innerZ});
  stone.addBox({-innerX, 0.0f, innerZ}, {innerX, upperStorey.ceilingY, outerZ});
  addSlabWithOpening(stone, {-innerX, groundStorey.ceilingY, -innerZ}, {innerX, upperStorey.floorY, innerZ},
                     -courtOpening, courtOpening);
  addSlabWithOpening(stone, {-outerX, upperStorey.ceilingY, -outerZ},
                     {outerX, upperStorey.ceilingY + kSlabThickness, outerZ}, -courtOpening, courtOpening);

  const std::vector<glm::vec2> columnLine = courtColumnLine();
  addArcade(stone, marble, columnLine, groundStorey);
  addArcade(stone, marble, columnLine, upperStorey);

  // Banners on both long sides, every other bay, hanging just in front of the slab's edge.
  constexpr float bannerWidth = 2.4f;
  constexpr float bannerThickness = 0.05f;
  const float bannerTop = upperStorey.floorY + 0.8f;
  const float bannerBottom = bannerTop - 4.0f;
  const float bannerZ = courtOpening.y - 0.1f;
  size_t bannerIndex = 0;
  for (const float side : {-1.0f, 1.0f}) {
    for (const float x : {-12.0f, -4.0f, 4.0f, 12.0f}) {
      const float nearZ = side * bannerZ;
      const float farZ = side * (bannerZ - bannerThickness);
      banners[bannerIndex++ % banners.size()]->addBox({x - 0.5f * bannerWidth, bannerBottom, std::min(nearZ, farZ)},
                                                      {x + 0.5f * bannerWidth, bannerTop, std::max(nearZ, farZ)});
    }
  }

  // A fountain in the middle of the court, and planted tubs.
  stone.addCylinder({0.0f, 0.0f, 0.0f}, 2.5f, 0.5f, 32);
  stone.addCylinder({0.0f, 0.5f, 0.0f}, 0.3f, 1.8f, 12);
  marble.addSphere({0.0f, 2.8f, 0.0f}, 0.5f, 10, 20);
  for (const float x : {-12.0f, 12.0f}) {
    for (const float z : {-5.0f, 5.0f}) {
      terracotta.addBox({x, 0.4f, z}, {1.0f, 0.8f, 1.0f}, 0.0f);
      foliage.addSphere({x, 1.4f, z}, 0.7f, 8, 16);
    }
  }

  // Low blocks around the building, out to ±70 m.
  struct Block {
    glm::vec2 center;
    glm::vec2 size;
    float height;
  };
  constexpr std::array<Block, 10> blocks = {{
      {{-50.0f, -45.0f}, {20.0f, 14.0f}, 8.0f},
      {{-10.0f, -50.0f}, {24.0f, 10.0f}, 6.0f},
      {{35.0f, -48.0f}, {18.0f, 16.0f}, 10.0f},
      {{62.0f, -12.0f}, {12.0f, 30.0f}, 7.0f},
      {{55.0f, 32.0f}, {16.0f, 20.0f}, 9.0f},
      {{15.0f, 55.0f}, {26.0f, 12.0f}, 6.0f},
      {{-30.0f, 52.0f}, {20.0f, 14.0f}, 8.0f},
      {{-62.0f, 10.0f}, {12.0f, 24.0f}, 10.0f},
      {{-68.0f, -68.0f}, {8.0f, 8.0f}, 12.0f},
      {{68.0f, 68.0f}, {8.0f, 8.0f}, 12.0f},
  }};
  for (const Block& block : blocks) {
    plaster.addBox({block.center.x - 0.5f * block.size.x, -0.2f, block.center.y - 0.5f * block.size.y},
                   {block.center.x + 0.5f * block.size.x, block.height, block.center.y + 0.5f * block.size.y});
  }

  assembly.setSun(30.0f, 55.0f, {6.0f, 5.6f, 5.0f}, options);
  assembly.scene().sky.kind = SkyKind::Default;

  constexpr float eyeHeight = 1.7f;
  assembly.addCamera("court", {-15.0f, eyeHeight, 0.0f}, {10.0f, 3.0f, 0.0f}, 60.0f);
  assembly.addCamera("gallery", {-20.0f, eyeHeight, -10.0f}, {15.0f, 2.5f, -10.0f}, 60.0f);
  assembly.addCamera("above", {0.0f, 30.0f, 35.0f}, {0.0f, 3.0f, 0.0f}, 60.0f);
  // A walk around the fountain, looking ahead.
  assembly.setCameraLoop({{{-15.0f, eyeHeight, 0.0f}, {-6.0f, 2.2f, 5.5f}},
                          {{-6.0f, eyeHeight, 5.5f}, {6.0f, 2.2f, 5.5f}},
                          {{6.0f, eyeHeight, 5.5f}, {15.0f, 2.2f, 0.0f}},
                          {{15.0f, eyeHeight, 0.0f}, {6.0f, 2.2f, -5.5f}},
                          {{6.0f, eyeHeight, -5.5f}, {-6.0f, 2.2f, -5.5f}},
                          {{-6.0f, eyeHeight, -5.5f}, {-15.0f, 2.2f, 0.0f}}},
                         6.0f);
  if (options.movingObject) {
    // Crosses the court south of the fountain.
    assembly.setMovingObject(cubeShape(1.0f), {0.9f, 0.5f, 0.2f}, {-6.0f, 0.5f, -3.5f}, {12.0f, 0.0f, 0.0f}, 8.0f);
  }
  return std::move(assembly).finish();
}

// A shaded gallery facing a sunlit wall behind the camera (SPEC §7): the gallery, 20 m long and 4 m deep (interior
// x∈[−10,10], z∈[−4,0], 3.5 m high), is open towards +z onto a yard; across it, 12 m away, a 9 m high ochre wall faces
// the gallery (its face at z = 12). The sun stands behind the gallery (azimuth 200°, 35° up): the gallery's back wall
// and roof keep it in shade, the sun lights the yard beyond their shadow and the far wall. There is no sky: nearly
// all the light in the gallery has bounced off that wall and the yard. The camera stands in the gallery looking at
// its back wall: what lights its view is never on screen.
Scene makeGallery(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("gallery");
  MeshBuilder& ground = assembly.material("ground", {0.3f, 0.3f, 0.28f});
  MeshBuilder& plaster = assembly.material("plaster", {0.75f, 0.73f, 0.7f});
  MeshBuilder& ochre = assembly.material("ochre", {0.8f, 0.55f, 0.3f});
  MeshBuilder& green = assembly.material("green", {0.15f, 0.45f, 0.12f});

  ground.addBox({-40.0f, -0.2f, -40.0f}, {40.0f, 0.0f, 40.0f});
  plaster.addBox({-10.5f, 0.0f, -4.5f}, {10.5f, 4.0f, -4.0f});   // back wall
  plaster.addBox({-10.5f, 3.5f, -4.0f}, {10.5f, 4.0f, 0.5f});    // roof
  plaster.addBox({-10.5f, 0.0f, -4.0f}, {-10.0f, 3.5f, 0.0f});   // end walls
  plaster.addBox({10.0f, 0.0f, -4.0f}, {10.5f, 3.5f, 0.0f});
  for (float x = -8.0f; x <= 8.0f; x += 4.0f) plaster.addBox({x - 0.25f, 0.0f, -0.25f}, {x + 0.25f, 3.5f, 0.25f});
  green.addBox({-3.0f, 0.0f, -4.0f}, {-1.0f, 1.0f, -3.2f});  // a bench against the back wall
  ochre.addBox({-14.0f, 0.0f, 12.0f}, {14.0f, 9.0f, 12.5f});

  assembly.setSun(200.0f, 35.0f, {8.0f, 7.6f, 7.0f}, options);
  assembly.addCamera("gallery", {0.5f, 1.6f, -0.5f}, {-1.0f, 1.3f, -4.5f}, 60.0f);
  if (options.movingObject) {
    // Walks along the gallery.
    assembly.setMovingObject(cubeShape(0.6f), {0.9f, 0.5f, 0.2f}, {-6.0f, 0.3f, -2.0f}, {12.0f, 0.0f, 0.0f}, 8.0f);
  }
  return std::move(assembly).finish();
}

// A closed hall lit only by a uniform sky through two openings in its roof (SPEC §7): interior x∈[−6,6], y∈[0,6],
// z∈[−10,10], walls, floor and roof 0.3 m thick, 2×2 m openings over z∈[−6,−4] and z∈[3,5]. The camera stands near
// one end looking level along the hall: the roof above and behind it — with the nearer opening — is never on screen.
Scene makeHall(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("hall");
  MeshBuilder& walls = assembly.material("walls", {0.72f, 0.7f, 0.66f});
  MeshBuilder& floor = assembly.material("floor", {0.5f, 0.42f, 0.34f});
  MeshBuilder& red = assembly.material("red", {0.7f, 0.1f, 0.08f});
  MeshBuilder& blue = assembly.material("blue", {0.1f, 0.18f, 0.6f});

  constexpr float wall = 0.3f;
  constexpr float halfX = 6.0f;
  constexpr float halfZ = 10.0f;
  constexpr float height = 6.0f;
  floor.addBox({-halfX - wall, -wall, -halfZ - wall}, {halfX + wall, 0.0f, halfZ + wall});
  walls.addBox({-halfX - wall, 0.0f, -halfZ - wall}, {-halfX, height, halfZ + wall});
  walls.addBox({halfX, 0.0f, -halfZ - wall}, {halfX + wall, height, halfZ + wall});
  walls.addBox({-halfX, 0.0f, -halfZ - wall}, {halfX, height, -halfZ});
  walls.addBox({-halfX, 0.0f, halfZ}, {halfX, height, halfZ + wall});
  // The roof as slabs around the two openings: the openings x∈[−1,1] at z∈[−6,−4] and z∈[3,5].
  const float roofLow = height, roofHigh = height + wall;
  walls.addBox({-halfX - wall, roofLow, -halfZ - wall}, {-1.0f, roofHigh, halfZ + wall});
  walls.addBox({1.0f, roofLow, -halfZ - wall}, {halfX + wall, roofHigh, halfZ + wall});
  walls.addBox({-1.0f, roofLow, -halfZ - wall}, {1.0f, roofHigh, -6.0f});
  walls.addBox({-1.0f, roofLow, -4.0f}, {1.0f, roofHigh, 3.0f});
  walls.addBox({-1.0f, roofLow, 5.0f}, {1.0f, roofHigh, halfZ + wall});
  red.addBox({-3.0f, 0.75f, -5.0f}, {1.5f, 1.5f, 1.5f}, glm::radians(20.0f));
  blue.addCylinder({3.0f, 0.0f, 0.0f}, 0.5f, 3.0f, 16);

  assembly.scene().sky = {.kind = SkyKind::Uniform, .uniformRadiance = glm::vec3(1.0f)};
  assembly.addCamera("hall", {1.5f, 1.6f, 8.5f}, {1.5f, 1.6f, -10.0f}, 60.0f);
  if (options.movingObject) {
    // Passes under the nearer opening.
    assembly.setMovingObject(sphereShape(0.5f), {0.9f, 0.9f, 0.9f}, {-3.0f, 0.5f, 4.0f}, {6.0f, 0.0f, 0.0f}, 6.0f);
  }
  return std::move(assembly).finish();
}

// A closed room lit only by two emissive panels (SPEC §6.7): interior x∈[−2.5,2.5], y∈[0,3], z∈[−2.5,2.5], walls,
// floor and ceiling 0.25 m thick; a warm 1×2 m panel on the ceiling (radiance 20) and a cyan 0.5×1.5 m panel on the
// back wall (radiance 15), both 2 cm thick and reflecting nothing, as a luminaire's diffuser does; a yellow block in
// the back corner and a white one beside the camera. No sun, no sky, no delta light: the renderer's direct light is
// zero everywhere and every watt on screen comes through the GI. The camera looks at the cyan panel's wall with the
// ceiling panel above its view.
Scene makePanelRoom(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("panel-room");
  MeshBuilder& white = assembly.material("white", {0.75f, 0.75f, 0.73f});
  MeshBuilder& yellow = assembly.material("yellow", {0.8f, 0.65f, 0.15f});
  MeshBuilder& ceilingPanel = assembly.material("ceiling panel", glm::vec3(0.0f), glm::vec3(1.0f, 0.85f, 0.62f) * 20.0f);
  MeshBuilder& wallPanel = assembly.material("wall panel", glm::vec3(0.0f), glm::vec3(0.1f, 0.85f, 1.0f) * 15.0f);

  constexpr float wall = 0.25f;
  constexpr float half = 2.5f;
  constexpr float height = 3.0f;
  white.addBox({-half - wall, -wall, -half - wall}, {half + wall, 0.0f, half + wall});            // floor
  white.addBox({-half - wall, height, -half - wall}, {half + wall, height + wall, half + wall});  // ceiling
  white.addBox({-half - wall, 0.0f, -half - wall}, {-half, height, half + wall});                 // left wall
  white.addBox({half, 0.0f, -half - wall}, {half + wall, height, half + wall});                   // right wall
  white.addBox({-half, 0.0f, -half - wall}, {half, height, -half});                               // back wall
  white.addBox({-half, 0.0f, half}, {half, height, half + wall});                                 // front wall
  yellow.addBox({1.6f, 0.0f, -half}, {half, 0.9f, -1.6f});
  white.addBox({-2.0f, 0.0f, 0.8f}, {-1.2f, 1.2f, 1.6f});
  ceilingPanel.addBox({-0.5f, height - 0.02f, -1.5f}, {0.5f, height, 0.5f});
  wallPanel.addBox({-1.5f, 0.8f, -half}, {-1.0f, 2.3f, -half + 0.02f});

  assembly.addCamera("room", {0.3f, 1.5f, 2.2f}, {-0.4f, 1.2f, -2.5f}, 60.0f);
  if (options.movingObject) {
    // Passes in front of the wall panel.
    assembly.setMovingObject(sphereShape(0.3f), {0.8f, 0.8f, 0.8f}, {-2.0f, 1.0f, -1.5f}, {2.5f, 0.0f, 0.0f}, 5.0f);
  }
  return std::move(assembly).finish();
}

// The analytic test case. Tests compute direct light from this geometry, so it is exact:
//   plane     a box x∈[−10,10], y∈[−0.1,0], z∈[−10,10] (top face at y = 0), albedo 0.8 ("plane");
//   occluder  a 0.5 m cube centred at (3, 1, 0): x∈[2.75,3.25], y∈[0.75,1.25], z∈[−0.25,0.25], albedo 0.8 ("occluder");
//             its shadow from the light falls on the plane around (6, 0, 0);
//   light     a shadowed point light at (0, 2, 0), intensity 10 W/sr in every channel;
//   no sky, no sun; camera at (0, 6, 6) looking at the origin, vertical field of view 60°.
// No camera path: the view stays still for the analytic comparison.
Scene makePlanePointLight(const BuiltinSceneOptions& options) {
  SceneAssembly assembly("plane-point-light");
  assembly.material("plane", glm::vec3(0.8f)).addBox({-10.0f, -0.1f, -10.0f}, {10.0f, 0.0f, 10.0f});
  assembly.material("occluder", glm::vec3(0.8f)).addBox({3.0f, 1.0f, 0.0f}, glm::vec3(0.5f), 0.0f);
  assembly.scene().lights.push_back({.name = "point", .position = {0.0f, 2.0f, 0.0f}, .intensity = glm::vec3(10.0f)});
  assembly.addCamera("above", {0.0f, 6.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 60.0f);
  if (options.movingObject) {
    // Passes between the light and the plane on the side away from the occluder.
    assembly.setMovingObject(sphereShape(0.4f), {0.8f, 0.8f, 0.8f}, {-3.0f, 0.8f, 3.0f}, {0.0f, 0.0f, -6.0f}, 6.0f);
  }
  return std::move(assembly).finish();
}

struct BuiltinScene {
  const char* name;
  Scene (*make)(const BuiltinSceneOptions&);
};

constexpr std::array<BuiltinScene, 8> kBuiltinScenes = {{
    {"cornell", makeCornell},
    {"two-rooms", makeTwoRooms},
    {"dark-room", makeDarkRoom},
    {"courtyard", makeCourtyard},
    {"gallery", makeGallery},
    {"hall", makeHall},
    {"panel-room", makePanelRoom},
    {"plane-point-light", makePlanePointLight},
}};

}  // namespace

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> names;
  for (const BuiltinScene& scene : kBuiltinScenes) names.emplace_back(scene.name);
  return names;
}

std::optional<Scene> makeBuiltinScene(std::string_view name, const BuiltinSceneOptions& options) {
  for (const BuiltinScene& scene : kBuiltinScenes) {
    if (name == scene.name) return scene.make(options);
  }
  return std::nullopt;
}

}  // namespace ssvgi::renderer
