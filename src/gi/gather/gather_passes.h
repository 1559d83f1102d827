#pragma once
// The passes that turn the probe volume into ssvgi's output image (SPEC §4 steps 10–12; the talk's "Part3 Shading"),
// in frame order. Each is one compute shader in shaders/gi/gather/ and one small class that binds and dispatches it.
#include "gather_targets.h"
#include "gpu/command_list.h"
#include "shared/gi_frame.h"
#include "gi/voxels/voxel_scene.h"

namespace ssvgi::gi {

// What every gather pass reads of the host's frame: GiFrame and the current depth and normal (untracked host images).
struct GatherInputs {
  const gpu::Buffer& frame;  // GiFrame (shared/gi_frame.h)
  VkSampler pointSampler;
  VkImageView depth;
  VkImageView normal;

  // The bindings every gather pass starts from: GiFrame, GatherConstants, the depth and the normal, added to `base`
  // (the voxel scene's, for FinalGather's visibility test).
  gpu::Bindings bindings(const GatherTargets& targets, gpu::Bindings base = {}) const {
    return base
        .buffer(shader::kBindGiFrame, frame)
        .buffer(shader::kBindGatherConstants, targets.constants())
        .externalSampled(shader::kBindGatherDepth, depth, pointSampler)
        .externalSampled(shader::kBindGatherNormal, normal, pointSampler);
  }
};

// FinalGather: one probe-volume sample per 4×4 tile, with the leak weights → tile irradiance and confidence.
class FinalGather {
 public:
  explicit FinalGather(gpu::Device& device);
  // `probes`: Probe[kProbeLevels · probes per level], level-major (ProbeVolume::probes()).
  void record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets,
              const VoxelScene& scene, const gpu::Buffer& probes);

 private:
  gpu::ComputePipeline pipeline_;
};

// TemporalUpsample (SPEC §4 steps 11 and 12): joint bilateral upsampling of the tile irradiance to half resolution,
// blended into its reprojected, geometry-tested, neighbourhood-clamped history → the output image; the tiles'
// confidence upsampled with the same weights → the confidence image.
class TemporalUpsample {
 public:
  explicit TemporalUpsample(gpu::Device& device);
  void record(gpu::CommandList& commands, const GatherInputs& inputs, const GatherTargets& targets);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
