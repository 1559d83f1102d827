#include "gpu_test_device.h"

#include <memory>

namespace ssvgi::testing {

namespace {
std::unique_ptr<gpu::Device> sharedDevice;
}

gpu::Device& gpuTestDevice() {
  if (!sharedDevice) sharedDevice = std::make_unique<gpu::Device>(gpu::DeviceDesc{"auto", true});
  return *sharedDevice;
}

void releaseGpuTestDevice() { sharedDevice.reset(); }

}  // namespace ssvgi::testing

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  ssvgi::testing::releaseGpuTestDevice();
  return result;
}
