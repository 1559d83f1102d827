#include "gpu_test_device.h"

#include <memory>

namespace ssvgi::testing {

namespace {
std::unique_ptr<gpu::OwnedDevice> sharedDevice;
}

gpu::OwnedDevice& gpuTestDevice() {
  if (!sharedDevice) sharedDevice = std::make_unique<gpu::OwnedDevice>(gpu::DeviceDesc{"auto", true});
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
