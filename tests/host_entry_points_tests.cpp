// A host's own Vulkan entry points (ContextDesc::vkGetInstanceProcAddr/vkGetDeviceProcAddr): the context calls the
// device through them, and a Vulkan failure comes back with its VkResult (Error::vkResult).
#include "gpu_test_device.h"

#include <cstring>

namespace ssvgi {
namespace {

// The host's entry points wrap the loader's: vkCreateBuffer is counted, or fails with `failBuffersWith`.
PFN_vkGetInstanceProcAddr loaderGetInstanceProcAddr = vkGetInstanceProcAddr;
PFN_vkGetDeviceProcAddr loaderGetDeviceProcAddr = nullptr;
PFN_vkCreateBuffer loaderCreateBuffer = nullptr;
uint32_t buffersCreated = 0;
VkResult failBuffersWith = VK_SUCCESS;

VKAPI_ATTR VkResult VKAPI_CALL hostCreateBuffer(VkDevice device, const VkBufferCreateInfo* info,
                                                const VkAllocationCallbacks* allocator, VkBuffer* buffer) {
  if (failBuffersWith != VK_SUCCESS) return failBuffersWith;
  ++buffersCreated;
  return loaderCreateBuffer(device, info, allocator, buffer);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL hostGetDeviceProcAddr(VkDevice device, const char* name) {
  if (std::strcmp(name, "vkCreateBuffer") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&hostCreateBuffer);
  return loaderGetDeviceProcAddr(device, name);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL hostGetInstanceProcAddr(VkInstance instance, const char* name) {
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&hostGetDeviceProcAddr);
  return loaderGetInstanceProcAddr(instance, name);
}

class HostEntryPoints : public testing::GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    loaderGetDeviceProcAddr = reinterpret_cast<PFN_vkGetDeviceProcAddr>(
        vkGetInstanceProcAddr(device().instance(), "vkGetDeviceProcAddr"));
    loaderCreateBuffer =
        reinterpret_cast<PFN_vkCreateBuffer>(loaderGetDeviceProcAddr(device().device(), "vkCreateBuffer"));
    buffersCreated = 0;
    failBuffersWith = VK_SUCCESS;
  }
  void TearDown() override {
    failBuffersWith = VK_SUCCESS;
    GpuTest::TearDown();
  }
  static ContextDesc desc() {
    Settings settings = settingsForTier(QualityTier::Low);
    settings.volumeBricks = {16, 16, 16};
    settings.brickPoolCapacity = 512;
    settings.probeGrid = {8, 8, 8};
    return testing::gpuTestContextDesc(settings, 64);
  }
};

TEST_F(HostEntryPoints, theContextCreatesItsBuffersThroughTheHostsDeviceProcAddr) {
  ContextDesc contextDesc = desc();
  contextDesc.vkGetInstanceProcAddr = loaderGetInstanceProcAddr;
  contextDesc.vkGetDeviceProcAddr = hostGetDeviceProcAddr;
  auto created = Context::create(contextDesc);
  ASSERT_TRUE(created.ok()) << created.error().message;
  EXPECT_GT(buffersCreated, 10u);
}

TEST_F(HostEntryPoints, withoutADeviceProcAddrTheContextLooksItUpThroughTheHostsInstanceProcAddr) {
  ContextDesc contextDesc = desc();
  contextDesc.vkGetInstanceProcAddr = hostGetInstanceProcAddr;
  auto created = Context::create(contextDesc);
  ASSERT_TRUE(created.ok()) << created.error().message;
  EXPECT_GT(buffersCreated, 10u);
}

TEST_F(HostEntryPoints, aFailedCallReturnsItsVkResultAndOutOfDeviceMemoryIsToldApart) {
  ContextDesc contextDesc = desc();
  contextDesc.vkGetDeviceProcAddr = hostGetDeviceProcAddr;
  failBuffersWith = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  auto outOfMemory = Context::create(contextDesc);
  ASSERT_FALSE(outOfMemory.ok());
  EXPECT_EQ(outOfMemory.error().status, Status::OutOfDeviceMemory);
  EXPECT_EQ(outOfMemory.error().vkResult, VK_ERROR_OUT_OF_DEVICE_MEMORY);

  failBuffersWith = VK_ERROR_OUT_OF_HOST_MEMORY;
  auto failed = Context::create(contextDesc);
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(failed.error().status, Status::VulkanError);
  EXPECT_EQ(failed.error().vkResult, VK_ERROR_OUT_OF_HOST_MEMORY);
  EXPECT_NE(failed.error().message.find("vkCreateBuffer"), std::string::npos) << failed.error().message;
}

TEST_F(HostEntryPoints, anErrorThatNoVulkanCallReturnedCarriesVkSuccess) {
  ContextDesc contextDesc = desc();
  contextDesc.settings.voxelSize = -1.0f;
  auto invalid = Context::create(contextDesc);
  ASSERT_FALSE(invalid.ok());
  EXPECT_EQ(invalid.error().status, Status::InvalidDescription);
  EXPECT_EQ(invalid.error().vkResult, VK_SUCCESS);
}

}  // namespace
}  // namespace ssvgi
