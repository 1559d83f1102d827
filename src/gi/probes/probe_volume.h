#pragma once
// The GPU resources of the probe radiance cache (SPEC §4.5) and each frame's choice of what to update: the level
// (round-robin), its placement around the camera and the CPU's coarse frustum cull of its blocks.
#include "gpu/pipelines.h"
#include "shared/probe_interface.h"
#include "ssvgi/ssvgi.h"

#include <glm/glm.hpp>

#include <array>
#include <span>
#include <vector>

namespace ssvgi::gi {

// The blocks of kProbeBlockSize³ probes ProbeVolume::prepare offers the placement: those in view, then as many
// beyond it, in that order in ProbeVolume::offeredBlocks().
struct OfferedProbeBlocks {
  uint32_t inView = 0;
  uint32_t beyondView = 0;
};

// The watched probes' leaning pooled over frames' tallies (shared/probe_interface.h, "A drift many probes share"): its
// mean and standard error, and the mean direct share of their light; all 0 where fewer than
// kProbeSharedChangeMinimumProbes leaned.
struct ProbeLeaning {
  double mean = 0.0;
  double standardError = 0.0;
  double directShare = 0.0;
  // The share by which the probes' histories fall short of where the loop leads them, 2·lean / direct share (infinite
  // where a lean toward more light has no direct light to come from: all of it comes round the loop).
  double gap() const;
};
ProbeLeaning probeLeaning(std::span<const shader::ProbeChangeTally> tallies);
// Whether a leaning shows light coming round the loop: toward more light by more than kProbeSharedDriftErrors standard
// errors — kProbeSharedDriftHoldErrors where the frame before `followed` a drift already — and a gap above
// kProbeSharedDriftGapFloor.
bool showsSharedDrift(const ProbeLeaning& leaning, bool followed = false);
// The history cap a shared drift holds the probes at: about 1/gap updates, between kProbeSharedDriftShortestHistoryCap
// and kProbeSharedDriftHistoryCap.
uint32_t sharedDriftHistoryCap(const ProbeLeaning& leaning);

class ProbeVolume {
 public:
  ProbeVolume(gpu::Device& device, const Settings& settings, uint32_t framesInFlight);
  // The bytes the constructor allocates for these arguments, without allocating them (the memory budget's count).
  static VkDeviceSize bytes(const Settings& settings, uint32_t framesInFlight);

  // Prepares this frame's update and uploads its ProbeUpdate and block list: level frameIndex % kProbeLevels, centred
  // on the camera, its blocks of kProbeBlockSize³ probes whose ranges reach into the frustum (planes pointing inwards,
  // as GiFrame's), then the next Settings::probeBlocksBeyondView of the others in turn, the sky, and rays traced as far
  // as the voxel volume reaches (`hasSkyMap`: rays that leave it see the host's sky map). Reads back the change tally
  // of the frame that last used this frame's slot (the host has waited for it) and starts a recovery in every probe
  // where many probes saw a change at once, or holds the history short where many lean toward more light.
  OfferedProbeBlocks prepare(uint32_t frameIndex, glm::vec3 cameraPosition, const glm::vec4 frustumPlanes[6],
                   const std::array<float, 12>& skyRadianceSh, bool hasSkyMap, const shader::VoxelVolume& voxels);

  const gpu::Buffer& probes() const { return probes_; }  // Probe[kProbeLevels · probes per level], level-major
  const gpu::Buffer& list() const { return list_; }      // IndirectList of probe indices, then the indices
  // kProbeStrata reservoirs per probe of level 0 (Settings::probeReservoirs; one word when off: nothing reads it).
  const gpu::Buffer& reservoirs() const { return reservoirs_; }
  // Per probe, how far its updates usually stray from its history (shared/probe_interface.h, "Less lag").
  const gpu::Buffer& changes() const { return changes_; }
  // This frame's ProbeChangeTally, which ProbeTrace counts into, and the host copy of it that this frame's slot keeps
  // until prepare() reads it framesInFlight frames later.
  const gpu::Buffer& changeTally() const { return changeTally_; }
  const gpu::Buffer& changeTallyReadback() const { return tallyReadbacks_[currentFrame_]; }
  // The tally prepare() last read back (of the frame framesInFlight before its own): for Stats.
  const shader::ProbeChangeTally& lastTally() const { return lastTally_; }
  // The leaning of the tallies read back since the last drift followed (at most kProbeSharedDriftWindow), pooled: what
  // prepare() tells a drift many probes share by.
  const ProbeLeaning& leaning() const { return leaning_; }
  // Whether this frame's update holds the history short for a drift many probes share.
  bool followsSharedDrift() const { return followsSharedDrift_; }
  const gpu::Buffer& update() const { return updates_[currentFrame_]; }  // this frame's ProbeUpdate
  // `bindings` plus what a pass over the listed probes binds: this frame's update, the probes, the list.
  gpu::Bindings listedProbeBindings(gpu::Bindings bindings) const {
    return bindings.buffer(shader::kBindProbeUpdate, update())
        .buffer(shader::kBindProbes, probes())
        .buffer(shader::kBindProbeList, list());
  }
  const gpu::Buffer& offeredBlocks() const { return blocks_[currentFrame_]; }
  const shader::ProbeUpdate& current() const { return current_; }
  uint32_t probesPerLevel() const;
  // Where a level stands for a camera: every level is centred on it (SPEC §4.5).
  float levelSpacing(uint32_t level) const;
  glm::ivec3 levelOrigin(uint32_t level, glm::vec3 cameraPosition) const;  // world probe coordinate of its min corner

 private:
  struct BufferBytes;
  static BufferBytes bufferBytes(const Settings& settings);
  ProbeVolume(gpu::Device& device, const Settings& settings, uint32_t framesInFlight, const BufferBytes& bytes);
  Settings settings_;
  gpu::Buffer probes_;
  gpu::Buffer list_;
  gpu::Buffer reservoirs_;
  gpu::Buffer changes_;
  std::vector<gpu::Buffer> updates_;
  std::vector<gpu::Buffer> blocks_;
  gpu::Buffer changeTally_;
  std::vector<gpu::Buffer> tallyReadbacks_;
  shader::ProbeChangeTally lastTally_{};
  uint32_t sharedRecoveryFramesLeft_ = 0;  // frames to come that start a recovery in every probe they update
  std::vector<shader::ProbeChangeTally> driftWindow_;  // the last kProbeSharedDriftWindow tallies read back
  ProbeLeaning leaning_;
  uint32_t sharedDriftHistoryCap_ = shader::kProbeSharedDriftHistoryCap;  // the cap it holds them at
  bool followsSharedDrift_ = false;
  size_t currentFrame_ = 0;
  // Per level, where the turn of the blocks beyond the view stands (an index into those beyond it, in grid order).
  std::array<uint32_t, shader::kProbeLevels> beyondViewTurn_{};
  shader::ProbeUpdate current_{};
};

}  // namespace ssvgi::gi
