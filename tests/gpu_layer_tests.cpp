// The Vulkan layer: transfers, reflection-driven dispatch, barriers and timestamps.
#include "gpu/command_list.h"
#include "gpu_host/transfers.h"
#include "gpu_test_device.h"
#include "ssvgi_gpu_tests_shaders.h"

#include <cstring>
#include <numeric>
#include <vector>

namespace ssvgi {
namespace {

using testing::GpuTest;

struct ScalePush {
  float scale;
  float offset;
  uint32_t count;
};

class GpuLayer : public GpuTest {};

TEST_F(GpuLayer, uploadAndReadbackRoundTripIsExact) {
  std::vector<uint32_t> values(10'000);
  std::iota(values.begin(), values.end(), 0xabc0000u);
  gpu::Buffer buffer(device(), "round trip", values.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device(), buffer, std::as_bytes(std::span(values)));
  EXPECT_EQ(gpu::readBufferAs<uint32_t>(device(), buffer), values);
}

TEST_F(GpuLayer, aSubmitFromInsideARecordingIsRefusedAndTheDeviceStaysUsable) {
  // The device re-records one command buffer: a nested submit would reset it mid-recording.
  gpu::Buffer buffer(device(), "nested submit", 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  EXPECT_THROW(device().submitAndWait([&](VkCommandBuffer) { device().submitAndWait([](VkCommandBuffer) {}); }),
               gpu::GpuError);
  const std::vector<uint32_t> values{7, 8, 9, 10};
  gpu::uploadBuffer(device(), buffer, std::as_bytes(std::span(values)));
  EXPECT_EQ(gpu::readBufferAs<uint32_t>(device(), buffer), values);
}

TEST_F(GpuLayer, imageUploadAndReadbackRoundTripIsExact) {
  gpu::Image image(device(), {"round trip image", VK_FORMAT_R32G32B32A32_SFLOAT, 13, 7, 1, 1,
                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT});
  std::vector<float> texels(13 * 7 * 4);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = float(i) * 0.37f - 11.0f;
  gpu::uploadImage(device(), image, std::as_bytes(std::span(texels)));
  const auto bytes = gpu::readImage(device(), image);
  ASSERT_EQ(bytes.size(), texels.size() * sizeof(float));
  EXPECT_EQ(std::memcmp(bytes.data(), texels.data(), bytes.size()), 0);
}

TEST_F(GpuLayer, computeDispatchChainsThroughTrackedBarriers) {
  // Two dependent dispatches (a -> b, then b -> a) in one command buffer: without the read-after-write barrier the
  // second would read stale values on a real GPU, and validation's synchronization checks would flag it.
  constexpr uint32_t kCount = 1000;  // not a multiple of the local size: the group count must round up
  std::vector<float> input(kCount);
  std::iota(input.begin(), input.end(), 1.0f);
  gpu::Buffer a(device(), "a", kCount * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::Buffer b(device(), "b", kCount * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device(), a, std::as_bytes(std::span(input)));

  gpu::ComputePipeline pipeline(device(), tests::scale_values_comp);
  EXPECT_EQ(pipeline.localSize().x, 64u);
  EXPECT_EQ(pipeline.layout().pushConstantBytes(), sizeof(ScalePush));
  ASSERT_EQ(pipeline.layout().bindings().size(), 2u);
  EXPECT_FALSE(pipeline.layout().bindings()[0].writable);
  EXPECT_TRUE(pipeline.layout().bindings()[1].writable);

  gpu::DescriptorArena descriptors(device());
  gpu::Profiler profiler(device());
  device().submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList list(device(), commandBuffer, descriptors, &profiler);
    profiler.begin(commandBuffer);
    {
      auto scope = list.scope("test: first");
      list.dispatch(pipeline, gpu::Bindings().buffer(0, a).buffer(1, b), {kCount, 1, 1}, ScalePush{2.0f, 1.0f, kCount});
    }
    {
      auto scope = list.scope("test: second");
      list.dispatch(pipeline, gpu::Bindings().buffer(0, b).buffer(1, a), {kCount, 1, 1}, ScalePush{0.5f, -3.0f, kCount});
    }
  });
  const auto result = gpu::readBufferAs<float>(device(), a);
  for (uint32_t i = 0; i < kCount; ++i) ASSERT_FLOAT_EQ(result[i], (input[i] * 2.0f + 1.0f) * 0.5f - 3.0f) << i;

  const auto timings = profiler.resolve();
  if (profiler.supported()) {
    ASSERT_EQ(timings.size(), 2u);
    EXPECT_EQ(timings[0].name, "test: first");
    EXPECT_EQ(timings[1].name, "test: second");
    for (const auto& timing : timings) {
      EXPECT_GT(timing.milliseconds, 0.0) << timing.name;
      EXPECT_LT(timing.milliseconds, 10'000.0) << timing.name;
    }
  }
}

TEST_F(GpuLayer, dispatchWithAMissingBindingNamesTheShaderAndSlot) {
  gpu::ComputePipeline pipeline(device(), tests::scale_values_comp);
  gpu::Buffer a(device(), "a", 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::DescriptorArena descriptors(device());
  device().submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList list(device(), commandBuffer, descriptors);
    try {
      list.dispatch(pipeline, gpu::Bindings().buffer(0, a), {1, 1, 1}, ScalePush{1, 0, 1});
      ADD_FAILURE() << "expected an error";
    } catch (const gpu::GpuError& error) {
      EXPECT_NE(std::string(error.what()).find("tests/scale_values.comp: binding 1 (Output) is not bound"),
                std::string::npos)
          << error.what();
    }
    EXPECT_THROW(list.dispatch(pipeline, gpu::Bindings().buffer(0, a).buffer(1, a), {1, 1, 1}, uint32_t{0}),
                 gpu::GpuError);  // push constant size mismatch
  });
}

TEST_F(GpuLayer, memoryOfNamedResourcesIsTracked) {
  const auto before = device().allocations();
  {
    gpu::Buffer buffer(device(), "tracked buffer", 4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    EXPECT_EQ(device().allocations().at("tracked buffer"), 4096u);
  }
  EXPECT_EQ(device().allocations(), before);
}

TEST(GpuDeviceSelection, anUnknownSelectorIsAClearError) {
  try {
    gpu::OwnedDevice device(gpu::DeviceDesc{"fastest", false});
    ADD_FAILURE() << "expected an error";
  } catch (const gpu::GpuError& error) {
    EXPECT_NE(std::string(error.what()).find("device selector 'fastest': must be auto, cpu, gpu or a device index"),
              std::string::npos);
  }
  EXPECT_THROW(gpu::OwnedDevice(gpu::DeviceDesc{"99", false}), gpu::GpuError);
}

}  // namespace
}  // namespace ssvgi

namespace ssvgi {
namespace {

// Proves the validation hook is live, so that a clean GpuTest means something: an invalid call must be counted.
TEST(GpuValidation, anInvalidCallIsCountedAsAValidationError) {
  gpu::OwnedDevice& device = testing::gpuTestDevice();
  const uint32_t before = device.validationErrorCount();
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 0;  // VUID-VkBufferCreateInfo-size-00912
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  if (vkCreateBuffer(device.device(), &info, nullptr, &buffer) == VK_SUCCESS) vkDestroyBuffer(device.device(), buffer, nullptr);
  EXPECT_GT(device.validationErrorCount(), before);
}

}  // namespace
}  // namespace ssvgi
