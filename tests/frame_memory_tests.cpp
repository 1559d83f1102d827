// A host renders frame after frame for hours: nothing that ssvgi, the renderer or the Vulkan driver allocates for a
// frame may outlive it. On lavapipe, while the passes' constants were uniform blocks, the driver compiled a variant of
// a dozen shaders at every bind and kept each one: the process grew frame after frame until it was killed
// (docs/PERFORMANCE.md, "Lavapipe compiled shaders at every bind").
#include "builtin_scenes.h"
#include "gpu_test_device.h"
#include "renderer.h"
#include "scenario_rendering.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>

namespace ssvgi {
namespace {

// The process's resident memory, from /proc/self/statm (its second field, in pages).
int64_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  int64_t sizePages = 0, residentPages = 0;
  statm >> sizePages >> residentPages;
  return residentPages * int64_t(sysconf(_SC_PAGESIZE));
}

class FrameMemory : public testing::GpuTest {};

TEST_F(FrameMemory, renderingFrameAfterFrameDoesNotGrowTheProcess) {
  // The panel room with every view the renderer gives ssvgi by default (the capture around the camera and the
  // overhead view), so that every pass and both kinds of view run.
  const renderer::Scene scene = *renderer::makeBuiltinScene("panel-room");
  bench::ScenarioRenderer frames(device(), scene, {64, 36, renderer::giSettingsFor(QualityTier::High, scene)});
  frames.render(scene.cameras.front(), 16);  // every pipeline compiled, every pool and cache at its size
  const int64_t before = residentBytes();
  constexpr uint32_t kFrames = 48;
  frames.render(scene.cameras.front(), kFrames);
  const int64_t grown = residentBytes() - before;
  std::printf("the process grew by %lld KiB over %u frames\n", static_cast<long long>(grown / 1024), kFrames);
  // 8 MB leaves room for the allocator's and the validation layer's own bookkeeping, and is less than a single frame
  // grew the process by with uniform blocks (the figures: docs/PERFORMANCE.md).
  EXPECT_LT(grown, int64_t(8) << 20) << "the process grew by " << grown / 1024 << " KiB over " << kFrames << " frames";
}

}  // namespace
}  // namespace ssvgi
