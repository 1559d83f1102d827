#include "voxel_scene.h"

#include "shared/work_counters.h"

#include <cmath>
#include <cstring>

namespace ssvgi::gi {

namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

uint32_t gridWords(glm::uvec3 dimensions) { return (dimensions.x * dimensions.y * dimensions.z + 31u) / 32u; }

// Bit volumes of grid levels 2–4 over the volume's brick cells (the occupancy grid, the observed space).
VkDeviceSize gridBytes(const Settings& settings) {
  const glm::uvec3 dimensions(settings.volumeBricks[0], settings.volumeBricks[1], settings.volumeBricks[2]);
  return 4 * VkDeviceSize(gridWords(dimensions) + gridWords(dimensions / 2u) + gridWords(dimensions / 4u));
}

}  // namespace

// The bytes of each buffer of a scene of `settings`: what the constructor allocates and bytes() counts.
struct VoxelScene::BufferBytes {
  VkDeviceSize brickLookup, brickHeaders, voxels, grid, poolState, changedCells, workCounters, volume;
};

VoxelScene::BufferBytes VoxelScene::bufferBytes(const Settings& settings) {
  const VkDeviceSize capacity = settings.brickPoolCapacity;
  return {VkDeviceSize(settings.volumeBricks[0]) * settings.volumeBricks[1] * settings.volumeBricks[2] * 4,
          capacity * sizeof(shader::Brick),
          capacity * shader::kVoxelsPerBrick * sizeof(shader::Voxel),
          gridBytes(settings),
          sizeof(shader::BrickPoolState) + capacity * 4,
          sizeof(shader::IndirectList) + capacity * 2 * 4,
          sizeof(shader::WorkCounters),
          sizeof(shader::VoxelVolume)};
}

VoxelScene::VoxelScene(gpu::Device& device, const Settings& settings, uint32_t framesInFlight)
    : VoxelScene(device, settings, framesInFlight, bufferBytes(settings)) {}

VoxelScene::VoxelScene(gpu::Device& device, const Settings& settings, uint32_t framesInFlight,
                       const BufferBytes& bytes)
    : settings_(settings),
      brickLookup_(device, "ssvgi brick lookup", bytes.brickLookup, kStorage),
      bricks_(device, "ssvgi brick pool headers", bytes.brickHeaders, kStorage),
      voxels_(device, "ssvgi brick pool voxels", bytes.voxels, kStorage),
      occupancyGrid_(device, "ssvgi occupancy grid", bytes.grid, kStorage),
      observedSpace_(device, "ssvgi observed space", bytes.grid, kStorage),
      poolState_(device, "ssvgi brick pool state and free list", bytes.poolState, kStorage),
      changedCells_(device, "ssvgi changed brick cells", bytes.changedCells,
                    kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT),
      workCounters_(device, "ssvgi work counters", bytes.workCounters, kStorage) {
  for (uint32_t i = 0; i < framesInFlight; ++i)
    volumes_.emplace_back(device, "ssvgi voxel volume", bytes.volume, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          gpu::MemoryUsage::HostUpload);
  const glm::uvec3 dimensions(settings.volumeBricks[0], settings.volumeBricks[1], settings.volumeBricks[2]);
  current_.dimensionsBricks = glm::ivec3(dimensions);
  current_.brickPoolCapacity = settings.brickPoolCapacity;
  current_.voxelSize = settings.voxelSize;
  current_.brickSize = settings.voxelSize * shader::kBrickSizeVoxels;
  current_.bricksPerMetre = 1.0f / current_.brickSize;
  const uint32_t level2 = gridWords(dimensions), level3 = gridWords(dimensions / 2u), level4 = gridWords(dimensions / 4u);
  current_.gridWordOffsets = glm::uvec3(0, level2, level2 + level3);
  current_.gridWords = level2 + level3 + level4;
  current_.invalidFramesToClear = settings.invalidFramesToClear;
  current_.emptyFramesToRelease = settings.emptyFramesToRelease;
  current_.skyOnlyThroughObservedSpace = settings.skyOnlyThroughObservedSpace ? 1u : 0u;
}

VkDeviceSize VoxelScene::bytes(const Settings& settings, uint32_t framesInFlight) {
  const BufferBytes bytes = bufferBytes(settings);
  return bytes.brickLookup + bytes.brickHeaders + bytes.voxels + 2 * bytes.grid + bytes.poolState +
         bytes.changedCells + bytes.workCounters + framesInFlight * bytes.volume;
}

gpu::Bindings VoxelScene::bindings() const {
  return gpu::Bindings()
      .buffer(shader::kBindVoxelVolume, volume())
      .buffer(shader::kBindBrickLookup, brickLookup_)
      .buffer(shader::kBindBricks, bricks_)
      .buffer(shader::kBindVoxels, voxels_)
      .buffer(shader::kBindOccupancyGrid, occupancyGrid_)
      .buffer(shader::kBindObservedSpace, observedSpace_)
      .buffer(shader::kBindPoolState, poolState_)
      .buffer(shader::kBindChangedCells, changedCells_)
      .accumulator(shader::kBindWorkCounters, workCounters_);
}

uint32_t VoxelScene::cellCount() const {
  return settings_.volumeBricks[0] * settings_.volumeBricks[1] * settings_.volumeBricks[2];
}

shader::VoxelVolume VoxelScene::place(glm::vec3 cameraPosition, uint32_t frameIndex, bool countsWork,
                                      bool& scrolled) {
  const glm::ivec3 dimensions = current_.dimensionsBricks;
  const float brickSize = current_.brickSize;
  const int step = shader::kScrollStepBricks;
  // The step-aligned brick under the camera, minus half the volume (itself a multiple of the step: dimensions are
  // multiples of 2 × step).
  const glm::ivec3 cameraBrick = glm::ivec3(glm::floor(cameraPosition / (brickSize * float(step)))) * step;
  const glm::ivec3 origin = cameraBrick - dimensions / 2;
  scrolled = !placed_ || origin != current_.originBrick;
  current_.previousOriginBrick = placed_ ? current_.originBrick : origin;
  placed_ = true;
  current_.originBrick = origin;
  current_.countsWork = countsWork ? 1u : 0u;
  currentVolume_ = frameIndex % volumes_.size();
  std::memcpy(volumes_[currentVolume_].mapped(), &current_, sizeof(current_));
  return current_;
}

}  // namespace ssvgi::gi
