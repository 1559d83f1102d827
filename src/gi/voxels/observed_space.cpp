#include "ssvgi_shaders.h"
#include "voxel_passes.h"

#include <algorithm>
#include <cmath>

namespace ssvgi::gi {

namespace {

// About this many rays per view and frame, whatever its size: a 1280×720 camera walks every 7th pixel in X and Y,
// whose rays lie 0.8 m apart 64 m away (less than a 1 m brick; the offset moves every frame), and a 64×64 face of the
// capture around the camera every pixel.
constexpr double kRaysPerView = 16384.0;

}  // namespace

ObservedSpace::ObservedSpace(gpu::Device& device)
    : perspective_(device, shaders::observed_space_comp, {VK_FALSE}),
      orthographic_(device, shaders::observed_space_comp, {VK_TRUE}) {}

void ObservedSpace::record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
                           const shader::GiFrame& frame) {
  auto scope = commands.scope("ssvgi: ObservedSpace");
  const glm::uvec2 depthSize = frame.size;
  // An orthographic projection leaves w alone: the bottom row of its matrix is (0, 0, 0, 1).
  const glm::mat4& projection = frame.viewProjection;
  const bool orthographic = projection[0][3] == 0.0f && projection[1][3] == 0.0f && projection[2][3] == 0.0f;
  const uint32_t pixelStride =
      std::max(1u, uint32_t(std::sqrt(double(depthSize.x) * double(depthSize.y) / kRaysPerView)));
  const glm::uvec2 threads = (depthSize + pixelStride - 1u) / pixelStride;
  commands.dispatch(orthographic ? orthographic_ : perspective_,
                    scene.bindings()
                        .buffer(shader::kBindGiFrame, inputs.frame)
                        .externalSampled(shader::kBindFirstPassSlot, inputs.depth, inputs.pointSampler),
                    {threads.x, threads.y, 1}, pixelStride);
}

}  // namespace ssvgi::gi
