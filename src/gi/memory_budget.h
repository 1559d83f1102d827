#pragma once
// A host-set memory budget (SPEC §6.5): the bytes a context allocates for a description, counted from the sizes its
// constructors allocate, and the settings that fit a budget.
#include "gpu/device.h"
#include "shared/gi_frame.h"
#include "ssvgi/ssvgi.h"

namespace ssvgi::gi {

// Levels of the Hi-Z pyramid for a depth of `width` × `height`: level 0 is half size, down to 1×1.
uint32_t hizLayout(uint32_t width, uint32_t height, shader::HiZLevel levels[shader::kMaxHiZLevels]);

// The buffers a context allocates beside its voxel scene, probe volume and gather targets.
struct ContextBufferBytes {
  VkDeviceSize hiz = 0;                // the pyramid of the largest view: the camera's frame or an extra view
  VkDeviceSize visibleBricks = 0;      // the list of bricks to inject
  VkDeviceSize viewConstants = 0;      // a GiFrame: per frame in flight, the camera's and one per extra view
  VkDeviceSize statsReadback = 0;      // per frame in flight
  VkDeviceSize probeListReadback = 0;  // per frame in flight
  VkDeviceSize workReadback = 0;       // per frame in flight: the WorkCounters of a frame that counts its work

  static ContextBufferBytes of(const ContextDesc& desc, const Settings& settings);
  VkDeviceSize total(uint32_t framesInFlight) const;
};

// The settings a context of `desc` runs with: desc.settings without a budget (memoryBudgetBytes 0) or where they fit
// it; otherwise desc.settings shrunk, least harmful first, until every byte the context allocates fits (the order is
// in memory_budget.cpp and docs/INTEGRATION.md). InvalidDescription, naming the budget and the minimum, when even the
// smallest do not fit.
Result<Settings> settingsWithinBudget(gpu::Device& device, const ContextDesc& desc);

}  // namespace ssvgi::gi
