#include "memory_budget.h"

#include "gather/gather_targets.h"
#include "probes/probe_volume.h"
#include "shared/probe_interface.h"
#include "shared/voxel_interface.h"
#include "shared/work_counters.h"
#include "voxels/voxel_scene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace ssvgi::gi {

namespace {

using Axes = std::array<uint32_t, 3>;

uint32_t roundUp(uint32_t value, uint32_t multiple) { return (value + multiple - 1) / multiple * multiple; }

// What a voxel volume plausibly needs of the brick pool: a quarter of its footprint (X × Z) in bricks. Surfaces fill
// about one layer of bricks over the footprint at most, and a view sees a fraction of it: a quarter holds what the
// courtyard's camera alone fills, with room to spare (docs/QUALITY.md, "A memory budget"); a budget that would take
// the pool lower shrinks the probes, then the volume.
uint32_t brickPoolFloor(const Settings& settings, uint32_t setCapacity) {
  return std::clamp(settings.volumeBricks[0] * settings.volumeBricks[2] / 4, 1u, setCapacity);
}

// The fewest probes per axis with which the coarsest probe level still covers the voxel volume: a voxel outside every
// level gets no light from the probes (VoxelRelight), and nor does a surface the gather shades there.
Axes probeGridFloor(const Settings& settings, const Axes& setGrid) {
  const float coarsestSpacing = settings.probeSpacing * float(1u << (shader::kProbeLevels - 1));
  const float brickSize = settings.voxelSize * float(shader::kBrickSizeVoxels);
  Axes grid;
  for (size_t axis = 0; axis < grid.size(); ++axis) {
    const float probes = std::ceil(float(settings.volumeBricks[axis]) * brickSize / coarsestSpacing);
    grid[axis] = std::min(setGrid[axis], roundUp(std::max(uint32_t(probes), 1u), shader::kProbeBlockSize));
  }
  return grid;
}

// `set` scaled by step/steps on every axis (its proportions kept), each axis a multiple of `multiple` and at least
// `floor`'s (floor ≤ set): step = steps gives `set`, step = 0 `floor`.
Axes scaledDown(const Axes& set, uint32_t step, uint32_t steps, uint32_t multiple, const Axes& floor) {
  Axes scaled;
  for (size_t axis = 0; axis < scaled.size(); ++axis)
    scaled[axis] = std::max(floor[axis], uint32_t(uint64_t(set[axis]) * step / steps) / multiple * multiple);
  return scaled;
}

// Steps from `set` down to its floor, one multiple of `multiple` of its largest axis at a time.
uint32_t stepsOf(const Axes& set, uint32_t multiple) { return *std::max_element(set.begin(), set.end()) / multiple; }

std::string mebibytes(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f MiB", double(bytes) / double(1u << 20));
  return text;
}

}  // namespace

uint32_t hizLayout(uint32_t width, uint32_t height, shader::HiZLevel levels[shader::kMaxHiZLevels]) {
  uint32_t count = 0, offset = 0;
  glm::uvec2 size((width + 1) / 2, (height + 1) / 2);
  for (;;) {
    levels[count++] = {size, offset, 0};
    offset += size.x * size.y;
    if ((size.x == 1 && size.y == 1) || count == shader::kMaxHiZLevels) return count;
    size = (size + 1u) / 2u;
  }
}

ContextBufferBytes ContextBufferBytes::of(const ContextDesc& desc, const Settings& settings) {
  shader::HiZLevel levels[shader::kMaxHiZLevels];
  const uint32_t count = hizLayout(std::max(desc.maxWidth, desc.maxExtraViewSize),
                                   std::max(desc.maxHeight, desc.maxExtraViewSize), levels);
  ContextBufferBytes bytes;
  bytes.hiz = VkDeviceSize(levels[count - 1].firstTexel + 1) * sizeof(float);
  bytes.visibleBricks = sizeof(shader::IndirectList) + VkDeviceSize(settings.brickPoolCapacity) * 4;
  bytes.viewConstants = sizeof(shader::GiFrame);
  bytes.statsReadback = sizeof(shader::BrickPoolState);
  bytes.probeListReadback = sizeof(shader::IndirectList);
  bytes.workReadback = sizeof(shader::WorkCounters);
  return bytes;
}

VkDeviceSize ContextBufferBytes::total(uint32_t framesInFlight) const {
  return hiz + visibleBricks +
         framesInFlight * ((1 + kMaxExtraViews) * viewConstants + statsReadback + probeListReadback + workReadback);
}

// The order in which a budget shrinks the settings, least harmful first:
//   1. the brick pool's capacity, down to brickPoolFloor: a full pool only drops the bricks of surfaces seen last,
//      and most scenes use a fraction of the set capacity (the courtyard with its extra views half of high tier's);
//   2. the probe grid (probes per level, the spacing kept: a smaller clipmap), down to probeGridFloor: the finest
//      levels then reach less far and the gather takes coarser probes sooner, but every voxel keeps probes around it;
//   3. the voxel volume (bricks per axis, its proportions kept, which also shrinks the brick lookup and the grids),
//      with the probe grid at the floor of the smaller volume: what lies beyond it no longer occludes or reflects,
//      the harm a budget does last.
// Steps 2 and 3 shrink in steps; what a step leaves of the budget goes back to the pool, up to its set capacity.
// The gather's images and the Hi-Z pyramid follow ContextDesc::maxWidth/maxHeight/maxExtraViewSize, the host's
// choice, and never shrink: a budget they do not leave room for is refused.
Result<Settings> settingsWithinBudget(gpu::Device& device, const ContextDesc& desc) {
  const Settings& set = desc.settings;
  if (desc.memoryBudgetBytes == 0) return set;
  const uint32_t framesInFlight = desc.framesInFlight;
  const VkDeviceSize gatherBytes = GatherTargets::bytes(device, desc.maxWidth, desc.maxHeight, framesInFlight);
  const auto bytesOf = [&](const Settings& settings) {
    return gatherBytes + VoxelScene::bytes(settings, framesInFlight) + ProbeVolume::bytes(settings, framesInFlight) +
           ContextBufferBytes::of(desc, settings).total(framesInFlight);
  };
  const auto fits = [&](const Settings& settings) { return bytesOf(settings) <= desc.memoryBudgetBytes; };
  if (fits(set)) return set;

  // `settings` with the largest pool capacity between its floor and the set capacity that fits, if any does (the
  // bytes grow with the capacity).
  const auto withLargestPoolThatFits = [&](Settings settings) -> std::optional<Settings> {
    uint32_t smallest = brickPoolFloor(settings, set.brickPoolCapacity), largest = set.brickPoolCapacity;
    settings.brickPoolCapacity = smallest;
    if (!fits(settings)) return std::nullopt;
    while (smallest < largest) {
      settings.brickPoolCapacity = smallest + (largest - smallest + 1) / 2;
      if (fits(settings)) smallest = settings.brickPoolCapacity;
      else largest = settings.brickPoolCapacity - 1;
    }
    settings.brickPoolCapacity = smallest;
    return settings;
  };

  // 1. The pool alone.
  if (const std::optional<Settings> fitted = withLargestPoolThatFits(set)) return *fitted;

  // 2. The probe grid, a block of probes at a time on its longest axis.
  Settings smaller = set;
  const Axes gridFloor = probeGridFloor(set, set.probeGrid);
  const uint32_t gridSteps = stepsOf(set.probeGrid, shader::kProbeBlockSize);
  for (uint32_t step = gridSteps; step-- > 0;) {
    smaller.probeGrid = scaledDown(set.probeGrid, step, gridSteps, shader::kProbeBlockSize, gridFloor);
    if (const std::optional<Settings> fitted = withLargestPoolThatFits(smaller)) return *fitted;
  }

  // 3. The voxel volume, a scroll step on each side of its longest axis at a time, with the probe grid at the floor
  //    of the smaller volume.
  const uint32_t volumeMultiple = 2 * uint32_t(shader::kScrollStepBricks);
  const Axes volumeFloor{volumeMultiple, volumeMultiple, volumeMultiple};
  const uint32_t volumeSteps = stepsOf(set.volumeBricks, volumeMultiple);
  for (uint32_t step = volumeSteps; step-- > 0;) {
    smaller.volumeBricks = scaledDown(set.volumeBricks, step, volumeSteps, volumeMultiple, volumeFloor);
    smaller.probeGrid = probeGridFloor(smaller, set.probeGrid);
    if (const std::optional<Settings> fitted = withLargestPoolThatFits(smaller)) return *fitted;
  }
  smaller.brickPoolCapacity = brickPoolFloor(smaller, set.brickPoolCapacity);
  const VkDeviceSize minimum = bytesOf(smaller);
  return Error{Status::InvalidDescription,
               "ContextDesc::memoryBudgetBytes: " + std::to_string(desc.memoryBudgetBytes) + " bytes (" +
                   mebibytes(desc.memoryBudgetBytes) + ") is below the minimum of " + std::to_string(minimum) +
                   " bytes (" + mebibytes(minimum) + ") for frames of " + std::to_string(desc.maxWidth) + "×" +
                   std::to_string(desc.maxHeight) + ", whose final-gather images alone take " +
                   std::to_string(gatherBytes) + " bytes (a smaller maxWidth/maxHeight needs less)"};
}

}  // namespace ssvgi::gi
