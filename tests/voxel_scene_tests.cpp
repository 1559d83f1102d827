// The voxel scene (SPEC §4.1–4.3) through the public API, checked against its GPU state: injection of known frames,
// clearing behind a moving object, release and reuse of bricks, pool accounting, exhaustion and the memory budget.
#include "camera.h"
#include "gi/context_internals.h"
#include "gi/memory_budget.h"
#include "gi/voxels/voxel_passes.h"
#include "gpu_host/transfers.h"
#include "gpu_test_device.h"
#include "voxel_readback.h"
#include "shared/gi_frame.h"
#include "shared/probe_interface.h"
#include "shared/ray_box.h"
#include "shared/sampling.h"
#include "shared/voxel_interface.h"
#include "ssvgi/ssvgi.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <type_traits>
#include <variant>

namespace ssvgi {
namespace {

constexpr uint32_t kSize = 64;  // frame size in pixels
constexpr float kVoxel = 0.25f;

struct TestBox {
  glm::vec3 min;
  glm::vec3 max;
  glm::vec3 radiance;
  glm::mat3 orientation{1.0f};  // turned by this about its centre (its columns: its axes in the world)
};

// What one pixel of a host frame shows.
struct PixelSurface {
  bool hit = false;
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
};

// The frames a host would hand ssvgi: depth, colour and normal of a scene of boxes seen through a reversed-Z
// view-projection (perspective or orthographic), computed on the CPU by ray casting (so the test knows exactly which
// surface each pixel shows).
struct HostFrame {
  HostFrame(gpu::OwnedDevice& device, const glm::mat4& viewMatrix, const glm::mat4& projection,
            const std::vector<TestBox>& boxes, uint32_t size = kSize)
      : depth(device, {"test depth", VK_FORMAT_R32_SFLOAT, size, size, 1, 1, VK_IMAGE_USAGE_SAMPLED_BIT}),
        color(device, {"test colour", VK_FORMAT_R32G32B32A32_SFLOAT, size, size, 1, 1, VK_IMAGE_USAGE_SAMPLED_BIT}),
        normal(device, {"test normal", VK_FORMAT_R32G32B32A32_SFLOAT, size, size, 1, 1, VK_IMAGE_USAGE_SAMPLED_BIT}),
        viewProjection(projection * viewMatrix),
        surfaces(size * size) {
    const glm::mat4 inverse = glm::inverse(viewProjection);
    const auto unproject = [&](glm::vec2 ndc, float depthValue) {
      const glm::vec4 world = inverse * glm::vec4(ndc, depthValue, 1.0f);
      return glm::vec3(world) / world.w;
    };
    std::vector<float> depths(size * size, 0.0f), colors(size * size * 4, 0.0f), normals(size * size * 4, 0.0f);
    for (uint32_t y = 0; y < size; ++y) {
      for (uint32_t x = 0; x < size; ++x) {
        // The pixel's ray from the near plane (NDC depth 1), towards greater depth.
        const glm::vec2 ndc((float(x) + 0.5f) / float(size) * 2.0f - 1.0f,
                            1.0f - (float(y) + 0.5f) / float(size) * 2.0f);
        const glm::vec3 origin = unproject(ndc, 1.0f);
        const glm::vec3 direction = glm::normalize(unproject(ndc, 0.5f) - origin);
        const size_t i = y * size + x;
        float nearest = 1e30f;
        for (const TestBox& box : boxes) {
          // In the box's own frame, where it is axis-aligned (the ray as it is where the box is not turned).
          const bool turned = box.orientation != glm::mat3(1.0f);
          const glm::vec3 centre = 0.5f * (box.min + box.max);
          const glm::mat3 toBox = glm::transpose(box.orientation);
          const glm::vec3 boxOrigin = turned ? centre + toBox * (origin - centre) : origin;
          const glm::vec3 boxDirection = turned ? toBox * direction : direction;
          glm::vec3 enterNormal(0.0f);
          float enter = 0.0f, exit = 1e30f;
          for (int axis = 0; axis < 3; ++axis) {
            float t0 = (box.min[axis] - boxOrigin[axis]) / boxDirection[axis];
            float t1 = (box.max[axis] - boxOrigin[axis]) / boxDirection[axis];
            glm::vec3 axisNormal(0.0f);
            axisNormal[axis] = -1.0f;
            if (t0 > t1) std::swap(t0, t1), axisNormal[axis] = 1.0f;
            if (t0 > enter) enter = t0, enterNormal = axisNormal;
            exit = std::min(exit, t1);
          }
          enterNormal = box.orientation * enterNormal;
          if (enter < exit && enter > 0.0f && enter < nearest) {
            nearest = enter;
            const glm::vec3 hit = origin + enter * direction;
            const glm::vec4 clip = viewProjection * glm::vec4(hit, 1.0f);
            depths[i] = clip.z / clip.w;
            surfaces[i] = {true, hit, enterNormal};
            for (int c = 0; c < 3; ++c) {
              colors[i * 4 + c] = box.radiance[c];
              normals[i * 4 + c] = enterNormal[c];
            }
          }
        }
      }
    }
    depthValues = depths;
    colorValues = colors;
    normalValues = normals;
    upload(device);
    const float* matrix = glm::value_ptr(viewProjection);
    std::copy(matrix, matrix + 16, view.viewProjection.begin());
    const glm::vec3 eye = glm::inverse(viewMatrix)[3];
    view.position = {eye.x, eye.y, eye.z};
    view.width = view.height = size;
  }
  HostFrame(gpu::OwnedDevice& device, const renderer::Camera& camera, const std::vector<TestBox>& boxes,
            uint32_t size = kSize)
      : HostFrame(device, renderer::viewMatrix(camera),
                  renderer::reversedZInfiniteProjection(camera.verticalFov, 1.0f, camera.nearPlane), boxes, size) {}

  gpu::Image depth;
  gpu::Image color;
  gpu::Image normal;
  glm::mat4 viewProjection;
  std::vector<PixelSurface> surfaces;  // per pixel, rows from the top
  std::vector<float> depthValues;      // the depth image's values
  std::vector<float> colorValues;      // rgba per pixel
  std::vector<float> normalValues;     // xyz0 per pixel
  View view;

  // Uploads the images' values (after a test has changed them).
  void upload(gpu::OwnedDevice& device) {
    gpu::uploadImage(device, depth, std::as_bytes(std::span(depthValues)));
    gpu::uploadImage(device, color, std::as_bytes(std::span(colorValues)));
    gpu::uploadImage(device, normal, std::as_bytes(std::span(normalValues)));
  }
};

// A camera at `position` looking at `target`, its near plane 0.1 m away.
renderer::Camera looking(glm::vec3 position, glm::vec3 target, float fovDegrees) {
  renderer::Camera camera;
  camera.position = position;
  camera.target = target;
  camera.verticalFov = glm::radians(fovDegrees);
  camera.nearPlane = 0.1f;
  return camera;
}

renderer::Camera lookingDown(glm::vec3 position, float fovDegrees = 30.0f) {
  renderer::Camera camera = looking(position, position - glm::vec3(0.0f, 1.0f, 0.0f), fovDegrees);
  camera.up = {0.0f, 0.0f, -1.0f};
  return camera;
}

// The floor: its top face at y = 0.1, inside the lowest voxel layer (y in [0, 0.25)).
const TestBox kFloor{{-1000.0f, -1.0f, -1000.0f}, {1000.0f, 0.1f, 1000.0f}, {0.5f, 0.25f, 0.125f}};

Settings smallSettings() {
  Settings settings;
  settings.volumeBricks = {16, 8, 16};
  settings.brickPoolCapacity = 512;
  settings.invalidFramesToClear = 4;
  settings.emptyFramesToRelease = 4;
  settings.allocationPixelStride = 1;
  return settings;
}

struct GpuState {
  std::vector<uint32_t> lookup;
  std::vector<shader::Brick> bricks;
  std::vector<shader::Voxel> voxels;
  shader::BrickPoolState pool{};
  std::vector<uint32_t> freeList;
};

class VoxelScene : public testing::GpuTest {
 protected:
  void create(const Settings& settings, uint32_t maxExtraViewSize = kSize) {
    ContextDesc desc = testing::gpuTestContextDesc(settings, kSize);
    desc.maxExtraViewSize = maxExtraViewSize;
    auto result = Context::create(desc);
    ASSERT_TRUE(result.ok()) << result.error().message;
    context_ = std::move(result.value());
  }

  std::map<int, bool> cellsObservedBesideAWallUnderARoofsRim(float rim, float texel);

  // One frame: the current frame is also the lit frame (a static view re-lit by the same image).
  void dispatch(const HostFrame& current, const HostFrame* lit, const std::vector<ExtraView>& extraViews = {},
                const std::array<float, 12>& skyRadianceSh = {}) {
    FrameDesc frame;
    frame.extraViews = extraViews;
    frame.skyRadianceSh = skyRadianceSh;
    frame.frameIndex = frameIndex_++;
    frame.countWork = countWork_;
    frame.camera = current.view;
    frame.depth.view = current.depth.view();
    frame.normal.view = current.normal.view();
    if (lit) {
      frame.hasLitFrame = true;
      frame.litCamera = lit->view;
      frame.litColor.view = lit->color.view();
      frame.litDepth.view = lit->depth.view();
      frame.litNormal.view = lit->normal.view();
    }
    Error error;
    device().submitAndWait([&](VkCommandBuffer commandBuffer) { error = context_->dispatch(frame, commandBuffer); });
    ASSERT_FALSE(error) << error.message;
  }

  // Dispatches one frame of `frame`'s depth and normal seen from `camera`, without a lit frame; returns dispatch()'s
  // answer (for the tests of what it refuses).
  Error tryDispatch(const HostFrame& frame, const View& camera, const std::vector<ExtraView>& extraViews = {}) {
    FrameDesc desc;
    desc.camera = camera;
    desc.depth.view = frame.depth.view();
    desc.normal.view = frame.normal.view();
    desc.extraViews = extraViews;
    Error error;
    device().submitAndWait([&](VkCommandBuffer commandBuffer) { error = context_->dispatch(desc, commandBuffer); });
    return error;
  }

  void run(const HostFrame& frame, uint32_t frames) {
    for (uint32_t i = 0; i < frames; ++i) dispatch(frame, &frame);
  }

  GpuState readState() {
    const gi::VoxelScene& scene = gi::voxelSceneOf(*context_);
    GpuState state;
    state.lookup = gpu::readBufferAs<uint32_t>(device(), scene.brickLookup());
    state.bricks = gpu::readBufferAs<shader::Brick>(device(), scene.bricks());
    state.voxels = gpu::readBufferAs<shader::Voxel>(device(), scene.voxels());
    const auto poolWords = gpu::readBufferAs<uint32_t>(device(), scene.poolState());
    std::memcpy(&state.pool, poolWords.data(), sizeof(state.pool));
    state.freeList.assign(poolWords.begin() + sizeof(state.pool) / 4, poolWords.end());
    return state;
  }

  static std::map<testing::VoxelCoordinate, shader::Voxel> occupiedVoxels(const GpuState& state) {
    return testing::occupiedVoxels(state.bricks, state.voxels, state.pool.bumpCount);
  }

  // Every invariant of the pool: live bricks are exactly those the lookup points to, at their own cells; the free
  // list holds exactly the other slots below the bump count, once each.
  static void expectPoolConsistent(const GpuState& state, const Settings& settings) {
    const glm::ivec3 dimensions(settings.volumeBricks[0], settings.volumeBricks[1], settings.volumeBricks[2]);
    ASSERT_LE(state.pool.bumpCount, settings.brickPoolCapacity);
    ASSERT_LE(state.pool.freeCount, state.pool.bumpCount);
    std::set<uint32_t> referenced;
    for (uint32_t cell = 0; cell < state.lookup.size(); ++cell) {
      const uint32_t brick = state.lookup[cell];
      if (brick == shader::kInvalidBrick) continue;
      ASSERT_LT(brick, state.pool.bumpCount) << "cell " << cell;
      ASSERT_TRUE(referenced.insert(brick).second) << "brick " << brick << " is in two cells";
      ASSERT_EQ(state.bricks[brick].live, 1u) << "cell " << cell << " points to a free brick";
      ASSERT_EQ(shader::brickCellIndex(state.bricks[brick].coordinate, dimensions), cell);
    }
    std::set<uint32_t> free(state.freeList.begin(), state.freeList.begin() + state.pool.freeCount);
    ASSERT_EQ(free.size(), state.pool.freeCount) << "an index is on the free list twice";
    for (uint32_t brick = 0; brick < state.pool.bumpCount; ++brick) {
      const bool live = state.bricks[brick].live == 1u;
      ASSERT_EQ(live, referenced.count(brick) == 1) << "brick " << brick;
      ASSERT_EQ(live, free.count(brick) == 0) << "brick " << brick;
    }
  }

  std::unique_ptr<Context> context_;
  bool countWork_ = false;  // dispatch()'s frames count their work (FrameDesc::countWork)
  uint32_t frameIndex_ = 0;
};

TEST_F(VoxelScene, injectingAFloorOccupiesItsVoxelLayerWithItsColourAndNothingInFront) {
  create(smallSettings());
  const HostFrame frame(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  run(frame, 24);
  const GpuState state = readState();
  const auto occupied = occupiedVoxels(state);
  ASSERT_FALSE(occupied.empty());
  for (const auto& [coordinate, voxel] : occupied) {
    const auto [x, y, z] = coordinate;
    ASSERT_EQ(y, 0) << "voxel " << x << "," << y << "," << z << " is not in the floor's layer";
    const glm::vec3 radiance = shader::unpackR11G11B10F(voxel.radiance);
    // R11G11B10F keeps 6 (R, G) and 5 (B) mantissa bits: relative error below 2^-6 and 2^-5.
    EXPECT_NEAR(radiance.x, kFloor.radiance.x, kFloor.radiance.x / 64.0f);
    EXPECT_NEAR(radiance.y, kFloor.radiance.y, kFloor.radiance.y / 64.0f);
    EXPECT_NEAR(radiance.z, kFloor.radiance.z, kFloor.radiance.z / 32.0f);
    EXPECT_GT(shader::voxelNormal(voxel).y, 0.99f);
    EXPECT_LT(shader::voxelSeenThroughCount(voxel),
              smallSettings().invalidFramesToClear);  // valid
    // The floor's top (y = 0.1) lies 0.1 voxels below the centre of its layer (y in [0, 0.25)): the voxel's plane.
    // 0.01: the plane's 8-bit step (0.007 voxels) and the depth's float error.
    const uint32_t planeCode = shader::voxelPlaneCode(voxel);
    ASSERT_NE(planeCode, 0u);
    EXPECT_NEAR(shader::unpackVoxelPlane(planeCode), -0.1f, 0.01f);
  }
  // The camera sees the floor within tan(15°) · 5.9 m ≈ 1.58 m of (0.5, 0.5); every voxel well inside is found.
  for (int x = -3; x <= 4; ++x)
    for (int z = -3; z <= 4; ++z) EXPECT_TRUE(occupied.count({x, 0, z})) << "voxel " << x << ",0," << z << " missing";
  expectPoolConsistent(state, smallSettings());
}

TEST_F(VoxelScene, aFloorOnAVoxelBoundaryIsHeldByTheLayerBelowIt) {
  // The floor's top at y = 0, the boundary between voxel layers −1 and 0: its points are held a hair behind the
  // surface, so the floor lies in layer −1 alone, whole, and never spreads into layer 0 by rounding. (From 3.5 m up
  // the voxel volume reaches down to y = −4 m; the camera sees the floor within 0.94 m of (0.5, 0.5).)
  create(smallSettings());
  const TestBox floorOnBoundary{{-1000.0f, -1.0f, -1000.0f}, {1000.0f, 0.0f, 1000.0f}, kFloor.radiance};
  const HostFrame frame(device(), lookingDown({0.5f, 3.5f, 0.5f}), {floorOnBoundary});
  run(frame, 24);
  const GpuState state = readState();
  const auto occupied = occupiedVoxels(state);
  for (const auto& [coordinate, voxel] : occupied)
    EXPECT_EQ(std::get<1>(coordinate), -1) << "voxel " << std::get<0>(coordinate) << "," << std::get<1>(coordinate)
                                           << "," << std::get<2>(coordinate);
  for (int x = 0; x <= 3; ++x)
    for (int z = 0; z <= 3; ++z) EXPECT_TRUE(occupied.count({x, -1, z})) << "voxel " << x << ",-1," << z << " missing";
  expectPoolConsistent(state, smallSettings());
}

// 0.5 m above kFloor's top, looking 5.7° down: the floor 1.5 m to 4 m ahead (voxels x 0..3, z −16..−6, 44 in all)
// is seen at 6° to 21°.
renderer::Camera grazingFloorCamera() { return looking({0.5f, 0.6f, 0.5f}, {0.5f, 0.1f, -4.5f}, 30.0f); }

TEST_F(VoxelScene, aFloorSeenAtAGrazingAngleKeepsEveryVoxelOfIt) {
  // The camera 0.5 m above the floor, looking 5.7° down: the floor's voxels ahead are seen at 6° to 21°. Most random
  // points of such a voxel lie above the floor's top (y = 0.1 in a layer 0.25 m high) and see the floor further on,
  // which must not count as seeing through the voxel: after 48 frames (12 × invalidFramesToClear) the floor's layer is
  // whole from 1.5 m to 4 m ahead, and nothing above it is occupied.
  create(smallSettings());
  const renderer::Camera camera = grazingFloorCamera();
  const HostFrame frame(device(), camera, {kFloor});
  run(frame, 48);
  const GpuState state = readState();
  const auto occupied = occupiedVoxels(state);
  for (const auto& [coordinate, voxel] : occupied)
    EXPECT_EQ(std::get<1>(coordinate), 0) << "voxel " << std::get<0>(coordinate) << "," << std::get<1>(coordinate)
                                          << "," << std::get<2>(coordinate) << " is not in the floor's layer";
  uint32_t missing = 0;
  for (int x = 0; x <= 3; ++x)
    for (int z = -16; z <= -6; ++z) missing += occupied.count({x, 0, z}) == 0;
  EXPECT_EQ(missing, 0u) << "of 44 voxels of the floor ahead";
  expectPoolConsistent(state, smallSettings());
}

TEST_F(VoxelScene, aFloorSeenAtAGrazingAngleTakesANewColourWithinAFewFrames) {
  // The grazing view above: few random points of a voxel land on the voxel's own pixels, but pixels of its surface
  // within a voxel of it count too, so when the light on the floor changes, every voxel ahead has the new colour
  // within 10 frames (QUALITY.md, "What the scenario tests' bounds rest on", has what it was without them).
  create(smallSettings());
  const renderer::Camera camera = grazingFloorCamera();
  run(HostFrame(device(), camera, {kFloor}), 48);
  TestBox relit = kFloor;
  relit.radiance = {0.125f, 0.5f, 0.25f};
  run(HostFrame(device(), camera, {relit}), 10);
  const auto occupied = occupiedVoxels(readState());
  uint32_t stale = 0, found = 0;
  for (int x = 0; x <= 3; ++x)
    for (int z = -16; z <= -6; ++z) {
      const auto voxel = occupied.find({x, 0, z});
      if (voxel == occupied.end()) continue;
      ++found;
      const glm::vec3 radiance = shader::unpackR11G11B10F(voxel->second.radiance);
      stale += std::abs(radiance.y - relit.radiance.y) > relit.radiance.y / 64.0f;
    }
  EXPECT_EQ(found, 44u);
  EXPECT_EQ(stale, 0u) << "voxels of the floor ahead still holding the old colour";
}

// A host frame as an extra view (SPEC §6.3); with `albedo` (a frame whose colour is the surfaces' albedo), one lit
// by direct light only, to which ssvgi adds its probes' light.
ExtraView extraView(const HostFrame& frame, const HostFrame* albedo = nullptr) {
  ExtraView view;
  view.camera = frame.view;
  view.color.view = frame.color.view();
  view.depth.view = frame.depth.view();
  view.normal.view = frame.normal.view();
  if (albedo) view.albedo.view = albedo->color.view();
  return view;
}

TEST_F(VoxelScene, anExtraViewFillsTheVoxelsTheCameraNeverSeesAndTheLitFrameWinsWhereBothSee) {
  // The camera sees the floor within tan(15°) · 5.9 m ≈ 1.58 m of (0.5, 0.5); an extra view from the same point with
  // a 60° field sees it within 3.4 m, in another colour.
  create(smallSettings());
  const HostFrame camera(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  TestBox otherColour = kFloor;
  otherColour.radiance = {0.125f, 0.5f, 0.25f};
  const HostFrame wide(device(), lookingDown({0.5f, 6.0f, 0.5f}, 60.0f), {otherColour});
  for (uint32_t frame = 0; frame < 24; ++frame) dispatch(camera, &camera, {extraView(wide)});
  const GpuState state = readState();
  const auto occupied = occupiedVoxels(state);
  uint32_t outerVoxels = 0;
  for (const auto& [coordinate, voxel] : occupied) {
    const auto [x, y, z] = coordinate;
    ASSERT_EQ(y, 0) << "voxel " << x << "," << y << "," << z << " is not in the floor's layer";
    // Voxel centres 2.4 m to 3.1 m from (0.5, 0.5) along an axis: only the extra view sees them.
    const float offset = std::max(std::abs((float(x) + 0.5f) * kVoxel - 0.5f), std::abs((float(z) + 0.5f) * kVoxel - 0.5f));
    const bool cameraSees = offset < 1.2f, onlyExtraSees = offset > 2.4f && offset < 3.1f;
    if (!cameraSees && !onlyExtraSees) continue;
    const glm::vec3 expected = cameraSees ? kFloor.radiance : otherColour.radiance;
    const glm::vec3 radiance = shader::unpackR11G11B10F(voxel.radiance);
    EXPECT_NEAR(radiance.y, expected.y, expected.y / 64.0f) << "voxel " << x << ",0," << z;
    EXPECT_NEAR(radiance.z, expected.z, expected.z / 32.0f) << "voxel " << x << ",0," << z;
    outerVoxels += onlyExtraSees;
  }
  // Every voxel of the ring: centres 10.5 or 11.5 voxels from (0.5, 0.5) along the farther axis, 24² − 20² of them.
  EXPECT_EQ(outerVoxels, 176u) << "the extra view's voxels beyond the camera's view are missing";
  expectPoolConsistent(state, smallSettings());
}

TEST_F(VoxelScene, injectionCountsEveryVoxelOfEachBrickInViewForTheCameraAndTheExtraViewsApart) {
  // The previous test's floor, seen by the camera and by a wider extra view. SceneVoxelization runs a thread per voxel
  // of each brick BrickCulling listed, whose count Stats sums over the views; of those, the voxels whose random point
  // lies in the view read its texels. ObservedSpace walks each view's pixels, every ray marking at least its first
  // brick cell.
  Settings settings = smallSettings();
  settings.skyOnlyThroughObservedSpace = true;  // ObservedSpace runs
  create(settings);
  const HostFrame camera(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  const HostFrame wide(device(), lookingDown({0.5f, 6.0f, 0.5f}, 60.0f), {kFloor});
  for (uint32_t frame = 0; frame < 4; ++frame) dispatch(camera, &camera, {extraView(wide)});
  countWork_ = true;
  dispatch(camera, &camera, {extraView(wide)});
  const Stats stats = context_->stats();
  ASSERT_TRUE(stats.work.counted);
  const WorkCounts::Injection& cameraInjection = stats.work.sceneVoxelization;
  const WorkCounts::Injection& extraViewInjection = stats.work.extraViewVoxelization;
  EXPECT_EQ(cameraInjection.voxels + extraViewInjection.voxels,
            shader::kVoxelsPerBrick * stats.bricksVisibleLastFrame);
  EXPECT_GT(cameraInjection.voxels, 0u);
  EXPECT_GT(extraViewInjection.voxels, cameraInjection.voxels);  // it sees more of the floor
  EXPECT_GT(cameraInjection.voxelsInView, 0u);
  EXPECT_LE(cameraInjection.voxelsInView, cameraInjection.voxels);
  EXPECT_GT(extraViewInjection.voxelsInView, 0u);
  EXPECT_LE(extraViewInjection.voxelsInView, extraViewInjection.voxels);
  EXPECT_GT(stats.work.observedSpace.rays, 0u);
  EXPECT_LE(stats.work.observedSpace.rays, 2 * kSize * kSize);
  EXPECT_GE(stats.work.observedSpace.cells, stats.work.observedSpace.rays);
}

TEST_F(VoxelScene, anExtraViewLitByDirectLightOnlyTakesTheProbesLightReflectedByItsAlbedo) {
  // A black floor (no direct light) under a uniform sky of radiance L, seen only by an extra view that gives its
  // albedo a: the probes above it see L over their upper hemisphere, so E(up) = π·L at the floor, whatever the floor
  // below them reflects (SH2 reconstructs E of a hemisphere step at its axis exactly: π/2·(L+F) + π/2·(L−F)), and the
  // floor's voxels must hold a/π · π·L = a·L. The camera, with no lit frame, only places and traces the probes.
  // The open sky above is the test's premise — no view looks up at it — so rays that meet no voxel see it.
  Settings settings = smallSettings();
  settings.skyOnlyThroughObservedSpace = false;
  create(settings);
  constexpr float kSky = 1.0f, kAlbedo = 0.5f;
  std::array<float, 12> sky{};
  for (int channel = 0; channel < 3; ++channel) sky[channel * 4] = kSky / 0.282095f;  // L00 = L · √(4π)
  const TestBox black{kFloor.min, kFloor.max, glm::vec3(0.0f)};
  const TestBox albedo{kFloor.min, kFloor.max, glm::vec3(kAlbedo)};
  // From 3 m the 90° view sees the floor within 2.9 m, in pixels of 9 cm: every voxel of it holds a pixel's point.
  const HostFrame floorView(device(), lookingDown({0.5f, 3.0f, 0.5f}, 90.0f), {black});
  const HostFrame floorAlbedo(device(), lookingDown({0.5f, 3.0f, 0.5f}, 90.0f), {albedo});
  const HostFrame camera(device(), lookingDown({0.5f, 3.0f, 0.5f}, 60.0f), {black});
  // 40 updates of the finest level (one level a frame): its probes have averaged all 1024 directions of their set.
  for (uint32_t frame = 0; frame < 120; ++frame) dispatch(camera, nullptr, {extraView(floorView, &floorAlbedo)}, sky);
  const auto occupied = occupiedVoxels(readState());
  uint32_t checked = 0;
  for (int x = 0; x <= 3; ++x)  // voxel centres within 0.4 m of (0.5, 0.5), amid probes the camera sees
    for (int z = 0; z <= 3; ++z) {
      const auto voxel = occupied.find({x, 0, z});
      ASSERT_NE(voxel, occupied.end()) << "voxel " << x << ",0," << z << " missing";
      // 5 %: the sky seen below the horizon where the floor has no voxels (beyond 2.9 m: +3 % on E(up), worked out
      // from the SH2 projection), the probes' remaining noise and R11G11B10F's 1.6 %.
      const glm::vec3 radiance = shader::unpackR11G11B10F(voxel->second.radiance);
      EXPECT_NEAR(radiance.y, kAlbedo * kSky, 0.05f * kAlbedo * kSky) << "voxel " << x << ",0," << z;
      ++checked;
    }
  EXPECT_EQ(checked, 16u);
}

// SceneVoxelization's rules (SPEC §4.3 and the refinements in scene_voxelization.comp) for the voxels of a static
// view, on the CPU: frame by frame, the same random point of each voxel (shared/sampling.h's hash), the pixel it
// projects to, and Valid / refresh / Invalid from the surface that pixel shows exactly. A decision that lies within
// float rounding of a threshold (a point on a pixel's edge, a surface point on a voxel's face) marks the voxel as one
// the GPU may decide otherwise.
class InjectionOracle {
 public:
  // `viewpoint`: the corner of the scroll step under the camera, metres (volumeViewpoint). Injecting extra views only, as here, every occupied voxel
  // has been written by one, so each visit writes (kVoxelExtraViewsBeforeWrite does not hold any back).
  // `secondLook`: whether an empty voxel looks again at a random texel of its footprint (SceneVoxelization does; off,
  // the oracle tells what the point's own pixel alone would fill).
  InjectionOracle(float voxelSize, uint32_t invalidFramesToClear, glm::vec3 viewpoint, bool secondLook = true)
      : voxelSize_(voxelSize),
        invalidFramesToClear_(invalidFramesToClear),
        viewpoint_(viewpoint),
        secondLook_(secondLook) {}

  // Every voxel a pixel of `frame` shows a surface in can become occupied; one that holds no seen point never is.
  void addCandidates(const HostFrame& frame) {
    for (const PixelSurface& surface : frame.surfaces)
      if (surface.hit) voxels_.try_emplace(key(glm::ivec3(glm::floor(held(surface) / voxelSize_))));
  }
  // A voxel to follow though no pixel shows a surface in it (for what the view observes of it).
  void addVoxel(glm::ivec3 worldVoxel) { voxels_.try_emplace(key(worldVoxel)); }

  // One injection of `frame` as an extra view with frame index `frameIndex`.
  void inject(const HostFrame& frame, uint32_t frameIndex) {
    const glm::mat4 inverse = glm::inverse(frame.viewProjection);
    for (auto& [coordinate, voxel] : voxels_) {
      const glm::ivec3 worldVoxel(std::get<0>(coordinate), std::get<1>(coordinate), std::get<2>(coordinate));
      const glm::vec3 voxelMin = glm::vec3(worldVoxel) * voxelSize_;
      const glm::vec3 samplePoint =
          voxelMin + shader::hashToUnitCube(glm::uvec3(worldVoxel) ^ glm::uvec3(0u, 0u, frameIndex * 0x9e3779b9u)) *
                         voxelSize_;
      const glm::vec4 clip = frame.viewProjection * glm::vec4(samplePoint, 1.0f);
      const glm::vec3 ndc = glm::vec3(clip) / clip.w;
      const glm::vec2 pixel = shader::ssvgiNdcToPixel(glm::vec2(ndc), glm::vec2(kSize));
      const glm::vec2 fraction = glm::fract(pixel);
      voxel.ambiguous |= glm::any(glm::lessThan(glm::min(fraction, 1.0f - fraction), glm::vec2(1e-4f)));
      if (!(clip.w > 0.0f && ndc.z <= 1.0f && ndc.z >= 0.0f) || glm::any(glm::lessThan(pixel, glm::vec2(0.0f))) ||
          glm::any(glm::greaterThanEqual(pixel, glm::vec2(kSize))))
        continue;  // Skip: not seen
      const PixelSurface& surface = frame.surfaces[size_t(pixel.y) * kSize + size_t(pixel.x)];
      // Seen through only in front of the nearest surface of the 2×2 texels nearest the point; observed only where
      // none of them shows a surface inside the voxel.
      float nearestDepth = 0.0f;
      bool surfaceAround = false;
      const glm::ivec2 firstTexel(glm::floor(pixel - 0.5f));
      for (int corner = 0; corner < 4; ++corner) {
        const glm::ivec2 neighbour =
            glm::clamp(firstTexel + glm::ivec2(corner & 1, corner >> 1), glm::ivec2(0), glm::ivec2(kSize - 1));
        nearestDepth = std::max(nearestDepth, frame.depthValues[size_t(neighbour.y) * kSize + size_t(neighbour.x)]);
        const PixelSurface& around = frame.surfaces[size_t(neighbour.y) * kSize + size_t(neighbour.x)];
        if (!around.hit) continue;
        const glm::vec3 fromMin = held(around) - voxelMin;
        voxel.ambiguous |= nearAnyOf(fromMin, 0.0f) || nearAnyOf(fromMin, voxelSize_);
        surfaceAround |= glm::all(glm::greaterThanEqual(fromMin, glm::vec3(0.0f))) &&
                         glm::all(glm::lessThan(fromMin, glm::vec3(voxelSize_)));
      }
      bool holds = holdsSurface(voxel, voxelMin, surface);
      // Failing that, an empty voxel's second look: a random texel of its footprint.
      const PixelSurface* shown = &surface;
      if (secondLook_ && !holds && !voxel.occupied) {
        if (const std::optional<glm::ivec2> texel = footprintTexel(frame, voxel, voxelMin, worldVoxel, frameIndex)) {
          shown = &frame.surfaces[size_t(texel->y) * kSize + size_t(texel->x)];
          holds = holdsSurface(voxel, voxelMin, *shown);
        }
      }
      // The line of sight through the centre of the point's own texel crosses the voxel and leaves it half a voxel
      // before the surface the texel shows, if any (observed empty).
      const float seesPastBy = sightCrossesVoxelBy(frame, glm::ivec2(pixel), surface, voxelMin);
      voxel.ambiguous |= std::abs(seesPastBy) < 1e-4f;
      if (nearestDepth <= 0.0f) {  // nothing around the point: seen through, unless the second look found the surface
        if (holds) {
          occupy(voxel, *shown);
        } else {
          countSeenThrough(voxel);
        }
        voxel.observed |= voxel.occupied || seesPastBy > 0.0f;
        continue;
      }
      const glm::vec3 heldPoint = held(surface);
      const glm::vec4 nearPoint = inverse * glm::vec4(glm::vec2(ndc), 1.0f, 1.0f);
      const glm::vec4 fartherPoint = inverse * glm::vec4(glm::vec2(ndc), 0.5f, 1.0f);
      const glm::vec3 rayDirection =
          glm::normalize(glm::vec3(fartherPoint) / fartherPoint.w - glm::vec3(nearPoint) / nearPoint.w);
      const glm::vec4 nearest = inverse * glm::vec4(glm::vec2(ndc), nearestDepth, 1.0f);
      const float inFrontBy = glm::dot(glm::vec3(nearest) / nearest.w - samplePoint, rayDirection) - 0.5f * voxelSize_;
      const float planeCut = 0.5f * voxelSize_ * glm::dot(glm::abs(surface.normal), glm::vec3(1.0f)) -
                             std::abs(glm::dot(voxelMin + 0.5f * voxelSize_ - heldPoint, surface.normal));
      voxel.ambiguous |= std::abs(inFrontBy) < 1e-4f || std::abs(planeCut) < 1e-4f;
      const bool cut = surface.hit && planeCut > 0.0f;  // no surface at the point's own texel: no plane
      const bool refreshes = voxel.occupied && cut &&
                             glm::distance(heldPoint, glm::clamp(heldPoint, voxelMin, voxelMin + voxelSize_)) <=
                                 voxelSize_ &&
                             glm::dot(voxel.normal, surface.normal) > 0.9f;
      if (holds) {
        occupy(voxel, *shown);
      } else if (refreshes) {
        voxel.seenThrough = 0;
      } else {
        if (inFrontBy > 0.0f && !cut) countSeenThrough(voxel);
        voxel.observed |= seesPastBy > 0.0f && !cut && !surfaceAround;
      }
      voxel.observed |= voxel.occupied;
    }
  }

  // The voxels that end occupied, and those whose fate the GPU's rounding may change.
  std::set<std::tuple<int, int, int>> occupied() const { return select([](const Voxel& v) { return v.occupied; }); }
  std::set<std::tuple<int, int, int>> ambiguous() const { return select([](const Voxel& v) { return v.ambiguous; }); }
  // The voxels a view has seen holding a surface or seen through (Brick::observed), of those followed.
  std::set<std::tuple<int, int, int>> observed() const { return select([](const Voxel& v) { return v.observed; }); }
  std::set<std::tuple<int, int, int>> followed() const { return select([](const Voxel&) { return true; }); }

 private:
  struct Voxel {
    bool occupied = false;
    bool ambiguous = false;
    uint32_t seenThrough = 0;
    glm::vec3 normal{0.0f};
    bool observed = false;
  };
  static std::tuple<int, int, int> key(glm::ivec3 v) { return {v.x, v.y, v.z}; }
  glm::vec3 held(const PixelSurface& surface) const { return surface.position - surface.normal * (0.01f * voxelSize_); }
  // Valid: the surface lies inside the voxel, unless it would turn the voxel's surface round — of two opposite faces,
  // a voxel keeps the one towards the volume's middle.
  bool holdsSurface(Voxel& voxel, glm::vec3 voxelMin, const PixelSurface& surface) const {
    const glm::vec3 fromMin = held(surface) - voxelMin;
    const bool turnsAround = voxel.occupied && glm::dot(voxel.normal, surface.normal) < 0.0f &&
                             glm::dot(surface.normal, viewpoint_ - (voxelMin + 0.5f * voxelSize_)) <= 0.0f;
    if (surface.hit) voxel.ambiguous |= nearAnyOf(fromMin, 0.0f) || nearAnyOf(fromMin, voxelSize_);
    return surface.hit && !turnsAround && glm::all(glm::greaterThanEqual(fromMin, glm::vec3(0.0f))) &&
           glm::all(glm::lessThan(fromMin, glm::vec3(voxelSize_)));
  }
  // The texel of the second look: a random one (voxelFootprintSeed) of the bounding rectangle of the voxel's
  // corners' projections, clipped to the image; none where that lies off the image or behind the eye.
  static std::optional<glm::ivec2> footprintTexel(const HostFrame& frame, Voxel& voxel, glm::vec3 voxelMin,
                                                  glm::ivec3 worldVoxel, uint32_t frameIndex) {
    glm::vec2 lowest(3.0e38f), highest(-3.0e38f);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 point = voxelMin + kVoxel * glm::vec3(corner & 1, (corner >> 1) & 1, corner >> 2);
      const glm::vec4 clip = frame.viewProjection * glm::vec4(point, 1.0f);
      if (clip.w <= 0.0f) return std::nullopt;
      const glm::vec2 pixel = shader::ssvgiNdcToPixel(glm::vec2(clip) / clip.w, glm::vec2(kSize));
      lowest = glm::min(lowest, pixel);
      highest = glm::max(highest, pixel);
    }
    lowest = glm::max(lowest, glm::vec2(0.0f));
    highest = glm::min(highest, glm::vec2(float(kSize) - 1.0f));
    if (glm::any(glm::greaterThan(lowest, highest))) return std::nullopt;
    const glm::vec2 pick = glm::vec2(shader::hashToUnitCube(shader::voxelFootprintSeed(glm::uvec3(worldVoxel), frameIndex)));
    const glm::vec2 texel = glm::mix(lowest, highest, pick);
    const glm::vec2 fraction = glm::fract(texel);
    voxel.ambiguous |= glm::any(glm::lessThan(glm::min(fraction, 1.0f - fraction), glm::vec2(1e-3f)));
    return glm::ivec2(texel);
  }
  // How far the line of sight through the centre of `texel` (along which the view measured its depth) passes inside
  // the voxel's box before leaving it, and leaves it more than half a voxel before the surface the texel shows: the
  // smaller of the two margins, positive where both hold (SceneVoxelization's sightCrossesVoxel).
  float sightCrossesVoxelBy(const HostFrame& frame, glm::ivec2 texel, const PixelSurface& surface,
                            glm::vec3 voxelMin) const {
    const glm::mat4 inverse = glm::inverse(frame.viewProjection);
    const glm::vec2 ndc = shader::ssvgiPixelToNdc(glm::vec2(texel), glm::vec2(kSize));
    const glm::vec4 nearPoint = inverse * glm::vec4(ndc, 1.0f, 1.0f);
    const glm::vec4 fartherPoint = inverse * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 origin = glm::vec3(nearPoint) / nearPoint.w;
    const glm::vec3 direction = glm::normalize(glm::vec3(fartherPoint) / fartherPoint.w - origin);
    const glm::vec2 span = shader::intersectBounds(origin, shader::safeInverseDirection(direction), voxelMin,
                                                   voxelMin + glm::vec3(voxelSize_));
    const float crossing = span.y - std::max(span.x, 0.0f);
    if (!surface.hit) return crossing;
    return std::min(crossing, glm::dot(surface.position - origin, direction) - 0.5f * voxelSize_ - span.y);
  }
  static bool nearAnyOf(glm::vec3 values, float boundary) {
    return glm::any(glm::lessThan(glm::abs(values - boundary), glm::vec3(1e-4f)));
  }
  // Valid: the voxel holds the surface shown, and its counter starts again.
  static void occupy(Voxel& voxel, const PixelSurface& surface) {
    voxel.occupied = true;
    voxel.seenThrough = 0;
    voxel.normal = surface.normal;
  }
  void countSeenThrough(Voxel& voxel) const {
    if (!voxel.occupied) return;
    if (++voxel.seenThrough >= invalidFramesToClear_) voxel = Voxel{false, voxel.ambiguous, 0, glm::vec3(0.0f), true};
  }
  template <typename Predicate>
  std::set<std::tuple<int, int, int>> select(Predicate predicate) const {
    std::set<std::tuple<int, int, int>> selected;
    for (const auto& [coordinate, voxel] : voxels_)
      if (predicate(voxel)) selected.insert(coordinate);
    return selected;
  }

  float voxelSize_;
  uint32_t invalidFramesToClear_;
  glm::vec3 viewpoint_;
  bool secondLook_;
  std::map<std::tuple<int, int, int>, Voxel> voxels_;
};

using VoxelSet = std::set<testing::VoxelCoordinate>;

// The GPU's occupied voxels against an oracle's: each one it has not marked ambiguous must be expected, and each
// expected one occupied. Returns how many occupied voxels were compared.
uint32_t expectAsTheOracle(const std::map<testing::VoxelCoordinate, shader::Voxel>& occupied, const VoxelSet& expected,
                           const VoxelSet& ambiguous) {
  uint32_t compared = 0;
  for (const auto& [coordinate, voxel] : occupied) {
    if (ambiguous.count(coordinate)) continue;
    ++compared;
    const auto [x, y, z] = coordinate;
    EXPECT_TRUE(expected.count(coordinate)) << "voxel " << x << "," << y << "," << z << " should be empty";
  }
  for (const auto& coordinate : expected) {
    const auto [x, y, z] = coordinate;
    if (!ambiguous.count(coordinate)) {
      EXPECT_TRUE(occupied.count(coordinate)) << "voxel " << x << "," << y << "," << z << " missing";
    }
  }
  return compared;
}

// The corner of the scroll step under the camera, metres (volumeViewpoint: where the face a voxel keeps of two
// opposite ones looks).
glm::vec3 volumeViewpoint(const Context& context) {
  const shader::VoxelVolume& volume = gi::voxelSceneOf(context).current();
  const glm::ivec3 brick =
      volume.originBrick + volume.dimensionsBricks / 2 - glm::ivec3(0, volume.verticalShiftBricks, 0);
  return glm::vec3(brick) * volume.brickSize;
}

// A camera at `position` looking straight up into an empty sky: it places the volume and allocates nothing, so that
// what the voxels hold comes from the extra views alone.
renderer::Camera lookingUp(glm::vec3 position) {
  renderer::Camera camera = lookingDown(position);
  camera.target = camera.position + glm::vec3(0.0f, 1.0f, 0.0f);
  return camera;
}

TEST_F(VoxelScene, anOrthographicViewInjectsExactlyTheVoxelsItsRulesGive) {
  // An orthographic extra view (a sun's reflective shadow map) from 48° above the horizon over a 6 m square: the floor
  // and a 1 m box standing on it, whose faces lie off the voxel grid. The camera looks up at an empty sky and has no
  // lit frame, so what the voxels hold comes from this view alone. After 32 injections the occupied voxels must be
  // exactly those the CPU oracle of the injection rules gives, each in its surface's colour and normal. Then the view's
  // near plane moves into the box: it sees the floor through the box's clipped top, which must not clear the box's
  // voxels in front of that plane. Then the box is taken away: its voxels, seen through, go as the oracle says.
  const Settings settings = smallSettings();
  create(settings);
  const glm::vec3 centre(0.5f, 0.1f, 0.5f);
  const glm::vec3 towardsViewer = glm::normalize(glm::vec3(1.0f, 1.4f, 0.8f));
  const glm::mat4 view = glm::lookAtRH(centre + 8.0f * towardsViewer, centre, glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::mat4 projection = renderer::reversedZOrthographicProjection(-3.0f, 3.0f, -3.0f, 3.0f, 1.0f, 16.0f);
  const TestBox box{{0.3f, 0.1f, -0.4f}, {1.3f, 1.1f, 0.6f}, {0.125f, 0.5f, 0.25f}};
  const HostFrame withBox(device(), view, projection, {kFloor, box});
  const HostFrame floorOnly(device(), view, projection, {kFloor});
  // The box's top lies 6.8 to 7.7 m from the view's plane.
  const HostFrame nearPlaneInTheBox(device(), view,
                                    renderer::reversedZOrthographicProjection(-3.0f, 3.0f, -3.0f, 3.0f, 7.3f, 16.0f),
                                    {kFloor, box});
  const HostFrame sky(device(), lookingUp({0.5f, 1.0f, 0.5f}), {});

  dispatch(sky, nullptr);  // places the volume around the camera
  InjectionOracle oracle(kVoxel, settings.invalidFramesToClear, volumeViewpoint(*context_));
  oracle.addCandidates(withBox);
  oracle.addCandidates(floorOnly);
  oracle.addCandidates(nearPlaneInTheBox);
  auto injectFrames = [&](const HostFrame& frame, uint32_t frames) {
    for (uint32_t i = 0; i < frames; ++i) {
      oracle.inject(frame, frameIndex_);
      dispatch(sky, nullptr, {extraView(frame)});
    }
  };
  auto expectOracle = [&](const char* phase) {
    SCOPED_TRACE(phase);
    const auto occupied = occupiedVoxels(readState());
    const auto expected = oracle.occupied(), ambiguous = oracle.ambiguous();
    const uint32_t compared = expectAsTheOracle(occupied, expected, ambiguous);
    for (const auto& [coordinate, voxel] : occupied) {
      const auto [x, y, z] = coordinate;
      if (ambiguous.count(coordinate)) continue;
      // A voxel of the floor's layer (y = 0) facing up holds the floor; any other, the box — but for the voxels of
      // the box's foot (x 1–5, z −2–2 in the floor's layer), where both meet and an extra view averages what it
      // sees of either.
      const glm::vec3 normal = shader::voxelNormal(voxel);
      const bool boxFoot = y == 0 && x >= 1 && x <= 5 && z >= -2 && z <= 2;
      const glm::vec3 colour = y == 0 && normal.y > 0.99f ? kFloor.radiance : box.radiance;
      const glm::vec3 radiance = shader::unpackR11G11B10F(voxel.radiance);
      if (!boxFoot) {
        EXPECT_NEAR(radiance.y, colour.y, colour.y / 64.0f) << "voxel " << x << "," << y << "," << z;
      }
      EXPECT_GT(glm::max(glm::abs(normal).x, glm::max(glm::abs(normal).y, glm::abs(normal).z)), 0.99f)
          << "voxel " << x << "," << y << "," << z << ": not a box face's normal";
    }
    EXPECT_GT(compared, 300u);
    EXPECT_LT(ambiguous.size(), expected.size() / 10) << "too few voxels decided clearly to test";
    std::printf("%s: %u voxels compared, all as the oracle says; %zu left out as ambiguous\n", phase, compared,
                ambiguous.size());
  };
  injectFrames(withBox, 32);
  expectOracle("the floor and the box");
  const size_t boxVoxels = oracle.occupied().size();
  injectFrames(nearPlaneInTheBox, 2 * settings.invalidFramesToClear);
  expectOracle("the near plane in the box");
  EXPECT_GE(oracle.occupied().size(), boxVoxels) << "voxels in front of the near plane were cleared";
  injectFrames(floorOnly, 2 * settings.invalidFramesToClear);
  expectOracle("the box taken away");
}

// The albedo of a scene of boxes for a view lit by direct light only: 0.5 everywhere.
std::vector<TestBox> greyAlbedo(std::vector<TestBox> boxes) {
  for (TestBox& box : boxes) box.radiance = glm::vec3(0.5f);
  return boxes;
}

// What the voxel scene holds in each live brick, by its world brick coordinate (its slot in the pool set aside).
struct HeldBrick {
  uint64_t occupancy;  // a bit per voxel (bit = x + 4y + 16z)
  uint64_t observed;
  std::array<shader::Voxel, shader::kVoxelsPerBrick> voxels;
};

std::map<testing::VoxelCoordinate, HeldBrick> heldBricks(const GpuState& state) {
  std::map<testing::VoxelCoordinate, HeldBrick> held;
  for (uint32_t b = 0; b < state.pool.bumpCount; ++b) {
    const shader::Brick& brick = state.bricks[b];
    if (brick.live == 0u) continue;
    HeldBrick& entry = held[{brick.coordinate.x, brick.coordinate.y, brick.coordinate.z}];
    entry.occupancy = uint64_t(brick.occupancy.y) << 32 | brick.occupancy.x;
    entry.observed = uint64_t(brick.observed.y) << 32 | brick.observed.x;
    std::copy_n(state.voxels.begin() + b * shader::kVoxelsPerBrick, shader::kVoxelsPerBrick, entry.voxels.begin());
  }
  return held;
}

TEST_F(VoxelScene, occlusionCullingLeavesOutOnlyWhatInjectingWouldNotChange) {
  // Two walls off the voxel grid on the floor, the far one turned about the vertical, and between them a pillar and a
  // box tilted off it. A still camera (its lit frame is its current one) looks at the near wall from askew and sees
  // little behind it; two extra views see in between: a perspective one from the open side, low, and an orthographic
  // reflective shadow map from above askew (the sun's, which writes its shadow into the occupied voxels behind what it
  // shows). The injection leaves out the bricks and the blocks of 2×2×2 voxels that lie behind what each view drew
  // (Settings::occlusionCulling; of the sun's, only those holding no occupied voxel, a rule this scene would pass
  // without and the roof test below needs), which must change nothing: after the same frames with the culling on and
  // off — the box there, then every surface in another colour, then the box taken away, so that its voxels are seen
  // through and cleared — every live brick holds the same voxels, bit for bit, and the same observed voxels. A block or
  // brick tested at the wrong place (a block at twice its offset, the blocks in mirrored order) or against the wrong
  // depth leaves out a voxel a view would have filled, cleared or observed. And the culling must leave out work.
  constexpr uint32_t kExtraViewSize = 256;  // texels narrower than voxels: a tight Hi-Z
  const glm::mat3 turnedAboutY(glm::rotate(glm::mat4(1.0f), glm::radians(35.0f), glm::vec3(0.0f, 1.0f, 0.0f)));
  const glm::mat3 tilted(glm::rotate(glm::mat4(1.0f), glm::radians(25.0f), glm::vec3(0.3f, 0.0f, 1.0f)));
  const std::vector<TestBox> withBox = {
      kFloor,
      {{-1.43f, 0.1f, 0.93f}, {2.11f, 1.57f, 1.17f}, {0.5f, 0.375f, 0.25f}},                   // the near wall
      {{-1.43f, 0.1f, -1.93f}, {2.11f, 1.83f, -1.71f}, {0.25f, 0.5f, 0.375f}, turnedAboutY},  // the far wall
      {{0.37f, 0.1f, -0.77f}, {1.29f, 0.93f, 0.11f}, {0.125f, 0.5f, 0.25f}, tilted},          // the box
      {{-0.63f, 0.1f, -0.71f}, {-0.39f, 1.33f, -0.47f}, {0.25f, 0.25f, 0.5f}},                // the pillar
  };
  std::vector<TestBox> recoloured = withBox;  // the light changes
  for (TestBox& box : recoloured) box.radiance = glm::vec3(box.radiance.z, 2.0f * box.radiance.x, box.radiance.y);
  const std::vector<TestBox> withoutBox = {recoloured[0], recoloured[1], recoloured[2], recoloured[4]};
  const renderer::Camera camera = looking({1.9f, 1.3f, 3.6f}, {0.1f, 0.6f, 0.0f}, 50.0f);
  const renderer::Camera side = looking({-3.1f, 0.7f, -0.2f}, {1.0f, 0.4f, -0.5f}, 50.0f);
  const glm::vec3 centre(0.3f, 0.4f, -0.4f);
  const glm::mat4 above = glm::lookAtRH(centre + 8.0f * glm::normalize(glm::vec3(-0.7f, 1.3f, 0.5f)), centre,
                                        glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::mat4 orthographic = renderer::reversedZOrthographicProjection(-3.0f, 3.0f, -3.0f, 3.0f, 1.0f, 16.0f);
  struct Views {
    HostFrame camera, side, above, aboveAlbedo;
  };
  const auto viewsOf = [&](const std::vector<TestBox>& boxes) {
    return Views{{device(), camera, boxes},
                 {device(), side, boxes, kExtraViewSize},
                 {device(), above, orthographic, boxes, kExtraViewSize},
                 {device(), above, orthographic, greyAlbedo(boxes), kExtraViewSize}};
  };
  const std::array<Views, 3> scenes = {viewsOf(withBox), viewsOf(recoloured), viewsOf(withoutBox)};

  const auto run = [&](bool occlusionCulling) {
    Settings settings = smallSettings();
    settings.occlusionCulling = occlusionCulling;
    create(settings, kExtraViewSize);
    frameIndex_ = 0;
    uint64_t injectedVoxels = 0;
    for (const Views& views : scenes)
      for (uint32_t frame = 0; frame < 3 * settings.invalidFramesToClear; ++frame) {
        countWork_ = true;
        ExtraView sun = extraView(views.above, &views.aboveAlbedo);
        sun.isReflectiveShadowMap = true;
        dispatch(views.camera, &views.camera, {extraView(views.side), sun});
        const Stats stats = context_->stats();
        injectedVoxels += stats.work.sceneVoxelization.voxels + stats.work.extraViewVoxelization.voxels;
      }
    countWork_ = false;
    return std::pair(heldBricks(readState()), injectedVoxels);
  };
  const auto [culled, culledWork] = run(true);
  const auto [whole, wholeWork] = run(false);

  uint32_t occupied = 0, differing = 0;
  for (const auto& [coordinate, brick] : whole) {
    const auto [x, y, z] = coordinate;
    const auto found = culled.find(coordinate);
    if (found == culled.end()) {
      ADD_FAILURE() << "brick " << x << "," << y << "," << z << " is live only without the culling";
      continue;
    }
    occupied += uint32_t(std::popcount(brick.occupancy));
    EXPECT_EQ(found->second.occupancy, brick.occupancy) << "brick " << x << "," << y << "," << z;
    EXPECT_EQ(found->second.observed, brick.observed) << "brick " << x << "," << y << "," << z;
    for (uint32_t v = 0; v < shader::kVoxelsPerBrick; ++v)
      if (std::memcmp(&found->second.voxels[v], &brick.voxels[v], sizeof(shader::Voxel)) != 0 && differing++ < 8)
        ADD_FAILURE() << "brick " << x << "," << y << "," << z << " voxel " << v << " differs";
  }
  EXPECT_EQ(culled.size(), whole.size()) << "live bricks";
  EXPECT_EQ(differing, 0u) << "voxels that differ";
  EXPECT_GT(occupied, 400u) << "too few voxels to test";
  EXPECT_LT(culledWork, wholeWork * 9 / 10) << "the culling left out too little to test";
  std::printf("%u occupied voxels in %zu live bricks the same; %llu voxels injected with the culling, %llu without\n",
              occupied, whole.size(), static_cast<unsigned long long>(culledWork),
              static_cast<unsigned long long>(wholeWork));
}

// The share of a floor voxel's top face (y = 0.1) that a view's texels show lit: the texel each point projects to
// shows the floor there, not something above it (the shadow's edge as the view's texels draw it, on a grid of 16×16
// points).
float litShareAsTexelsShowIt(const HostFrame& view, int x, int z) {
  constexpr int kPoints = 16;
  int lit = 0;
  for (int i = 0; i < kPoints; ++i)
    for (int j = 0; j < kPoints; ++j) {
      const glm::vec3 point((float(x) + (float(i) + 0.5f) / kPoints) * kVoxel, kFloor.max.y,
                            (float(z) + (float(j) + 0.5f) / kPoints) * kVoxel);
      const glm::vec4 clip = view.viewProjection * glm::vec4(point, 1.0f);
      const glm::vec2 pixel = shader::ssvgiNdcToPixel(glm::vec2(clip) / clip.w, glm::vec2(kSize));
      const PixelSurface& shown = view.surfaces[size_t(pixel.y) * kSize + size_t(pixel.x)];
      lit += shown.hit && shown.position.y < kFloor.max.y + 0.01f;
    }
  return float(lit) / float(kPoints * kPoints);
}

// The sun's view of a scene of boxes on the floor, 63° above the horizon towards +x (orthographic, 6 m across), with
// what a reflective shadow map of it needs: its colour (the boxes' light) and its albedo (greyAlbedo).
struct SunsView {
  SunsView(gpu::OwnedDevice& device, const std::vector<TestBox>& boxes)
      : lit(device, view(), projection(), boxes), albedo(device, view(), projection(), greyAlbedo(boxes)) {}

  static glm::mat4 view() {
    const glm::vec3 centre(0.5f, 0.1f, 0.5f);
    const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f));
    return glm::lookAtRH(centre + 8.0f * towardsSun, centre, glm::vec3(0.0f, 0.0f, -1.0f));
  }
  static glm::mat4 projection() {
    return renderer::reversedZOrthographicProjection(-3.0f, 3.0f, -3.0f, 3.0f, 1.0f, 16.0f);
  }
  ExtraView given(bool isReflectiveShadowMap) const {
    ExtraView extra = extraView(lit, &albedo);
    extra.isReflectiveShadowMap = isReflectiveShadowMap;
    return extra;
  }

  HostFrame lit;
  HostFrame albedo;
};

TEST_F(VoxelScene, aReflectiveShadowMapTakesTheLightOfTheFloorItsLightNoLongerReachesAndOfThePartItsShadowCovers) {
  // A sun's reflective shadow map (orthographic, the sun 63° above the horizon towards +x) over a lit floor, the only
  // extra view, while the camera looks up at an empty sky. Then a slab appears 0.9 m above the floor, its shadow on the
  // floor at x < 0.125 m (the slab ends at x = 0.575; the sun's rays climb 0.9 m over 0.45 m): the voxel column x = 0
  // lies partly in it. The view sees only the lit part of the floor. Over a strip of floor voxels across the shadow's
  // edge (x and z from −1 to 1 m: 8 rows of 8), a row's direct light must come to the lit area's, as the view's
  // 0.105 m texels draw the shadow's edge (litShareAsTexelsShowIt): about 3.7 voxels' worth of the floor's light with
  // isReflectiveShadowMap. The voxels wholly in shadow lose theirs (0.75 kept per injection, 24 of them); a voxel the
  // edge crosses holds an average of lit and dark samples, whose noise over 8 rows is ±0.07 voxel: ±0.25 is three and
  // a half times that. Without the flag, what the view cannot see is unknown to it, and a row keeps all 8 voxels'
  // worth.
  const TestBox slab{{-3.0f, 1.0f, -3.0f}, {0.575f, 1.1f, 3.0f}, {0.2f, 0.2f, 0.2f}};
  const SunsView lit(device(), {kFloor}), shaded(device(), {kFloor, slab});
  const HostFrame sky(device(), lookingUp({0.5f, 1.0f, 0.5f}), {});
  float litArea = 0.0f;  // per row, in voxels
  for (int z = -4; z < 4; ++z)
    for (int x = -4; x < 4; ++x) litArea += litShareAsTexelsShowIt(shaded.lit, x, z) / 8.0f;

  for (const bool isReflectiveShadowMap : {true, false}) {
    SCOPED_TRACE(isReflectiveShadowMap ? "a reflective shadow map" : "a view that does not say it is one");
    create(smallSettings());
    for (uint32_t frame = 0; frame < 24; ++frame) dispatch(sky, nullptr, {lit.given(isReflectiveShadowMap)});
    for (uint32_t frame = 0; frame < 24; ++frame) dispatch(sky, nullptr, {shaded.given(isReflectiveShadowMap)});
    const auto occupied = occupiedVoxels(readState());
    float rowDirect = 0.0f, shadowedDirect = 0.0f, litDirect = 0.0f;
    for (int z = -4; z < 4; ++z)
      for (int x = -4; x < 4; ++x) {
        const auto voxel = occupied.find({x, 0, z});
        ASSERT_NE(voxel, occupied.end()) << "floor voxel " << x << ",0," << z << " missing";
        const float direct = shader::unpackR11G11B10F(voxel->second.directRadiance).y / kFloor.radiance.y;
        rowDirect += direct / 8.0f;
        if (x < 0) shadowedDirect = std::max(shadowedDirect, direct);
        if (x > 0) litDirect += direct / 24.0f;
      }
    std::printf("%s: a row holds %.3f voxels' worth of the floor's direct light (lit area %.3f); in the shadow at most "
                "%.3f, lit %.3f\n",
                isReflectiveShadowMap ? "reflective shadow map" : "without the flag", rowDirect, litArea,
                shadowedDirect, litDirect);
    EXPECT_NEAR(litDirect, 1.0f, 0.02f);
    if (isReflectiveShadowMap) {
      EXPECT_NEAR(rowDirect, litArea, 0.25f);
      EXPECT_LT(shadowedDirect, 0.02f);
    } else {
      EXPECT_NEAR(rowDirect, 8.0f, 0.1f);
    }
  }
}

TEST_F(VoxelScene, aFloorASunsReflectiveShadowMapLitLosesItsLightWhenARoofHighAboveThenHidesItWhole) {
  // The previous test's sun over the lit floor; then a roof 2.4 m above the floor covers all the view shows, so that
  // the floor's bricks lie wholly behind it — far past the margins of the Hi-Z culling (Settings::occlusionCulling, on).
  // A reflective shadow map writes its light's shadow into the occupied voxels behind what it shows, so the culling
  // must not leave those out: every floor voxel of a 4 m square under the roof loses its direct light (0.75 kept per
  // injection: 0.001 after 24). Left out, they kept all of it.
  const TestBox roof{{-8.0f, 2.5f, -8.0f}, {8.0f, 2.6f, 8.0f}, {0.2f, 0.2f, 0.2f}};
  const SunsView lit(device(), {kFloor}), roofed(device(), {kFloor, roof});
  const HostFrame sky(device(), lookingUp({0.5f, 1.0f, 0.5f}), {});
  create(smallSettings());
  for (uint32_t frame = 0; frame < 24; ++frame) dispatch(sky, nullptr, {lit.given(true)});
  const auto before = occupiedVoxels(readState());
  for (uint32_t frame = 0; frame < 24; ++frame) dispatch(sky, nullptr, {roofed.given(true)});
  const auto after = occupiedVoxels(readState());
  float litBefore = 1.0f, keptAfter = 0.0f;
  for (int z = -8; z < 8; ++z)
    for (int x = -8; x < 8; ++x) {
      const auto voxelBefore = before.find({x, 0, z}), voxelAfter = after.find({x, 0, z});
      ASSERT_NE(voxelBefore, before.end()) << "floor voxel " << x << ",0," << z << " missing";
      ASSERT_NE(voxelAfter, after.end()) << "floor voxel " << x << ",0," << z << " gone";
      const float fullLight = kFloor.radiance.y;
      litBefore = std::min(litBefore, shader::unpackR11G11B10F(voxelBefore->second.directRadiance).y / fullLight);
      keptAfter = std::max(keptAfter, shader::unpackR11G11B10F(voxelAfter->second.directRadiance).y / fullLight);
    }
  std::printf("the floor's direct light: at least %.3f of the sun's before the roof, at most %.3f under it\n",
              litBefore, keptAfter);
  EXPECT_GT(litBefore, 0.98f);
  EXPECT_LT(keptAfter, 0.02f);
}

// The grazing view of the floor, to be given as an extra view while the camera looks straight up into an empty sky, so
// that what the voxels hold comes from that view alone.
struct GrazedFloor {
  explicit GrazedFloor(gpu::OwnedDevice& device)
      : floor(device, grazingFloorCamera(), {kFloor}), sky(device, lookingUp({0.5f, 1.0f, 0.5f}), {}) {}
  HostFrame floor;
  HostFrame sky;
};

TEST_F(VoxelScene, anEmptyVoxelOfAFloorSeenAtAGrazingAngleIsFilledByALookAtItsFootprint) {
  // The grazing view of the floor (6° to 21° over the 44 voxels ahead) as an extra view: a random point of a floor
  // voxel projects to a pixel that shows the floor a voxel or more away unless it lies within a few centimetres of the
  // floor's plane, so the point's own pixel fills few of them per injection. The second look at a random texel of an
  // empty voxel's footprint finds the floor inside it more often. After 4 injections the occupied voxels are exactly
  // those of the oracle, and the floor ahead has clearly more of them than the point's pixels alone would fill.
  const Settings settings = smallSettings();
  create(settings);
  const GrazedFloor view(device());
  dispatch(view.sky, nullptr);  // places the volume around the camera
  InjectionOracle oracle(kVoxel, settings.invalidFramesToClear, volumeViewpoint(*context_));
  InjectionOracle pointOnly(kVoxel, settings.invalidFramesToClear, volumeViewpoint(*context_), false);
  oracle.addCandidates(view.floor);
  pointOnly.addCandidates(view.floor);
  for (uint32_t injection = 0; injection < 4; ++injection) {
    oracle.inject(view.floor, frameIndex_);
    pointOnly.inject(view.floor, frameIndex_);
    dispatch(view.sky, nullptr, {extraView(view.floor)});
  }
  // The view sees the floor to the horizon; the voxels are those inside the volume.
  const shader::VoxelVolume& volume = gi::voxelSceneOf(*context_).current();
  const glm::ivec3 volumeMin = glm::ivec3(volume.originBrick) * int(shader::kBrickSizeVoxels);
  const glm::ivec3 volumeMax = volumeMin + glm::ivec3(volume.dimensionsBricks) * int(shader::kBrickSizeVoxels);
  VoxelSet expected;
  for (const auto& [x, y, z] : oracle.occupied())
    if (glm::all(glm::greaterThanEqual(glm::ivec3(x, y, z), volumeMin)) &&
        glm::all(glm::lessThan(glm::ivec3(x, y, z), volumeMax)))
      expected.insert({x, y, z});
  const VoxelSet ambiguous = oracle.ambiguous();
  const uint32_t compared = expectAsTheOracle(occupiedVoxels(readState()), expected, ambiguous);
  EXPECT_GT(compared, 40u);
  const auto ahead = [](const std::set<std::tuple<int, int, int>>& voxels) {
    uint32_t count = 0;
    for (int x = 0; x <= 3; ++x)
      for (int z = -16; z <= -6; ++z) count += uint32_t(voxels.count({x, 0, z}));
    return count;
  };
  std::printf("%u voxels compared, all as the oracle says (%zu ambiguous); of the 44 voxels of the floor ahead after 4 "
              "injections: %u with the second look, %u without\n",
              compared, ambiguous.size(), ahead(expected), ahead(pointOnly.occupied()));
  EXPECT_GE(ahead(expected), ahead(pointOnly.occupied()) + 8u);
}

// Brick::observed of every voxel of every live brick.
std::map<testing::VoxelCoordinate, bool> observedBits(const GpuState& state) {
  std::map<testing::VoxelCoordinate, bool> observed;
  for (uint32_t b = 0; b < state.pool.bumpCount; ++b) {
    const shader::Brick& brick = state.bricks[b];
    if (brick.live == 0u) continue;
    for (uint32_t v = 0; v < shader::kVoxelsPerBrick; ++v) {
      const glm::ivec3 voxel = brick.coordinate * 4 + glm::ivec3(v & 3, (v >> 2) & 3, v >> 4);
      observed[{voxel.x, voxel.y, voxel.z}] = (((v < 32 ? brick.observed.x : brick.observed.y) >> (v & 31u)) & 1u) != 0;
    }
  }
  return observed;
}

TEST_F(VoxelScene, aViewObservesTheVoxelsItSeesThroughOrFilledButNotTheHolesOfAFloorItGrazes) {
  // The grazing view of the floor as an extra view, as above. Brick::observed (SPEC §6.4 at the voxel's scale) must be
  // exactly the oracle's: the voxels above the floor's layer that a random point saw through, and every voxel that was
  // filled. The floor's layer is cut by the floor's plane, so a point of one of its empty voxels that sees the floor
  // further on does not observe it: the holes a grazing view leaves stay unobserved, and a probe ray that watches
  // observed space ends there rather than passing through the floor (voxel_trace.glsl).
  const Settings settings = smallSettings();
  create(settings);
  const GrazedFloor view(device());
  dispatch(view.sky, nullptr);  // places the volume around the camera
  InjectionOracle oracle(kVoxel, settings.invalidFramesToClear, volumeViewpoint(*context_));
  for (int x = -8; x <= 8; ++x)
    for (int y = 0; y < int(shader::kBrickSizeVoxels); ++y)
      for (int z = -40; z <= 4; ++z) oracle.addVoxel({x, y, z});
  for (uint32_t injection = 0; injection < 4; ++injection) {
    oracle.inject(view.floor, frameIndex_);
    dispatch(view.sky, nullptr, {extraView(view.floor)});
  }
  const std::map<testing::VoxelCoordinate, bool> gpuObserved = observedBits(readState());
  const auto expected = oracle.observed(), ambiguous = oracle.ambiguous(), occupied = oracle.occupied();
  uint32_t compared = 0, observedAbove = 0, unobservedHoles = 0;
  for (const auto& coordinate : oracle.followed()) {
    const auto found = gpuObserved.find(coordinate);
    if (found == gpuObserved.end() || ambiguous.count(coordinate)) continue;  // no brick here, or a rounding's call
    ++compared;
    const auto [x, y, z] = coordinate;
    EXPECT_EQ(found->second, expected.count(coordinate) != 0) << "voxel " << x << "," << y << "," << z;
    observedAbove += y > 0 && found->second;
    unobservedHoles += y == 0 && !found->second && !occupied.count(coordinate);
  }
  std::printf("%u voxels of live bricks compared, all as the oracle says: %u observed above the floor's layer, %u holes "
              "in it unobserved\n", compared, observedAbove, unobservedHoles);
  EXPECT_GT(compared, 300u);
  EXPECT_GT(observedAbove, 100u);
  EXPECT_GT(unobservedHoles, 5u);
}

TEST_F(VoxelScene, aViewFromAboveDoesNotObserveAWallHiddenUnderARoofsRimThatItsTexelsStraddle) {
  // A wall one voxel thick (x from 1.5 to 1.75 m) under a roof flush with its outer face, seen straight down by an
  // orthographic view of 0.25 m texels (a voxel) placed so that a texel spans x 1.7 to 1.95: its centre, where the view
  // measured its depth, lies beyond the rim and sees the floor, while a fifth of the texel lies over the wall. No view
  // sees the wall, so its voxels in the floor's brick stay empty; a random point of one that projects into that texel
  // lies in front of the floor that texel shows, but the texel's line of sight passes beside the voxel, which is hidden
  // under the roof: it must not be observed, or a probe ray would cross the wall there as open air (the hall's sky
  // through its walls, docs/QUALITY.md). The air beyond the rim, which that line crosses, is observed. Brick::observed
  // must also be the oracle's over the whole slab.
  const Settings settings = smallSettings();
  create(settings);
  const TestBox wall{{1.5f, 0.1f, -2.0f}, {1.75f, 2.0f, 2.0f}, {0.4f, 0.4f, 0.4f}};
  const TestBox roof{{-1.0f, 2.0f, -2.0f}, {1.75f, 2.25f, 2.0f}, {0.3f, 0.3f, 0.3f}};
  constexpr float kHalfWidth = 0.5f * float(kSize) * kVoxel;  // 8 m: texels a voxel wide
  // The view's left edge 32 texels before x = 1.7 m, so that a texel starts there.
  const glm::vec3 eye(1.7f - 32.0f * kVoxel + kHalfWidth, 10.0f, 0.0f);
  const HostFrame fromAbove(
      device(), glm::lookAtRH(eye, eye - glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f)),
      renderer::reversedZOrthographicProjection(-kHalfWidth, kHalfWidth, -kHalfWidth, kHalfWidth, 0.0f, 20.0f),
      {kFloor, wall, roof});
  const HostFrame sky(device(), lookingUp({0.5f, 1.0f, 0.5f}), {});
  dispatch(sky, nullptr);  // places the volume around the camera
  InjectionOracle oracle(kVoxel, settings.invalidFramesToClear, volumeViewpoint(*context_));
  for (int x = 4; x <= 9; ++x)
    for (int y = 0; y < int(shader::kBrickSizeVoxels); ++y)
      for (int z = -8; z <= 7; ++z) oracle.addVoxel({x, y, z});
  for (uint32_t injection = 0; injection < 16; ++injection) {
    oracle.inject(fromAbove, frameIndex_);
    dispatch(sky, nullptr, {extraView(fromAbove)});
  }
  const std::map<testing::VoxelCoordinate, bool> gpuObserved = observedBits(readState());
  const auto expected = oracle.observed(), ambiguous = oracle.ambiguous();
  uint32_t compared = 0, wallVoxels = 0, wallObserved = 0, airVoxels = 0, airObserved = 0;
  for (const auto& coordinate : oracle.followed()) {
    const auto found = gpuObserved.find(coordinate);
    ASSERT_NE(found, gpuObserved.end()) << "the floor's bricks beyond the rim are not live";
    const auto [x, y, z] = coordinate;
    if (y >= 1 && x == 6) wallVoxels += 1, wallObserved += found->second;  // the wall, above the floor's layer
    if (y >= 1 && x == 7) airVoxels += 1, airObserved += found->second;    // the air beyond the rim
    if (ambiguous.count(coordinate)) continue;
    ++compared;
    EXPECT_EQ(found->second, expected.count(coordinate) != 0) << "voxel " << x << "," << y << "," << z;
  }
  std::printf("%u voxels compared, all as the oracle says; the wall: %u of %u observed; the air beyond the rim: %u of "
              "%u\n", compared, wallObserved, wallVoxels, airObserved, airVoxels);
  EXPECT_EQ(wallVoxels, 48u);
  EXPECT_EQ(wallObserved, 0u);
  EXPECT_EQ(airObserved, airVoxels);
  EXPECT_GT(compared, 300u);
}

// A wall one voxel thick under a roof flush with its outer face, its rim at `rim`, seen straight down by an
// orthographic view whose texels are `texel` wide, one of them starting at the rim. What the view has observed of the
// brick cells one metre above the floor: x → observed, for every cell x from 1 to 4 at z = −2..1 (all four alike).
std::map<int, bool> VoxelScene::cellsObservedBesideAWallUnderARoofsRim(float rim, float texel) {
  Settings settings = smallSettings();
  settings.skyOnlyThroughObservedSpace = true;  // ObservedSpace runs
  create(settings);
  const TestBox wall{{rim - kVoxel, 0.1f, -2.0f}, {rim, 2.0f, 2.0f}, {0.4f, 0.4f, 0.4f}};
  const TestBox roof{{-1.0f, 2.0f, -2.0f}, {rim, 2.25f, 2.0f}, {0.3f, 0.3f, 0.3f}};
  const float halfWidth = 0.5f * float(kSize) * texel;
  const glm::vec3 eye(rim - 32.0f * texel + halfWidth, 10.0f, 0.0f);
  const HostFrame fromAbove(
      device(), glm::lookAtRH(eye, eye - glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f)),
      renderer::reversedZOrthographicProjection(-halfWidth, halfWidth, -halfWidth, halfWidth, 0.0f, 20.0f),
      {kFloor, wall, roof});
  // The camera looks up from (0.5, 1, 0.5) through a 30° field: its rays reach x = 1 only above y = 2.
  const HostFrame sky(device(), lookingUp({0.5f, 1.0f, 0.5f}), {});
  dispatch(sky, nullptr);
  for (uint32_t injection = 0; injection < 4; ++injection) dispatch(sky, nullptr, {extraView(fromAbove)});
  const gi::VoxelScene& scene = gi::voxelSceneOf(*context_);
  const shader::VoxelVolume volume = scene.current();
  const std::vector<uint32_t> words = gpu::readBufferAs<uint32_t>(device(), scene.observedSpace());
  std::map<int, bool> observed;
  for (int x = 1; x <= 4; ++x) {
    uint32_t cells = 0;
    for (int z = -2; z < 2; ++z) {
      const uint32_t index = shader::brickCellIndex({x, 1, z}, glm::ivec3(volume.dimensionsBricks));
      cells += (words[volume.gridWordOffsets[0] + index / 32] >> (index % 32)) & 1u;
    }
    EXPECT_TRUE(cells == 0 || cells == 4) << "x " << x << ": " << cells << " of 4";
    observed[x] = cells == 4;
  }
  return observed;
}

TEST_F(VoxelScene, aViewFromAboveObservesTheBrickCellsBesideAWallUnderARoofsRimOnlyWhereItSeesThemWhole) {
  // The view's rays past the rim cross the brick cells under it down to the floor, but it sees only part of them: the
  // rest lies under the roof, where the wall is. An orthographic view observes a cell (seen through, known empty) only
  // where every texel over it shows what lies beyond it, so those cells stay unobserved, and a probe ray does not
  // cross the wall there as open air (the hall's sky through its walls, docs/QUALITY.md); the cells beyond, open to
  // the view, are observed.
  // Texels a voxel wide, the rim at x = 1.75 m: the cell x ∈ [1, 2) m is crossed past the rim; the texels whose
  // centres lie over it show the roof.
  std::map<int, bool> observed = cellsObservedBesideAWallUnderARoofsRim(1.75f, kVoxel);
  EXPECT_FALSE(observed[1]);
  EXPECT_TRUE(observed[2]);
  EXPECT_TRUE(observed[3]);
  // Texels two voxels wide (the overhead view's are about that), the rim at x = 2.1 m and the wall from 1.85 m: the
  // cell x ∈ [2, 3) m holds the wall's last 0.1 m, and the centres of the texels over it (2.35 and 2.85 m) see the
  // floor; the texel from 1.6 to 2.1 m, which it touches, shows the roof.
  observed = cellsObservedBesideAWallUnderARoofsRim(2.1f, 2.0f * kVoxel);
  EXPECT_FALSE(observed[2]);
  EXPECT_TRUE(observed[3]);
  EXPECT_TRUE(observed[4]);
}

TEST_F(VoxelScene, aWallOneVoxelThickTurnedRoundByAViewFromInsideTakesThatViewsLightWhole) {
  // A wall one voxel thick on the voxel grid holds both its faces in the same voxels. An extra view from outside sees
  // its outer face, sunlit, while the voxels are empty, and they take it; then a view from inside, towards the volume's
  // middle, turns them round. An extra view's light is averaged with what a voxel held (kVoxelExtraViewRadianceBlend),
  // but not across that turn: the inner face must not take three quarters of the outer face's light into the room.
  create(smallSettings());
  const HostFrame sky(device(), lookingUp({0.5f, 1.0f, 0.5f}), {});
  dispatch(sky, nullptr);  // places the volume around the camera
  ASSERT_LT(volumeViewpoint(*context_).x, 1.0f) << "the inner face must look towards the volume's middle";
  const glm::vec3 wallMin(1.0f, 0.0f, -1.0f), wallMax(1.25f, 2.0f, 2.0f);
  const glm::vec3 outerLight(2.0f), innerLight(0.125f);
  const renderer::Camera outside = looking({4.0f, 1.0f, 0.5f}, {0.0f, 1.0f, 0.5f}, 60.0f);
  const renderer::Camera inside = looking({-2.0f, 1.0f, 0.5f}, {4.0f, 1.0f, 0.5f}, 60.0f);
  const HostFrame fromOutside(device(), outside, {{wallMin, wallMax, outerLight}});
  const HostFrame fromInside(device(), inside, {{wallMin, wallMax, innerLight}});
  for (uint32_t injection = 0; injection < 8; ++injection) dispatch(sky, nullptr, {extraView(fromOutside)});
  const auto outer = occupiedVoxels(readState());
  ASSERT_GT(outer.size(), 50u);
  for (const auto& [coordinate, voxel] : outer)
    ASSERT_GT(shader::voxelNormal(voxel).x, 0.99f) << "the outer face first";
  dispatch(sky, nullptr, {extraView(fromInside)});
  uint32_t turned = 0;
  for (const auto& [coordinate, voxel] : occupiedVoxels(readState())) {
    if (shader::voxelNormal(voxel).x > -0.99f) continue;
    const auto [x, y, z] = coordinate;
    EXPECT_NEAR(shader::unpackR11G11B10F(voxel.radiance).y, innerLight.y, innerLight.y / 32.0f)
        << "voxel " << x << "," << y << "," << z << " turned round to the inner face";
    ++turned;
  }
  EXPECT_GT(turned, outer.size() / 4) << "of " << outer.size() << " voxels, too few turned round to test";
}

TEST_F(VoxelScene, badExtraViewsAreRefusedWithTheFieldNamed) {
  create(smallSettings());
  const HostFrame frame(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  auto dispatchWith = [&](const std::vector<ExtraView>& views) { return tryDispatch(frame, frame.view, views); };
  const Error tooMany = dispatchWith(std::vector<ExtraView>(kMaxExtraViews + 1, extraView(frame)));
  EXPECT_EQ(tooMany.status, Status::InvalidDescription);
  EXPECT_NE(tooMany.message.find("FrameDesc::extraViews: 9 views, at most 8"), std::string::npos) << tooMany.message;
  ExtraView noDepth = extraView(frame);
  noDepth.depth.view = VK_NULL_HANDLE;
  const Error missing = dispatchWith({extraView(frame), noDepth});
  EXPECT_EQ(missing.status, Status::InvalidDescription);
  EXPECT_NE(missing.message.find("FrameDesc::extraViews[1]: a depth view is required"), std::string::npos)
      << missing.message;
  ExtraView colourWithoutNormal = extraView(frame);
  colourWithoutNormal.normal.view = VK_NULL_HANDLE;
  EXPECT_NE(dispatchWith({colourWithoutNormal}).message.find("FrameDesc::extraViews[0]: a view with a color needs"),
            std::string::npos);
  ExtraView observesOnly = extraView(frame);
  observesOnly.color.view = observesOnly.normal.view = observesOnly.albedo.view = VK_NULL_HANDLE;
  EXPECT_FALSE(dispatchWith({observesOnly})) << "a view given with depth only observes space";
  ExtraView shadowMapWithoutAlbedo = extraView(frame);
  shadowMapWithoutAlbedo.isReflectiveShadowMap = true;
  EXPECT_NE(dispatchWith({shadowMapWithoutAlbedo})
                .message.find("FrameDesc::extraViews[0]: a reflective shadow map needs its albedo view"),
            std::string::npos);
  ExtraView tooLarge = extraView(frame);
  tooLarge.camera.width = kSize + 1;
  const Error large = dispatchWith({tooLarge});
  EXPECT_NE(large.message.find("FrameDesc::extraViews[0].camera: 65×64 exceeds ContextDesc::maxExtraViewSize (64×64)"),
            std::string::npos)
      << large.message;
  EXPECT_FALSE(dispatchWith({extraView(frame)})) << "a valid extra view";
}

TEST_F(VoxelScene, nonFiniteOrSingularViewsAndFarAwayCamerasAreRefused) {
  // A NaN or a singular matrix would make every pass's loops over the volume meaningless (issue 19 saw ProbePlacement
  // take 30 s a frame for a NaN camera); refused with the field named, and the context stays usable.
  create(smallSettings());
  const HostFrame frame(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  auto dispatchWith = [&](const View& camera, const std::vector<ExtraView>& views = {}) {
    return tryDispatch(frame, camera, views);
  };
  View nan = frame.view;
  nan.viewProjection[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(dispatchWith(nan).message.find("FrameDesc::camera.viewProjection: not finite"), std::string::npos);
  View singular = frame.view;
  singular.viewProjection = {};
  EXPECT_NE(dispatchWith(singular).message.find("FrameDesc::camera.viewProjection: not invertible"), std::string::npos);
  View farAway = frame.view;
  farAway.position[1] = 1e30f;
  const Error far = dispatchWith(farAway);
  EXPECT_EQ(far.status, Status::InvalidDescription);
  EXPECT_NE(far.message.find("FrameDesc::camera.position"), std::string::npos) << far.message;
  ExtraView badView = extraView(frame);
  badView.camera.viewProjection[0] = std::numeric_limits<float>::infinity();
  EXPECT_NE(dispatchWith(frame.view, {badView}).message.find("FrameDesc::extraViews[0].camera.viewProjection"),
            std::string::npos);
  EXPECT_FALSE(dispatchWith(frame.view)) << "the context refuses good frames after bad ones";
}

TEST_F(VoxelScene, nonFinitePixelsInTheHostsImagesLeaveNothingNonFiniteAndAreForgottenWithinThirtyTwoFrames) {
  // SPEC §1: a NaN reaching ssvgi through an image must not poison its voxels and probes for good. For 8 frames the
  // host's frames carry +∞ in every pixel's red (light too bright for the half floats ssvgi stores: its probes' SH
  // overflowed to ∞), and NaN or ±∞ in colour, depth or normal in every 7th pixel; every voxel, probe and output texel
  // must stay finite meanwhile, and 32 clean frames later the floor's voxels hold the floor's colour again.
  create(smallSettings());
  const HostFrame clean(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  HostFrame poisoned(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (size_t pixel = 0; pixel < size_t(kSize) * kSize; ++pixel) poisoned.colorValues[pixel * 4] = inf;
  for (size_t pixel = 0; pixel < size_t(kSize) * kSize; pixel += 7) {
    switch ((pixel / 7) % 4) {
      case 0: poisoned.colorValues[pixel * 4 + 1] = nan; break;
      case 1: poisoned.colorValues[pixel * 4 + 2] = -inf; break;
      case 2: poisoned.depthValues[pixel] = nan; break;
      default: poisoned.normalValues[pixel * 4 + 2] = -inf; break;
    }
  }
  poisoned.upload(device());
  auto expectAllFinite = [&](const char* when) {
    SCOPED_TRACE(when);
    for (const auto& [coordinate, voxel] : occupiedVoxels(readState())) {
      const glm::vec3 radiance = shader::unpackR11G11B10F(voxel.radiance);
      for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(radiance[c])) << "a voxel";
    }
    for (const shader::Probe& probe : gpu::readBufferAs<shader::Probe>(device(), gi::probeVolumeOf(*context_).probes())) {
      const shader::Sh2Rgb radiance = shader::probeRadianceSh(probe);
      for (const glm::vec4& channel : {radiance.r, radiance.g, radiance.b})
        for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(channel[c])) << "a probe";
    }
    const auto output = gpu::readImage(device(), gi::gatherTargetsOf(*context_).output());
    for (size_t i = 0; i < output.size() / 2; ++i) {
      uint16_t half = 0;
      std::memcpy(&half, output.data() + 2 * i, 2);
      ASSERT_TRUE(std::isfinite(glm::unpackHalf1x16(half))) << "output value " << i;
    }
  };
  run(poisoned, 8);
  expectAllFinite("with the non-finite pixels");
  run(clean, 32);
  expectAllFinite("after them");
  uint32_t floorVoxels = 0;
  for (const auto& [coordinate, voxel] : occupiedVoxels(readState())) {
    ++floorVoxels;
    EXPECT_NEAR(shader::unpackR11G11B10F(voxel.radiance).x, kFloor.radiance.x, kFloor.radiance.x / 64.0f);
  }
  EXPECT_GT(floorVoxels, 100u);
}

// Pool index of the live brick at a world brick coordinate, if any.
std::optional<uint32_t> liveBrickAt(const GpuState& state, glm::ivec3 coordinate) {
  for (uint32_t b = 0; b < state.pool.bumpCount; ++b)
    if (state.bricks[b].live == 1u && state.bricks[b].coordinate == coordinate) return b;
  return std::nullopt;
}

TEST_F(VoxelScene, aMovingObjectLeavesNoVoxelsBehindAndItsBricksAreReleasedAndReused) {
  const Settings settings = smallSettings();
  create(settings);
  // A pillar whose top (y = 2.1 m) lies in brick (0, 2, 0), seen from above.
  const TestBox pillar{{0.0f, 0.1f, 0.0f}, {0.6f, 2.1f, 0.6f}, {1.0f, 0.0f, 0.0f}};
  const HostFrame withPillar(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor, pillar});
  run(withPillar, 16);
  // Everything above the floor's voxel layer (y >= 0.25 m) belongs to the pillar.
  auto isPillarVoxel = [](const auto& entry) { return std::get<1>(entry.first) >= 1; };
  const GpuState before = readState();
  const auto occupiedBefore = occupiedVoxels(before);
  ASSERT_GT(std::count_if(occupiedBefore.begin(), occupiedBefore.end(), isPillarVoxel), 0) << "pillar not injected";
  const auto pillarBrick = liveBrickAt(before, {0, 2, 0});
  ASSERT_TRUE(pillarBrick);

  // The pillar moves away: the camera now sees the floor through its voxels.
  const HostFrame withoutPillar(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor});
  run(withoutPillar, settings.invalidFramesToClear + settings.emptyFramesToRelease + 2);
  const GpuState after = readState();
  const auto remaining = occupiedVoxels(after);
  EXPECT_EQ(std::count_if(remaining.begin(), remaining.end(), isPillarVoxel), 0);
  EXPECT_FALSE(liveBrickAt(after, {0, 2, 0})) << "the pillar's empty brick was not released";
  const std::set<uint32_t> freeAfter(after.freeList.begin(), after.freeList.begin() + after.pool.freeCount);
  EXPECT_TRUE(freeAfter.count(*pillarBrick)) << "its index is not on the free list";
  expectPoolConsistent(after, settings);

  // It comes back elsewhere: its new bricks (top and the sides now in view) take the free slots before any fresh one.
  const TestBox movedPillar{{1.0f, 0.1f, 1.0f}, {1.6f, 2.1f, 1.6f}, {1.0f, 0.0f, 0.0f}};
  const HostFrame moved(device(), lookingDown({0.5f, 6.0f, 0.5f}), {kFloor, movedPillar});
  run(moved, 2);
  const GpuState reused = readState();
  const auto movedBrick = liveBrickAt(reused, {1, 2, 1});
  ASSERT_TRUE(movedBrick);
  for (uint32_t index : freeAfter) EXPECT_EQ(reused.bricks[index].live, 1u) << "free slot " << index << " unused";
  expectPoolConsistent(reused, settings);
}

TEST_F(VoxelScene, poolAccountingBalancesOverTwoThousandFramesOfScrolling) {
  const Settings settings = smallSettings();
  create(settings);
  // Back and forth along X over 40 m: the 16 m volume scrolls every few frames and releases what it leaves.
  for (uint32_t frame = 0; frame < 2000; ++frame) {
    const float phase = float(frame % 400) / 400.0f;
    const float x = 40.0f * (phase < 0.5f ? 2.0f * phase : 2.0f - 2.0f * phase);
    const HostFrame current(device(), lookingDown({x, 4.0f, 0.3f * x}, 60.0f), {kFloor});
    dispatch(current, &current);
    if (frame % 250 == 249) {
      SCOPED_TRACE("frame " + std::to_string(frame));
      const GpuState state = readState();
      expectPoolConsistent(state, settings);
      const Stats stats = context_->stats();
      EXPECT_EQ(stats.bricksLive + stats.bricksFree + stats.bricksNeverUsed, settings.brickPoolCapacity);
      EXPECT_EQ(stats.bricksDroppedTotal, 0u);
    }
  }
  EXPECT_GT(context_->stats().bricksFree, 0u) << "nothing was ever released";
}

TEST_F(VoxelScene, aFullPoolDropsNewBricksCountsThemAndKeepsWhatItHolds) {
  Settings settings = smallSettings();
  settings.brickPoolCapacity = 8;
  create(settings);
  const HostFrame wide(device(), lookingDown({0.5f, 6.0f, 0.5f}, 60.0f), {kFloor});
  run(wide, 6);
  const GpuState full = readState();
  EXPECT_EQ(full.pool.bumpCount, 8u);
  EXPECT_GT(full.pool.droppedTotal, 0u);
  expectPoolConsistent(full, settings);
  const Stats stats = context_->stats();
  EXPECT_EQ(stats.bricksLive, 8u);
  EXPECT_GT(stats.bricksDroppedLastFrame, 0u);

  run(wide, 6);
  const GpuState later = readState();
  expectPoolConsistent(later, settings);
  // The same bricks at the same places, and every voxel they hold is the floor's: a full pool corrupts nothing.
  for (uint32_t brick = 0; brick < 8; ++brick) {
    EXPECT_EQ(later.bricks[brick].coordinate, full.bricks[brick].coordinate);
    EXPECT_EQ(later.bricks[brick].live, full.bricks[brick].live);
  }
  const auto occupied = occupiedVoxels(later);
  EXPECT_FALSE(occupied.empty());
  for (const auto& [coordinate, voxel] : occupied) {
    EXPECT_EQ(std::get<1>(coordinate), 0);
    EXPECT_NEAR(shader::unpackR11G11B10F(voxel.radiance).x, kFloor.radiance.x, kFloor.radiance.x / 64.0f);
  }
}

TEST_F(VoxelScene, theHighTierVoxelSceneFitsTheMemoryBudget) {
  create(settingsForTier(QualityTier::High));
  const Stats stats = context_->stats();
  uint64_t voxelBytes = 0;
  for (const auto& resource : stats.memory) {
    EXPECT_GT(resource.bytes, 0u) << resource.name;
    if (resource.name.rfind("ssvgi probe", 0) != 0) voxelBytes += resource.bytes;  // probe_tests.cpp checks those
  }
  // Issue 16: all GI data ≤ 24 MB at high tier by default (SPEC §5 allows 30); the voxel scene must leave room for the
  // probes (≈ 7 MB without reservoirs).
  EXPECT_LE(voxelBytes, 17u * 1024 * 1024);
  EXPECT_EQ(stats.brickPoolCapacity, 11776u);
}

// The volume is flat; from high above, looking down, a volume centred on the camera would hold none of what it sees.
TEST_F(VoxelScene, aCameraHighAboveTheFloorItLooksDownAtHasTheVolumeStandLowEnoughToHoldTheFloor) {
  Settings settings = smallSettings();
  settings.volumeBricks = {16, 24, 16};  // 6 steps of 4 m
  create(settings);
  EXPECT_EQ(context_->stats().voxelVolume.max, (std::array<float, 3>{})) << "no volume before the first dispatch";
  EXPECT_EQ(context_->voxelVolume().max, (std::array<float, 3>{}));
  // The camera's step is y ∈ [16, 20) m: centred, the volume spans y ∈ [4, 28) m, 4 m above the floor (y = 0.1 m).
  const HostFrame high(device(), lookingDown({0.5f, 18.1f, 0.5f}), {kFloor});
  dispatch(high, &high);
  const gi::VoxelScene& scene = gi::voxelSceneOf(*context_);
  EXPECT_EQ(scene.current().originBrick.y, 4) << "the first frame, nothing measured yet: centred";
  run(high, 4);  // the heights the first frame counted are read back two frames later (framesInFlight)
  EXPECT_EQ(scene.current().originBrick.y, 0) << "the placement nearest to centred that holds the floor";
  EXPECT_EQ(scene.current().verticalShiftBricks, -4);
  const WorldBox box = context_->stats().voxelVolume;  // the host's view of it
  EXPECT_EQ(box.min, (std::array<float, 3>{-8.0f, 0.0f, -8.0f}));
  EXPECT_EQ(box.max, (std::array<float, 3>{8.0f, 24.0f, 8.0f}));
  EXPECT_EQ(context_->voxelVolume().min, box.min) << "the same box, known as soon as dispatch() returns";
  EXPECT_EQ(context_->voxelVolume().max, box.max);
  const std::map<testing::VoxelCoordinate, shader::Voxel> occupied = occupiedVoxels(readState());
  ASSERT_FALSE(occupied.empty()) << "the floor has voxels";
  for (const auto& [coordinate, voxel] : occupied) EXPECT_EQ(std::get<1>(coordinate), 0);

  // Down at 2.1 m the volume still holds all the camera sees, and stays.
  run(HostFrame(device(), lookingDown({0.5f, 2.1f, 0.5f}), {kFloor}), 2 * gi::kSurfaceHeightFramePeriod);
  EXPECT_EQ(scene.current().originBrick.y, 0);
  EXPECT_EQ(scene.current().verticalShiftBricks, 12);
}

TEST(VolumeBottomStep, holdsTheMostPixelsNearestToCentredAndStaysWhileItHoldsNearlyAsMany) {
  // Twelve steps (high tier), the camera's step 7; bands counted around step 7 (band 32).
  std::array<uint32_t, shader::kSurfaceHeightBands> bands{};
  constexpr int kCamera = 7, kSteps = 12;
  constexpr int kCentred = kCamera - kSteps / 2;
  const auto bandOf = [](int step) { return size_t(step - kCamera + int(shader::kSurfaceHeightBands / 2)); };
  // Nothing seen (only sky): where it stands while that holds the camera's step, else centred.
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, kCentred + 2), kCentred + 2);
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, kCamera + 1), kCentred);
  // Everything seen within the centred volume: it stays centred.
  bands[bandOf(2)] = 1000;
  bands[bandOf(8)] = 200;
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, kCentred), kCentred);
  // The ground (held a hair below y = 0: step -1) and roofs at step 3, 8 and 4 steps below the camera: the bottom
  // nearest to centred among those that hold both.
  bands = {};
  bands[bandOf(-1)] = 900;
  bands[bandOf(3)] = 100;
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, kCentred), -1);
  // A camera further above the ground than the volume is tall: the volume holds the ground, not the camera.
  bands = {};
  bands[bandOf(-6)] = 900;
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, kCentred), -6);
  // The end bands, everything beyond, are held by none.
  bands = {};
  bands[0] = 1000;
  bands[bands.size() - 1] = 1000;
  bands[bandOf(2)] = 10;
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, kCentred), kCentred);
  // A placement that holds all but 1 % of what the best holds stays; one that holds 5 % less moves.
  bands = {};
  bands[bandOf(-1)] = 50;
  bands[bandOf(0)] = 4950;
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, 0), 0);
  bands[bandOf(-1)] = 250;
  bands[bandOf(0)] = 4750;
  EXPECT_EQ(gi::volumeBottomStep(bands, kCamera, kCamera, kSteps, 0), -1);
  // The bands measured when the camera stood elsewhere are read at their own steps: measured around step 9, the
  // ground's band there is 10 below the middle.
  bands = {};
  bands[size_t(-1 - 9 + int(shader::kSurfaceHeightBands / 2))] = 900;
  EXPECT_EQ(gi::volumeBottomStep(bands, 9, kCamera, kSteps, kCentred), -1);
}

// A description of the shared test device with default settings.
ContextDesc testDeviceDesc() {
  gpu::OwnedDevice& device = testing::gpuTestDevice();
  ContextDesc desc;
  desc.instance = device.instance();
  desc.physicalDevice = device.physicalDevice();
  desc.device = device.device();
  desc.maxWidth = desc.maxHeight = kSize;
  return desc;
}

// HiZBuild on its own: a depth image of odd size at every level, of random depths, against the pyramid built on the
// CPU — each texel the farthest (smallest reversed-Z) depth of the 2×2 texels below it, or of the 2 or 1 of them an
// odd-sized level's last column or row has.
class HiZPyramid : public testing::GpuTest {};

TEST_F(HiZPyramid, eachTexelIsTheFarthestDepthOfTheTexelsItCoversOnTheLevelBelow) {
  constexpr uint32_t kWidth = 45, kHeight = 27;  // 23×14, 12×7, 6×4, 3×2, 2×1, 1×1
  std::vector<float> depth(size_t(kWidth) * kHeight);
  uint32_t state = 12345u;
  for (float& value : depth) {
    state = state * 1664525u + 1013904223u;
    value = float(state >> 8) / float(1u << 24);
  }
  shader::GiFrame frame{};
  frame.size = frame.litSize = glm::uvec2(kWidth, kHeight);
  frame.hizLevelCount = gi::hizLayout(kWidth, kHeight, frame.hizLevels);
  ASSERT_EQ(frame.hizLevelCount, 6u);
  gpu::Buffer frameBuffer(device(), "test gi frame", sizeof(frame), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          gpu::MemoryUsage::HostUpload);
  std::memcpy(frameBuffer.mapped(), &frame, sizeof(frame));
  gpu::Image depthImage(device(), {"test depth", VK_FORMAT_R32_SFLOAT, kWidth, kHeight, 1, 1, VK_IMAGE_USAGE_SAMPLED_BIT});
  gpu::uploadImage(device(), depthImage, std::as_bytes(std::span(depth)));
  const shader::HiZLevel& lastLevel = frame.hizLevels[frame.hizLevelCount - 1];
  gpu::Buffer hiz(device(), "test hi-z", VkDeviceSize(lastLevel.firstTexel + 1) * sizeof(float),
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::Buffer unusedBricks(device(), "test visible bricks", 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  VkSamplerCreateInfo pointSampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  pointSampler.magFilter = pointSampler.minFilter = VK_FILTER_NEAREST;
  pointSampler.addressModeU = pointSampler.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  gpu::Sampler sampler(device(), pointSampler, "test point sampler");
  gi::HiZBuild hizBuild(device());
  gpu::DescriptorArena descriptors(device());
  device().submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList commands(device(), commandBuffer, descriptors);
    hizBuild.record(commands, {frameBuffer, sampler.handle(), depthImage.view(), depthImage.view(), hiz, unusedBricks},
                    frame, frame.hizLevelCount);
  });
  const std::vector<float> pyramid = gpu::readBufferAs<float>(device(), hiz);

  std::vector<float> below = depth;
  glm::uvec2 belowSize(kWidth, kHeight);
  for (uint32_t level = 0; level < frame.hizLevelCount; ++level) {
    const shader::HiZLevel& target = frame.hizLevels[level];
    std::vector<float> expected(size_t(target.size.x) * target.size.y);
    for (uint32_t y = 0; y < target.size.y; ++y)
      for (uint32_t x = 0; x < target.size.x; ++x) {
        const uint32_t lastX = std::min(2 * x + 1, belowSize.x - 1);
        const uint32_t lastY = std::min(2 * y + 1, belowSize.y - 1);
        float farthest = 1.0f;
        for (uint32_t by = 2 * y; by <= lastY; ++by)
          for (uint32_t bx = 2 * x; bx <= lastX; ++bx) farthest = std::min(farthest, below[by * belowSize.x + bx]);
        expected[y * target.size.x + x] = farthest;
        ASSERT_EQ(pyramid[target.firstTexel + y * target.size.x + x], farthest)
            << "level " << level << " texel " << x << ", " << y;
      }
    below = expected;
    belowSize = target.size;
  }
}

TEST(VoxelSceneApi, aDescriptionWithoutADeviceIsRefused) {
  ContextDesc desc = testDeviceDesc();
  desc.device = VK_NULL_HANDLE;
  EXPECT_EQ(Context::create(desc).error().status, Status::InvalidDescription);
}

TEST(VoxelSceneApi, everySettingOutsideWhatItsInfoAcceptsIsRefusedWithItsNameAndEveryTierIsAccepted) {
  // settingInfos() is the one list Context::create validates by: for every field, values just outside what its info
  // says it accepts — below its minimum, above its maximum, off its multiple, not a power of two, not finite — are
  // refused with the field named, and every tier's settings are accepted.
  ContextDesc desc = testDeviceDesc();
  for (QualityTier tier : {QualityTier::Low, QualityTier::Medium, QualityTier::High}) {
    desc.settings = settingsForTier(tier);
    const auto result = Context::create(desc);
    EXPECT_TRUE(result.ok()) << "tier " << int(tier) << ": " << (result.ok() ? "" : result.error().message);
  }
  uint32_t refused = 0;
  for (const SettingInfo& info : settingInfos()) {
    std::vector<double> outside;
    double below = info.minimumExcluded ? info.minimum : info.minimum - 1.0;
    if (info.zeroTurnsOff && below == 0.0) below = -1.0;  // 0 is accepted as off
    outside.push_back(below);
    if ((info.zeroTurnsOff || info.minimum < 1.0) && info.minimum > 0.0) outside.push_back(info.minimum / 2.0);
    if (std::isfinite(info.maximum)) outside.push_back(info.maximum + double(info.multipleOf));
    if (info.multipleOf > 1) outside.push_back(info.minimum + 1.0);
    if (info.powerOfTwo) outside.push_back(3.0);
    outside.push_back(std::numeric_limits<double>::quiet_NaN());
    for (double value : outside) {
      desc.settings = Settings{};
      bool settable = false;
      std::visit(
          [&](auto member) {
            using Value = std::remove_cvref_t<decltype(desc.settings.*member)>;
            if constexpr (std::is_same_v<Value, float>) {
              desc.settings.*member = float(value);
              settable = true;
            } else if constexpr (std::is_same_v<Value, uint32_t>) {
              settable = value >= 0.0 && value <= 4294967295.0;  // a uint32 cannot hold the others
              if (settable) desc.settings.*member = uint32_t(value);
            } else if constexpr (std::is_same_v<Value, std::array<uint32_t, 3>>) {
              settable = value >= 0.0 && value <= 4294967295.0;
              if (settable) desc.settings.*member = {uint32_t(value), 48u, uint32_t(value)};
            }
          },
          info.member);
      if (!settable) continue;
      const auto result = Context::create(desc);
      ASSERT_FALSE(result.ok()) << info.name << " = " << value << " was accepted";
      EXPECT_EQ(result.error().status, Status::InvalidDescription);
      EXPECT_NE(result.error().message.find(std::string("Settings::") + info.name), std::string::npos)
          << info.name << " = " << value << ": " << result.error().message;
      ++refused;
    }
  }
  std::printf("%u values outside what their settings accept, each refused with the setting named\n", refused);
  EXPECT_GT(refused, 20u);
}

TEST(VoxelSceneApi, aVoxelVolumeOrProbeLevelWiderThanTheViewsMayStandInIsRefusedWithItsSettingsNamed) {
  // Each setting is within its own range, but together they make a volume wider than the ±10^6 m that FrameDesc's
  // views may stand in; at the limit the high tier's 512 voxels across are 3,906.25 m each.
  ContextDesc desc = testDeviceDesc();
  desc.settings.voxelSize = 3906.25f;
  EXPECT_TRUE(Context::create(desc).ok()) << "2,000,000 m across is accepted";
  desc.settings.voxelSize = 3907.0f;
  auto result = Context::create(desc);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().status, Status::InvalidDescription);
  EXPECT_NE(result.error().message.find("Settings::voxelSize and Settings::volumeBricks"), std::string::npos)
      << result.error().message;
  desc.settings = Settings{};
  desc.settings.probeSpacing = 1.1e4f;  // the coarsest level: 48 probes 4 × 11,000 m apart, 2,112,000 m
  result = Context::create(desc);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("Settings::probeSpacing and Settings::probeGrid"), std::string::npos)
      << result.error().message;
}

}  // namespace
}  // namespace ssvgi
