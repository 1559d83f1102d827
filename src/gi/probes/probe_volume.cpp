#include "probe_volume.h"

#include "shared/gi_frame.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ssvgi::gi {

namespace {

glm::uvec3 gridOf(const Settings& settings) {
  return glm::uvec3(settings.probeGrid[0], settings.probeGrid[1], settings.probeGrid[2]);
}

}  // namespace

ProbeLeaning probeLeaning(std::span<const shader::ProbeChangeTally> tallies) {
  double probes = 0.0, sum = 0.0, squares = 0.0, directShares = 0.0;
  for (const shader::ProbeChangeTally& tally : tallies) {
    probes += double(tally.leaningProbes);
    sum += double(tally.leaningSum);
    squares += double(tally.leaningSquares);
    directShares += double(tally.directShareSum);
  }
  if (probes < shader::kProbeSharedChangeMinimumProbes) return {};
  const double scale = shader::kProbeLeaningScale * probes;
  const double mean = sum / scale, meanSquare = squares / scale;
  return {mean, std::sqrt(std::max(meanSquare - mean * mean, 0.0) / probes), directShares / scale};
}

double ProbeLeaning::gap() const {
  if (directShare > 0.0) return 2.0 * mean / directShare;
  return mean > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
}

bool showsSharedDrift(const ProbeLeaning& leaning, bool followed) {
  const double errors = followed ? shader::kProbeSharedDriftHoldErrors : shader::kProbeSharedDriftErrors;
  return leaning.mean > errors * leaning.standardError &&
         leaning.gap() > shader::kProbeSharedDriftGapFloor;
}

uint32_t sharedDriftHistoryCap(const ProbeLeaning& leaning) {
  return uint32_t(std::clamp(std::round(1.0 / leaning.gap()), double(shader::kProbeSharedDriftShortestHistoryCap),
                             double(shader::kProbeSharedDriftHistoryCap)));
}

// The bytes of each buffer of a volume of `settings`: what the constructor allocates and bytes() counts.
struct ProbeVolume::BufferBytes {
  VkDeviceSize probes, list, reservoirs, changes, update, offeredBlocks, changeTally;
};

ProbeVolume::BufferBytes ProbeVolume::bufferBytes(const Settings& settings) {
  const VkDeviceSize perLevel = VkDeviceSize(settings.probeGrid[0]) * settings.probeGrid[1] * settings.probeGrid[2];
  const glm::uvec3 blocks = gridOf(settings) / shader::kProbeBlockSize;
  return {shader::kProbeLevels * perLevel * sizeof(shader::Probe),
          sizeof(shader::IndirectList) + VkDeviceSize(settings.probeBudget) * 4,
          // Level 0 only: its probes come first in the probe buffer, so a probe's index is its reservoirs' too.
          settings.probeReservoirs ? perLevel * shader::kProbeStrata * sizeof(uint32_t) : sizeof(uint32_t),
          shader::kProbeLevels * perLevel * sizeof(uint32_t),
          sizeof(shader::ProbeUpdate),
          VkDeviceSize(blocks.x) * blocks.y * blocks.z * 4,
          sizeof(shader::ProbeChangeTally)};
}

ProbeVolume::ProbeVolume(gpu::Device& device, const Settings& settings, uint32_t framesInFlight)
    : ProbeVolume(device, settings, framesInFlight, bufferBytes(settings)) {}

ProbeVolume::ProbeVolume(gpu::Device& device, const Settings& settings, uint32_t framesInFlight,
                         const BufferBytes& bytes)
    : settings_(settings),
      probes_(device, "ssvgi probe volume", bytes.probes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      list_(device, "ssvgi probe list", bytes.list,
            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT),
      reservoirs_(device, "ssvgi probe reservoirs", bytes.reservoirs, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      changes_(device, "ssvgi probe change statistics", bytes.changes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      changeTally_(device, "ssvgi probe change tally", bytes.changeTally, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) {
  for (uint32_t i = 0; i < framesInFlight; ++i) {
    tallyReadbacks_.emplace_back(device, "ssvgi probe change tally readback", bytes.changeTally,
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::HostReadback);
    std::memset(tallyReadbacks_.back().mapped(), 0, bytes.changeTally);  // no frame has counted into it yet
    updates_.emplace_back(device, "ssvgi probe update", bytes.update, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          gpu::MemoryUsage::HostUpload);
    blocks_.emplace_back(device, "ssvgi probe blocks offered", bytes.offeredBlocks, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                         gpu::MemoryUsage::HostUpload);
  }
}

VkDeviceSize ProbeVolume::bytes(const Settings& settings, uint32_t framesInFlight) {
  const BufferBytes bytes = bufferBytes(settings);
  return bytes.probes + bytes.list + bytes.reservoirs + bytes.changes + bytes.changeTally +
         framesInFlight * (bytes.update + bytes.offeredBlocks + bytes.changeTally);
}

uint32_t ProbeVolume::probesPerLevel() const {
  return settings_.probeGrid[0] * settings_.probeGrid[1] * settings_.probeGrid[2];
}

float ProbeVolume::levelSpacing(uint32_t level) const { return settings_.probeSpacing * float(1u << level); }

glm::ivec3 ProbeVolume::levelOrigin(uint32_t level, glm::vec3 cameraPosition) const {
  return glm::ivec3(glm::floor(cameraPosition / levelSpacing(level))) - glm::ivec3(gridOf(settings_)) / 2;
}

OfferedProbeBlocks ProbeVolume::prepare(uint32_t frameIndex, glm::vec3 cameraPosition, const glm::vec4 frustumPlanes[6],
                              const std::array<float, 12>& skyRadianceSh, bool hasSkyMap,
                              const shader::VoxelVolume& voxels) {
  const uint32_t level = frameIndex % shader::kProbeLevels;
  const float spacing = levelSpacing(level);
  const glm::ivec3 dimensions(gridOf(settings_));
  const glm::ivec3 origin = levelOrigin(level, cameraPosition);
  // Rays go as far as the voxel volume reaches (its diagonal; the trace stops at its boundary anyway): a far wall
  // still hides the sky, and empty space costs a read per cell of up to 16 m.
  const float maxTraceDistance = glm::length(glm::vec3(voxels.dimensionsBricks) * voxels.brickSize);
  // The search level of ProbePlacement: the coarsest occupancy grid level whose cells are no wider than the spacing.
  const int searchLevel =
      std::clamp(int(std::floor(std::log2(spacing / voxels.voxelSize))), int(shader::kFirstGridLevel),
                 int(shader::kFirstLocalGridLevel) - 1);

  current_.originProbe = origin;
  current_.level = int(level);
  current_.probesPerAxis = dimensions;
  current_.probesPerLevel = int(probesPerLevel());
  current_.spacing = spacing;
  current_.rayLength = maxTraceDistance;
  current_.distanceRange = shader::kProbeDistanceRangeSpacings * spacing;
  current_.projectionWeight = 4.0f * shader::kPi / float(settings_.raysPerProbe);
  current_.raysPerProbe = settings_.raysPerProbe;
  current_.probeBudget = settings_.probeBudget;
  current_.placementSearchLevel = uint32_t(searchLevel);
  current_.keepsReservoirs = settings_.probeReservoirs && level == 0 ? 1u : 0u;
  current_.reservoirHistoryCap = settings_.probeReservoirHistoryCap;
  current_.frameIndex = frameIndex;
  current_.sampleClamp = settings_.probeSampleClamp;
  current_.changeThreshold = settings_.probeChangeThreshold;
  currentFrame_ = frameIndex % updates_.size();
  std::memcpy(&lastTally_, tallyReadbacks_[currentFrame_].mapped(), sizeof(lastTally_));
  const float sharedShare = settings_.probeSharedChangeShare;
  if (sharedShare > 0.0f && lastTally_.watchedProbes >= shader::kProbeSharedChangeMinimumProbes &&
      float(lastTally_.cutProbes) >= sharedShare * float(lastTally_.watchedProbes))
    sharedRecoveryFramesLeft_ = shader::kProbeLevels;
  current_.startsSharedRecovery = sharedRecoveryFramesLeft_ > 0 ? 1u : 0u;
  if (sharedRecoveryFramesLeft_ > 0) --sharedRecoveryFramesLeft_;
  // A drift is told from at least a round of tallies (an update of each level) and at most kProbeSharedDriftWindow,
  // the window sliding on while it is followed: the probes of a small scene are too few for each window to tell
  // their lean afresh by kProbeSharedDriftErrors standard errors.
  if (driftWindow_.size() == shader::kProbeSharedDriftWindow) driftWindow_.erase(driftWindow_.begin());
  driftWindow_.push_back(lastTally_);
  leaning_ = probeLeaning(driftWindow_);
  if (sharedShare > 0.0f && driftWindow_.size() >= shader::kProbeLevels) {
    followsSharedDrift_ = showsSharedDrift(leaning_, followsSharedDrift_);
    if (followsSharedDrift_) sharedDriftHistoryCap_ = sharedDriftHistoryCap(leaning_);
  }
  current_.historyCap = followsSharedDrift_ ? std::min(settings_.probeHistoryCap, sharedDriftHistoryCap_)
                                            : settings_.probeHistoryCap;
  current_.settledProbeInterval = followsSharedDrift_ ? 1u : settings_.settledProbeInterval;
  std::memcpy(&current_.skyRadiance, skyRadianceSh.data(), sizeof(current_.skyRadiance));
  current_.hasSkyMap = hasSkyMap ? 1u : 0u;

  // SPEC §4.5: "the CPU culls the level's volume against the frustum coarsely" — per block, the union of its probes'
  // ranges (one spacing around each).
  std::memcpy(updates_[currentFrame_].mapped(), &current_, sizeof(current_));
  auto* offered = static_cast<uint32_t*>(blocks_[currentFrame_].mapped());
  const glm::uvec3 blocks = gridOf(settings_) / shader::kProbeBlockSize;
  std::vector<uint32_t> beyondView;
  OfferedProbeBlocks count;
  for (uint32_t z = 0; z < blocks.z; ++z)
    for (uint32_t y = 0; y < blocks.y; ++y)
      for (uint32_t x = 0; x < blocks.x; ++x) {
        const glm::ivec3 firstProbe = origin + glm::ivec3(glm::uvec3(x, y, z) * shader::kProbeBlockSize);
        const glm::vec3 lo = glm::vec3(firstProbe - 1) * spacing;
        const glm::vec3 hi = glm::vec3(firstProbe + int(shader::kProbeBlockSize)) * spacing;
        const uint32_t block = shader::packProbeBlock(glm::uvec3(x, y, z));
        if (shader::boxInFrustum(lo, hi, frustumPlanes)) offered[count.inView++] = block;
        else beyondView.push_back(block);
      }
  // Those beyond the view take turns: the next probeBlocksBeyondView of them, after the last level update's.
  count.beyondView = std::min(settings_.probeBlocksBeyondView, uint32_t(beyondView.size()));
  uint32_t& turn = beyondViewTurn_[level];
  for (uint32_t i = 0; i < count.beyondView; ++i)
    offered[count.inView + i] = beyondView[(turn + i) % beyondView.size()];
  if (!beyondView.empty()) turn = (turn + count.beyondView) % uint32_t(beyondView.size());
  return count;
}

}  // namespace ssvgi::gi
