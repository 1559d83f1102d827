#pragma once
// The images of the final gather (SPEC §4.6) and each frame's GatherConstants. Sized once for the largest frame
// (ContextDesc::maxWidth/maxHeight); a frame uses their top-left corner.
#include "gpu/pipelines.h"
#include "shared/gather_interface.h"

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace ssvgi::gi {

class GatherTargets {
 public:
  GatherTargets(gpu::Device& device, uint32_t maxWidth, uint32_t maxHeight, uint32_t framesInFlight);
  // The bytes the constructor allocates for these arguments, without allocating them (the memory budget's count).
  static VkDeviceSize bytes(gpu::Device& device, uint32_t maxWidth, uint32_t maxHeight, uint32_t framesInFlight);

  // The placement of the probe levels this frame, as the gather reads them.
  struct ProbeLevels {
    std::array<glm::ivec3, shader::kProbeLevels> origins;  // world probe coordinate of each level's minimum corner
    glm::ivec3 dimensions;                                 // probes per level and axis
    std::array<float, shader::kProbeLevels> spacings;      // m
    shader::Sh2Rgb skyRadiance{};                          // the host's sky (FrameDesc::skyRadianceSh)
  };
  // Prepares a frame of `width` × `height` seen through `viewProjection`: uploads its GatherConstants and swaps the
  // output with the history (the last frame's output). The history is used when the last frame had the same size.
  void prepare(uint32_t frameIndex, const glm::mat4& viewProjection, uint32_t width, uint32_t height,
               const ProbeLevels& probes);

  const gpu::Buffer& constants() const { return constants_[currentFrame_]; }
  const gpu::Image& tileIrradiance() const { return tileIrradiance_; }  // rgba16f, 1/4: rgb E; a: confidence
  // r8, 1/4: how fast the tile's probes are following a change (GatheredLight::probeBlend): TemporalUpsample's
  // history follows as fast.
  const gpu::Image& tileProbeBlend() const { return tileProbeBlend_; }
  const gpu::Image& history() const { return outputs_[1 - currentOutput_]; }
  // rgba16f, 1/2: rgb E; a: depth. TemporalUpsample writes it.
  const gpu::Image& output() const { return outputs_[currentOutput_]; }
  // r8, 1/2: the confidence (SPEC §6.4) of the output's E. TemporalUpsample writes it; one image, no history.
  const gpu::Image& confidence() const { return confidence_; }
  glm::uvec2 tiles() const { return current_.tiles; }
  glm::uvec2 halfSize() const { return current_.halfSize; }

 private:
  std::vector<gpu::Buffer> constants_;
  gpu::Image tileIrradiance_;
  gpu::Image tileProbeBlend_;
  static constexpr size_t kOutputs = 2;  // the output and its history, alternating
  std::array<gpu::Image, kOutputs> outputs_;
  gpu::Image confidence_;
  size_t currentFrame_ = 0;
  uint32_t currentOutput_ = 0;
  bool prepared_ = false;
  glm::mat4 previousViewProjection_{1.0f};
  shader::GatherConstants current_{};
};

}  // namespace ssvgi::gi
