// The per-pixel voxel trace baseline of `ssvgi bench` (bench/trace_benchmark.h, SPEC §7) against an analytic case: in
// a context whose voxel scene is empty every ray misses, so under a uniform sky of radiance L each traced pixel's
// E = π/K·Σ L is exactly π·L, and the two halves of its rays agree (no noise).
#include "camera.h"
#include "gpu_host/transfers.h"
#include "gpu_test_device.h"
#include "trace_benchmark.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace ssvgi {
namespace {

constexpr uint32_t kSize = 32;
constexpr float kSkyRadiance = 0.75f;

class PixelTraceBaseline : public testing::GpuTest {
 protected:
  void SetUp() override {
    testing::GpuTest::SetUp();
    Settings settings;
    settings.volumeBricks = {16, 8, 16};
    settings.brickPoolCapacity = 256;
    settings.probeGrid = {8, 4, 8};
    auto created = Context::create(testing::gpuTestContextDesc(settings, kSize));
    ASSERT_TRUE(created.ok()) << created.error().message;
    context_ = std::move(created.value());
    // One frame that draws nothing (reversed-Z 0: infinitely far) places the voxel volume and leaves it empty.
    gpu::Image depth(device(), {"test depth", VK_FORMAT_R32_SFLOAT, kSize, kSize, 1, 1, VK_IMAGE_USAGE_SAMPLED_BIT});
    const std::vector<float> farAway(kSize * kSize, 0.0f);
    gpu::uploadImage(device(), depth, std::as_bytes(std::span(farAway)));
    camera_.position = {0.0f, 2.0f, 6.0f};
    camera_.target = {0.0f, 0.0f, 0.0f};
    camera_.verticalFov = glm::radians(60.0f);
    const glm::mat4 viewProjection =
        renderer::reversedZInfiniteProjection(camera_.verticalFov, 1.0f, camera_.nearPlane) *
        renderer::viewMatrix(camera_);
    FrameDesc frame;
    std::copy(glm::value_ptr(viewProjection), glm::value_ptr(viewProjection) + 16,
              frame.camera.viewProjection.begin());
    frame.camera.position = {camera_.position.x, camera_.position.y, camera_.position.z};
    frame.camera.width = frame.camera.height = kSize;
    frame.depth.view = depth.view();
    frame.normal.view = depth.view();  // nothing is drawn, so nothing reads a normal
    Error error;
    device().submitAndWait([&](VkCommandBuffer commandBuffer) { error = context_->dispatch(frame, commandBuffer); });
    ASSERT_FALSE(error) << error.message;
  }

  // A view whose every pixel shows a floor-like surface (normal +Y) 4 m away, and ssvgi's E there.
  static renderer::FloatImage filled(uint32_t channels, glm::vec3 value) {
    renderer::FloatImage image{kSize, kSize, channels, {}};
    for (uint32_t i = 0; i < kSize * kSize; ++i)
      for (uint32_t c = 0; c < channels; ++c) image.pixels.push_back(value[c]);
    return image;
  }

  std::unique_ptr<Context> context_;
  renderer::Camera camera_;
};

TEST_F(PixelTraceBaseline, underAUniformSkyWithNoVoxelsEveryPixelGetsPiTimesTheRadianceWithoutNoise) {
  const float band0 = 4.0f * shader::kPi * shader::kSh2Band0Basis * kSkyRadiance;
  const shader::Sh2Rgb sky{glm::vec4(band0, 0, 0, 0), glm::vec4(band0, 0, 0, 0), glm::vec4(band0, 0, 0, 0)};
  const auto result = bench::benchmarkPixelTrace(
      device(), *context_, camera_, filled(1, glm::vec3(4.0f)), filled(3, {0.0f, 1.0f, 0.0f}),
      filled(3, glm::vec3(shader::kPi * kSkyRadiance)), sky, 2, {4, 16}, 1);
  EXPECT_EQ(result.surfacePixels, kSize * kSize);
  EXPECT_EQ(result.tracedPixels, kSize * kSize / 4);
  ASSERT_EQ(result.results.size(), 2u);
  for (const auto& measured : result.results) {
    SCOPED_TRACE(std::to_string(measured.raysPerPixel) + " rays per pixel");
    // Float sums of identical terms: far below 0.1 %; one ray hitting anything would move a pixel by ≥ 1/16.
    EXPECT_LT(measured.differenceFromSsvgi, 1e-3);
    EXPECT_LT(measured.noise, 1e-3);
    EXPECT_GT(measured.milliseconds, 0.0);
    EXPECT_NEAR(measured.fullFrameMilliseconds, 4.0 * measured.milliseconds, 1e-9 * measured.milliseconds);
  }
}

TEST_F(PixelTraceBaseline, aRayCountThatIsNotAnEvenSquareIsRefusedWithTheReason) {
  const shader::Sh2Rgb sky{};
  try {
    bench::benchmarkPixelTrace(device(), *context_, camera_, filled(1, glm::vec3(4.0f)),
                               filled(3, {0.0f, 1.0f, 0.0f}), filled(3, glm::vec3(1.0f)), sky, 2, {9}, 1);
    FAIL() << "9 rays per pixel were accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("even squares"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace ssvgi
