#pragma once
// The passes that build the voxel scene each frame (SPEC §4 steps 1–5; the talk's "Part1 GI Scene"), in frame order.
// Each is one compute shader in shaders/gi/voxels/ and one small class that binds and dispatches it.
#include "gpu/command_list.h"
#include "shared/gi_frame.h"
#include "voxel_scene.h"

namespace ssvgi::gi {

// Everything a voxel pass reads from the frame besides the voxel scene.
struct VoxelFrameInputs {
  const gpu::Buffer& frame;  // GiFrame uniform
  VkSampler pointSampler;
  VkImageView depth;         // current depth (host image)
  VkImageView normal;        // current world normal (host image)
  const gpu::Buffer& hiz;    // Hi-Z pyramid
  const gpu::Buffer& visibleBricks;  // IndirectList of pool indices, written by BrickCulling
};

// HiZBuild: farthest-depth pyramid of the current depth.
class HiZBuild {
 public:
  explicit HiZBuild(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelFrameInputs& inputs, const shader::GiFrame& frame, uint32_t levels);

 private:
  gpu::ComputePipeline fromDepth_;  // level 0
  gpu::ComputePipeline fromLevelBefore_;
};

// VolumeScroll: releases the bricks the moved volume left behind.
class VolumeScroll {
 public:
  explicit VolumeScroll(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs);

 private:
  gpu::ComputePipeline pipeline_;
};

// BrickAllocate: a pool slot for every brick with on-screen surface.
class BrickAllocate {
 public:
  explicit BrickAllocate(gpu::Device& device);
  // `countsHeights`: the camera's surface pixels are counted by height band too (kSurfaceHeightFramePeriod).
  void record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
              glm::uvec2 depthSize, uint32_t pixelStride, bool countsHeights);

 private:
  gpu::ComputePipeline allocating_;
  gpu::ComputePipeline allocatingAndCountingHeights_;  // a pipeline apart, so the other frames skip its barriers
};

// ObservedSpace: the brick cells the view saw through or into (SPEC §6.4).
class ObservedSpace {
 public:
  explicit ObservedSpace(gpu::Device& device);
  // `frame`: the view's constants, as uploaded to inputs.frame.
  void record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
              const shader::GiFrame& frame);

 private:
  gpu::ComputePipeline perspective_;
  gpu::ComputePipeline orthographic_;
};

// BrickCulling: the live bricks in view and not occluded, as a list with its indirect dispatch.
class BrickCulling {
 public:
  explicit BrickCulling(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs);

 private:
  gpu::ComputePipeline pipeline_;
};

// SceneVoxelization: a view (the lit frame or an extra view) injected into the listed bricks.
struct LitFrameImages {
  VkImageView color;
  VkImageView depth;
  VkImageView normal;
  VkImageView albedo;  // read only for a view lit by direct light only (GiFrame kind kViewIsDirectOnly)
  const gpu::Image* lastOutput;  // ssvgi's last output, read only for kViewIsLitWithOutput
};
// The probes' light, which VoxelRelight gathers for the voxels.
struct ProbeLight {
  const gpu::Buffer& gatherConstants;  // GatherConstants of this frame (the probe levels' placement)
  const gpu::Buffer& probes;           // Probe[kProbeLevels · probes per level]
};
class SceneVoxelization {
 public:
  explicit SceneVoxelization(gpu::Device& device);
  // `viewKind`: the view's GiFrame::viewKind.
  void record(gpu::CommandList& commands, const VoxelScene& scene, const VoxelFrameInputs& inputs,
              const LitFrameImages& lit, uint32_t viewKind);

 private:
  gpu::ComputePipeline pipeline_;
  gpu::ComputePipeline reflectiveShadowMap_;  // for views with kViewIsReflectiveShadowMap
};

// VoxelRelight: the voxels given direct light and albedo get direct + albedo/π · E of the probes (SPEC §6.1), the
// bricks of one phase (from their world coordinate) a frame so that every voxel is relit once every `period` frames.
class VoxelRelight {
 public:
  explicit VoxelRelight(gpu::Device& device);
  void record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeLight& probeLight, uint32_t frameIndex,
              uint32_t period);

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace ssvgi::gi
