#pragma once
// The GPU resources of the voxel scene (SPEC §4.1) and its per-frame placement around the camera.
#include "gpu/pipelines.h"
#include "shared/voxel_interface.h"
#include "ssvgi/ssvgi.h"

#include <glm/glm.hpp>

#include <vector>

namespace ssvgi::gi {

class VoxelScene {
 public:
  VoxelScene(gpu::Device& device, const Settings& settings, uint32_t framesInFlight);
  // The bytes the constructor allocates for these arguments, without allocating them (the memory budget's count).
  static VkDeviceSize bytes(const Settings& settings, uint32_t framesInFlight);

  // Where the volume stands this frame: centred on the camera, its origin moving in kScrollStepBricks steps; and
  // whether the frame's passes count their work (VoxelVolume::countsWork). Returns the volume description to upload;
  // `scrolled` tells whether the origin moved since the last call.
  shader::VoxelVolume place(glm::vec3 cameraPosition, uint32_t frameIndex, bool countsWork, bool& scrolled);

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
};

}  // namespace ssvgi::gi
