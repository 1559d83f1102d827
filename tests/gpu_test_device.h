#pragma once
// One Vulkan device (lavapipe in CI) with validation on, shared by every GPU test of a test executable: creating a
// device and compiling pipelines dominate the run time on a CPU device. Deriving a test from GpuTest makes any
// validation error reported during that test fail it.
#include "gpu_host/owned_device.h"
#include "ssvgi/ssvgi.h"

#include <gtest/gtest.h>

namespace ssvgi::testing {

gpu::OwnedDevice& gpuTestDevice();

// A GI context description on the shared test device, for frames and extra views of at most `maxSize`² pixels.
inline ContextDesc gpuTestContextDesc(const Settings& settings, uint32_t maxSize) {
  ContextDesc desc;
  desc.instance = gpuTestDevice().instance();
  desc.physicalDevice = gpuTestDevice().physicalDevice();
  desc.device = gpuTestDevice().device();
  desc.debugUtilsEnabled = true;
  desc.settings = settings;
  desc.maxWidth = desc.maxHeight = desc.maxExtraViewSize = maxSize;
  return desc;
}

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override { errorsBefore_ = device().validationErrorCount(); }
  void TearDown() override {
    EXPECT_EQ(device().validationErrorCount(), errorsBefore_)
        << "validation error during the test: " << device().lastValidationError();
  }
  static gpu::OwnedDevice& device() { return gpuTestDevice(); }

 private:
  uint32_t errorsBefore_ = 0;
};

}  // namespace ssvgi::testing
