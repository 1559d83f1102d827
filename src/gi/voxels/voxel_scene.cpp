#include "voxel_scene.h"

#include "shared/work_counters.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace ssvgi::gi {

namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

glm::uvec3 volumeBricksOf(const Settings& settings) {
  return glm::uvec3(settings.volumeBricks[0], settings.volumeBricks[1], settings.volumeBricks[2]);
}

// Where the bit volume of each grid level (2–6) lies in the occupancy grid's buffer, and the observed space's: the
// toroidal levels over the volume's cells of theirs, the local ones rounded up past its far faces (voxel_interface.h).
struct GridLayout {
  static constexpr uint32_t kLevels = shader::kOccupancyLevels - shader::kFirstGridLevel;
  std::array<uint32_t, kLevels> firstWord{};
  std::array<uint32_t, kLevels> words{};
  uint32_t totalWords = 0;
};

GridLayout gridLayout(glm::uvec3 volumeBricks) {
  GridLayout layout;
  for (uint32_t level = shader::kFirstGridLevel; level < shader::kOccupancyLevels; ++level) {
    const uint32_t slot = level - shader::kFirstGridLevel;
    const glm::uvec3 cells(shader::gridLevelCells(level, glm::ivec3(volumeBricks)));
    layout.firstWord[slot] = layout.totalWords;
    layout.words[slot] = (cells.x * cells.y * cells.z + 31u) / 32u;
    layout.totalWords += layout.words[slot];
  }
  return layout;
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
          4 * VkDeviceSize(gridLayout(volumeBricksOf(settings)).totalWords),
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
  slotViewpointStep_.resize(framesInFlight);
  current_.dimensionsBricks = glm::ivec3(volumeBricksOf(settings));
  current_.brickPoolCapacity = settings.brickPoolCapacity;
  current_.voxelSize = settings.voxelSize;
  current_.brickSize = settings.voxelSize * shader::kBrickSizeVoxels;
  current_.bricksPerMetre = 1.0f / current_.brickSize;
  const GridLayout grid = gridLayout(volumeBricksOf(settings));
  current_.gridWordOffsets = glm::uvec3(grid.firstWord[0], grid.firstWord[1], grid.firstWord[2]);
  current_.localGridWordOffsets = glm::uvec2(grid.firstWord[3], grid.firstWord[4]);
  current_.gridWords = grid.totalWords;
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

uint32_t VoxelScene::gridLevelWords(uint32_t level) const {
  return gridLayout(volumeBricksOf(settings_)).words[level - shader::kFirstGridLevel];
}

uint32_t VoxelScene::cellCount() const {
  return settings_.volumeBricks[0] * settings_.volumeBricks[1] * settings_.volumeBricks[2];
}

int volumeBottomStep(std::span<const uint32_t> pixelsByBand, int bandsViewpointStep, int cameraStep, int volumeSteps,
                     int currentBottomStep) {
  const int centred = cameraStep - volumeSteps / 2;
  // Steps from firstStep up, with the pixels of steps below each (the end bands counted in the total alone).
  const int bands = int(pixelsByBand.size());
  const int firstStep = bandsViewpointStep - bands / 2 + 1;
  std::vector<uint64_t> below(size_t(bands - 1), 0);
  for (int band = 1; band + 1 < bands; ++band) below[size_t(band)] = below[size_t(band - 1)] + pixelsByBand[band];
  const uint64_t total = below.back() + pixelsByBand.front() + pixelsByBand.back();
  if (total == 0) {  // nothing seen: where it stands, while that holds the camera
    const bool holdsCamera = cameraStep >= currentBottomStep && cameraStep < currentBottomStep + volumeSteps;
    return holdsCamera ? currentBottomStep : centred;
  }
  const auto pixelsHeld = [&](int bottomStep) {  // of the steps [bottomStep, bottomStep + volumeSteps)
    const auto belowStep = [&](int step) { return below[size_t(std::clamp(step - firstStep, 0, bands - 2))]; };
    return belowStep(bottomStep + volumeSteps) - belowStep(bottomStep);
  };
  int best = centred;
  uint64_t bestHeld = pixelsHeld(centred);
  for (int bottom = firstStep + 1 - volumeSteps; bottom < firstStep + bands - 2; ++bottom) {  // those that hold a band
    const uint64_t held = pixelsHeld(bottom);
    if (held > bestHeld || (held == bestHeld && std::abs(bottom - centred) < std::abs(best - centred))) {
      best = bottom;
      bestHeld = held;
    }
  }
  if (double(pixelsHeld(currentBottomStep)) >= double(bestHeld) - kVolumePlacementSlack * double(total))
    return currentBottomStep;
  return best;
}

shader::VoxelVolume VoxelScene::place(glm::vec3 cameraPosition, const shader::BrickPoolState* seen,
                                      uint32_t frameIndex, bool countsWork, bool& scrolled) {
  const glm::ivec3 dimensions = current_.dimensionsBricks;
  const float brickSize = current_.brickSize;
  const int step = shader::kScrollStepBricks;
  currentVolume_ = frameIndex % volumes_.size();
  // The step-aligned brick under the camera, minus half the volume (itself a multiple of the step: dimensions are
  // multiples of 2 × step); then as high as the surfaces the camera saw ask for (nothing counted: where it stood).
  const glm::ivec3 cameraStep = glm::ivec3(glm::floor(cameraPosition / (brickSize * float(step))));
  glm::ivec3 origin = cameraStep * step - dimensions / 2;
  if (placed_)
    origin.y = seen ? step * volumeBottomStep(seen->surfacePixelsByHeight, slotViewpointStep_[currentVolume_],
                                              cameraStep.y, dimensions.y / step, current_.originBrick.y / step)
                    : current_.originBrick.y;
  slotViewpointStep_[currentVolume_] = cameraStep.y;
  scrolled = !placed_ || origin != current_.originBrick;
  current_.previousOriginBrick = placed_ ? current_.originBrick : origin;
  placed_ = true;
  current_.originBrick = origin;
  current_.verticalShiftBricks = origin.y + dimensions.y / 2 - cameraStep.y * step;
  current_.countsWork = countsWork ? 1u : 0u;
  std::memcpy(volumes_[currentVolume_].mapped(), &current_, sizeof(current_));
  return current_;
}

}  // namespace ssvgi::gi
