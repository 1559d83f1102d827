// A memory budget set by the host (SPEC §6.5, ContextDesc::memoryBudgetBytes): every byte the context allocates fits
// it, the settings shrink in the documented order (brick pool, then probe grid, then voxel volume), a frame still
// dispatches; a budget below the minimum is refused with a message naming it; without a budget nothing changes.
#include "camera.h"
#include "gpu_host/transfers.h"
#include "gpu_test_device.h"
#include "shared/probe_interface.h"
#include "shared/voxel_interface.h"
#include "ssvgi/ssvgi.h"

#include <glm/gtc/type_ptr.hpp>

#include <cstdio>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace ssvgi {
namespace {

constexpr uint64_t kMebibyte = uint64_t(1) << 20;  // SPEC §5's MB
// The frame dispatched: small, so that the test stays fast; the context is sized for maxWidth × maxHeight regardless.
constexpr uint32_t kFrameSize = 32;
constexpr float kNear = 0.1f, kWallDistance = 4.0f;

uint64_t sumOfMemory(const Stats& stats) {
  uint64_t bytes = 0;
  for (const ResourceMemory& resource : stats.memory) bytes += resource.bytes;
  return bytes;
}

uint64_t memoryOf(const Stats& stats, const std::string& name) {
  for (const ResourceMemory& resource : stats.memory)
    if (resource.name == name) return resource.bytes;
  return 0;
}

// Every field of `a` and `b` alike, by the one list of fields (settingInfos).
bool sameSettings(const Settings& a, const Settings& b) {
  bool same = true;
  for (const SettingInfo& field : settingInfos())
    std::visit([&](auto member) { same = same && a.*member == b.*member; }, field.member);
  return same;
}

uint64_t cells(const std::array<uint32_t, 3>& axes) { return uint64_t(axes[0]) * axes[1] * axes[2]; }

class MemoryBudget : public testing::GpuTest {
 protected:
  // The high tier for frames of up to `maxWidth` × `maxHeight`, extra views of up to 1024² (the default), within
  // `budgetBytes` (0: none).
  static ContextDesc highTier(uint32_t maxWidth, uint32_t maxHeight, uint64_t budgetBytes) {
    ContextDesc desc = testing::gpuTestContextDesc(settingsForTier(QualityTier::High), 1024);
    desc.maxWidth = maxWidth;
    desc.maxHeight = maxHeight;
    desc.memoryBudgetBytes = budgetBytes;
    return desc;
  }

  // One frame of a camera facing a wall kWallDistance away, with depth and normal only (no lit frame yet).
  void dispatchOneFrame(Context& context) {
    renderer::Camera camera;
    camera.position = {0.0f, 1.5f, 0.0f};
    camera.target = {0.0f, 1.5f, -1.0f};
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.verticalFov = glm::radians(60.0f);
    camera.nearPlane = kNear;
    const glm::mat4 viewProjection =
        renderer::reversedZInfiniteProjection(camera.verticalFov, 1.0f, kNear) * renderer::viewMatrix(camera);
    gpu::Image depth(device(), {"test depth", VK_FORMAT_R32_SFLOAT, kFrameSize, kFrameSize, 1, 1,
                                VK_IMAGE_USAGE_SAMPLED_BIT});
    gpu::Image normal(device(), {"test normal", VK_FORMAT_R32G32B32A32_SFLOAT, kFrameSize, kFrameSize, 1, 1,
                                 VK_IMAGE_USAGE_SAMPLED_BIT});
    const std::vector<float> depths(size_t(kFrameSize) * kFrameSize, kNear / kWallDistance);  // reversed-Z
    const std::vector<glm::vec4> normals(depths.size(), glm::vec4(0.0f, 0.0f, 1.0f, 0.0f));
    gpu::uploadImage(device(), depth, std::as_bytes(std::span(depths)));
    gpu::uploadImage(device(), normal, std::as_bytes(std::span(normals)));

    FrameDesc frame;
    std::copy(glm::value_ptr(viewProjection), glm::value_ptr(viewProjection) + 16, frame.camera.viewProjection.begin());
    frame.camera.position = {camera.position.x, camera.position.y, camera.position.z};
    frame.camera.width = frame.camera.height = kFrameSize;
    frame.depth.view = depth.view();
    frame.normal.view = normal.view();
    Error error;
    device().submitAndWait([&](VkCommandBuffer commandBuffer) { error = context.dispatch(frame, commandBuffer); });
    EXPECT_FALSE(error) << error.message;
    EXPECT_NE(context.output().view, VkImageView(VK_NULL_HANDLE));
  }
};

TEST_F(MemoryBudget, everyAllocationFitsTheBudgetTheSettingsShrinkPoolFirstThenProbesThenVolumeAndThePoolTakesTheRest) {
  // 32, 24 and 16 MB at 1920×1080. 8 MB cannot hold 1080p's gather images alone (SPEC §5 allows them 10 MB), which
  // follow the host's frame size and never shrink: it is measured for frames of up to 1280×720.
  struct Case {
    uint64_t budgetMebibytes;
    uint32_t maxWidth, maxHeight;
  };
  const Settings set = settingsForTier(QualityTier::High);
  Settings larger = set;  // the choice of the last, larger budget
  for (const Case& test : {Case{32, 1920, 1080}, Case{24, 1920, 1080}, Case{16, 1920, 1080}, Case{8, 1280, 720}}) {
    SCOPED_TRACE(std::to_string(test.budgetMebibytes) + " MB");
    const uint64_t budget = test.budgetMebibytes * kMebibyte;
    auto created = Context::create(highTier(test.maxWidth, test.maxHeight, budget));
    ASSERT_TRUE(created.ok()) << created.error().message;
    Context& context = *created.value();
    dispatchOneFrame(context);
    const Stats stats = context.stats();
    const Settings chosen = context.settings();
    EXPECT_LE(sumOfMemory(stats), budget);
    EXPECT_EQ(stats.totalBytes, sumOfMemory(stats));
    EXPECT_EQ(stats.memoryBudgetBytes, budget);
    EXPECT_TRUE(sameSettings(stats.settings, context.settings()));
    EXPECT_EQ(stats.brickPoolCapacity, context.settings().brickPoolCapacity);

    std::printf("%2llu MB at %ux%u: pool %u bricks, probe grid %ux%ux%u, volume %ux%ux%u bricks, %llu bytes\n",
                static_cast<unsigned long long>(test.budgetMebibytes), test.maxWidth, test.maxHeight,
                chosen.brickPoolCapacity, chosen.probeGrid[0], chosen.probeGrid[1], chosen.probeGrid[2],
                chosen.volumeBricks[0], chosen.volumeBricks[1], chosen.volumeBricks[2],
                static_cast<unsigned long long>(stats.totalBytes));
    // The order: the probe grid shrinks only once the pool has, the volume only once the probe grid has.
    if (cells(chosen.probeGrid) < cells(set.probeGrid)) {
      EXPECT_LT(chosen.brickPoolCapacity, set.brickPoolCapacity);
    }
    if (cells(chosen.volumeBricks) < cells(set.volumeBricks)) {
      EXPECT_LT(cells(chosen.probeGrid), cells(set.probeGrid));
    }
    // Nothing but those three changes, and a smaller budget never chooses a larger probe grid or volume.
    Settings others = chosen;
    others.brickPoolCapacity = set.brickPoolCapacity;
    others.probeGrid = set.probeGrid;
    others.volumeBricks = set.volumeBricks;
    EXPECT_TRUE(sameSettings(others, set));
    for (size_t axis = 0; axis < 3; ++axis) {
      EXPECT_LE(chosen.probeGrid[axis], larger.probeGrid[axis]);
      EXPECT_LE(chosen.volumeBricks[axis], larger.volumeBricks[axis]);
    }
    larger = chosen;
    // What the probe grid and volume leave of the budget goes to the pool: one brick more would not fit.
    ASSERT_LT(chosen.brickPoolCapacity, set.brickPoolCapacity);
    ContextDesc oneBrickMore = highTier(test.maxWidth, test.maxHeight, 0);
    oneBrickMore.settings = chosen;
    ++oneBrickMore.settings.brickPoolCapacity;
    created.value().reset();
    auto unbudgeted = Context::create(oneBrickMore);
    ASSERT_TRUE(unbudgeted.ok()) << unbudgeted.error().message;
    EXPECT_GT(unbudgeted.value()->stats().totalBytes, budget);
  }
  // The smallest budget had to give up some of the voxel volume.
  EXPECT_LT(cells(larger.volumeBricks), cells(set.volumeBricks));
}

TEST_F(MemoryBudget, aBudgetTheSettingsFitChangesNothingAndOneByteLessShrinksOnlyThePool) {
  auto unbudgeted = Context::create(highTier(1920, 1080, 0));
  ASSERT_TRUE(unbudgeted.ok()) << unbudgeted.error().message;
  const Stats today = unbudgeted.value()->stats();
  unbudgeted.value().reset();

  auto exact = Context::create(highTier(1920, 1080, today.totalBytes));
  ASSERT_TRUE(exact.ok()) << exact.error().message;
  EXPECT_TRUE(sameSettings(exact.value()->settings(), settingsForTier(QualityTier::High)));
  EXPECT_EQ(exact.value()->stats().totalBytes, today.totalBytes);
  exact.value().reset();

  auto tight = Context::create(highTier(1920, 1080, today.totalBytes - 1));
  ASSERT_TRUE(tight.ok()) << tight.error().message;
  const Settings& chosen = tight.value()->settings();
  const Settings set = settingsForTier(QualityTier::High);
  EXPECT_LT(chosen.brickPoolCapacity, set.brickPoolCapacity);
  EXPECT_EQ(chosen.probeGrid, set.probeGrid);
  EXPECT_EQ(chosen.volumeBricks, set.volumeBricks);
  // The largest pool that fits: a brick takes more than 1 byte, so one brick less is all it takes.
  EXPECT_EQ(chosen.brickPoolCapacity, set.brickPoolCapacity - 1);
  EXPECT_LE(tight.value()->stats().totalBytes, today.totalBytes - 1);
}

TEST_F(MemoryBudget, aBudgetBelowTheMinimumIsRefusedNamingTheBudgetAndTheMinimum) {
  // 8 MB at 1920×1080: the gather's images alone take more.
  const uint64_t budget = 8 * kMebibyte;
  auto refused = Context::create(highTier(1920, 1080, budget));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().status, Status::InvalidDescription);
  const std::string& message = refused.error().message;
  EXPECT_NE(message.find("memoryBudgetBytes"), std::string::npos) << message;
  EXPECT_NE(message.find(std::to_string(budget)), std::string::npos) << message;
  EXPECT_NE(message.find("minimum"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  std::printf("%s\n", message.c_str());

  // The minimum it names is one: a budget of exactly that is accepted, and fits.
  const size_t at = message.find("minimum of ") + std::string("minimum of ").size();
  const uint64_t minimum = std::stoull(message.substr(at));
  ASSERT_GT(minimum, budget);
  auto smallest = Context::create(highTier(1920, 1080, minimum));
  ASSERT_TRUE(smallest.ok()) << smallest.error().message;
  EXPECT_LE(smallest.value()->stats().totalBytes, minimum);
  auto below = Context::create(highTier(1920, 1080, minimum - 1));
  ASSERT_FALSE(below.ok());
  EXPECT_EQ(below.error().status, Status::InvalidDescription);
}

TEST_F(MemoryBudget, withoutABudgetTheSettingsAndSizesAreTodays) {
  const Settings set = settingsForTier(QualityTier::High);
  auto created = Context::create(highTier(1920, 1080, 0));
  ASSERT_TRUE(created.ok()) << created.error().message;
  const Context& context = *created.value();
  EXPECT_TRUE(sameSettings(context.settings(), set));
  const Stats stats = created.value()->stats();
  EXPECT_EQ(stats.memoryBudgetBytes, 0u);
  EXPECT_TRUE(sameSettings(stats.settings, set));
  EXPECT_EQ(stats.brickPoolCapacity, set.brickPoolCapacity);
  EXPECT_EQ(memoryOf(stats, "ssvgi brick pool voxels"),
            uint64_t(set.brickPoolCapacity) * shader::kVoxelsPerBrick * sizeof(shader::Voxel));
  EXPECT_EQ(memoryOf(stats, "ssvgi brick lookup"), cells(set.volumeBricks) * 4);
  EXPECT_EQ(memoryOf(stats, "ssvgi probe volume"), shader::kProbeLevels * cells(set.probeGrid) * sizeof(shader::Probe));
  std::printf("no budget at 1920x1080: pool %u bricks, %llu bytes\n", stats.brickPoolCapacity,
              static_cast<unsigned long long>(stats.totalBytes));  // docs/ARCHITECTURE.md's table
}

}  // namespace
}  // namespace ssvgi
