#pragma once
// The GPU resources of the voxel scene (SPEC §4.1) and its per-frame placement around the camera.
#include "gpu/pipelines.h"
#include "shared/voxel_interface.h"
#include "ssvgi/ssvgi.h"

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace ssvgi::gi {

// The lowest scroll step (kScrollStepBricks bricks) of a volume `volumeSteps` steps tall that holds the most of the
// surface pixels the camera saw — `pixelsByBand`, BrickPoolState::surfacePixelsByHeight, whose middle band is the step
// `bandsViewpointStep`; the end bands, which hold everything beyond, are held by none. The volume is flat (at high
// tier 12 steps tall, 32 across): a camera higher above the ground than half of that, looking down, sees the ground
// outside a volume centred on it. Where `currentBottomStep` holds no fewer than the best placement less
// kVolumePlacementSlack of all the pixels counted, it stays, so that the volume does not scroll back and forth with
// the camera's small moves; among equals, the one nearest to centred on the camera's step `cameraStep`. With no pixel
// counted (the camera saw only sky), it stays while it holds the camera's step, and is centred on it once it does not.
inline constexpr float kVolumePlacementSlack = 0.02f;  // of the pixels counted
// One camera frame in this many counts the heights (the context's own count of dispatches, whatever the host's frame
// indices); place() is given the counts of those frames only: the count's barriers make BrickAllocate dearer
// (PERFORMANCE.md).
inline constexpr uint32_t kSurfaceHeightFramePeriod = 4;
int volumeBottomStep(std::span<const uint32_t> pixelsByBand, int bandsViewpointStep, int cameraStep, int volumeSteps,
                     int currentBottomStep);

class VoxelScene {
 public:
  VoxelScene(gpu::Device& device, const Settings& settings, uint32_t framesInFlight);
  // The bytes the constructor allocates for these arguments, without allocating them (the memory budget's count).
  static VkDeviceSize bytes(const Settings& settings, uint32_t framesInFlight);

  // Where the volume stands this frame, its origin moving in kScrollStepBricks steps: centred on the camera across,
  // and as high as holds the most of the surfaces the camera saw (volumeBottomStep) — `seen`, the pool state read back
  // from the frame that last used this frame's slot (frame index modulo framesInFlight) where that frame counted the
  // heights, else nullptr: where it stood (centred at first). Also whether the frame's passes count their work
  // (VoxelVolume::countsWork). Returns the volume description to upload; `scrolled` tells whether the origin moved
  // since the last call.
  shader::VoxelVolume place(glm::vec3 cameraPosition, const shader::BrickPoolState* seen, uint32_t frameIndex,
                            bool countsWork, bool& scrolled);

  // This frame's VoxelVolume uniform buffer: one per frame in flight, so the host may write the next frame's while the
  // GPU still reads the last.
  const gpu::Buffer& volume() const { return volumes_[currentVolume_]; }
  const gpu::Buffer& brickLookup() const { return brickLookup_; }
  const gpu::Buffer& bricks() const { return bricks_; }
  const gpu::Buffer& voxels() const { return voxels_; }
  const gpu::Buffer& occupancyGrid() const { return occupancyGrid_; }
  const gpu::Buffer& observedSpace() const { return observedSpace_; }
  const gpu::Buffer& poolState() const { return poolState_; }   // BrickPoolState, then the free list (uint[capacity])
  const gpu::Buffer& changedCells() const { return changedCells_; }  // uint count, then brick cell indices
  // WorkCounters of a frame that counts its work: its passes add to it untracked (gpu::Bindings::accumulator), so
  // the frame clears and copies it with barriers of its own.
  const gpu::Buffer& workCounters() const { return workCounters_; }
  uint32_t cellCount() const;
  // The words of a grid level's bit volume (levels kFirstGridLevel and up; voxel_interface.h).
  uint32_t gridLevelWords(uint32_t level) const;
  // The scene's shared binding slots (voxel_access.glsl, brick_pool.glsl, work_counting.glsl) for a pass's Bindings.
  gpu::Bindings bindings() const;
  const Settings& settings() const { return settings_; }
  const shader::VoxelVolume& current() const { return current_; }

 private:
  struct BufferBytes;
  static BufferBytes bufferBytes(const Settings& settings);
  VoxelScene(gpu::Device& device, const Settings& settings, uint32_t framesInFlight, const BufferBytes& bytes);
  Settings settings_;
  std::vector<gpu::Buffer> volumes_;
  size_t currentVolume_ = 0;
  gpu::Buffer brickLookup_;
  gpu::Buffer bricks_;
  gpu::Buffer voxels_;
  gpu::Buffer occupancyGrid_;
  gpu::Buffer observedSpace_;
  gpu::Buffer poolState_;
  gpu::Buffer changedCells_;
  gpu::Buffer workCounters_;
  shader::VoxelVolume current_{};
  bool placed_ = false;
  // The camera's scroll step in each volume slot's frame: the middle band of the heights measured in it.
  std::vector<int> slotViewpointStep_;
};

}  // namespace ssvgi::gi
