#include "ssvgi/ssvgi.h"

#include "shared/probe_interface.h"
#include "shared/voxel_interface.h"

namespace ssvgi {

namespace {
constexpr double kUnlimited = std::numeric_limits<double>::infinity();
constexpr double kSmallestLength = 0.001;  // m
}  // namespace

// SPEC §4.7: the tiers differ in the voxel range, the probe budget and the rays per probe; the pool shrinks with the
// range. Medium and low keep 32×16×32 probes per level (level 0 then covers 32×16×32 m, level 2 128×64×128 m, past
// their voxel ranges, as high's does). Low traces 16 rays per update, so its history cap doubles to keep a window of
// all 1024 directions. Level 0's reservoirs (SPEC §4.5 "Stability") are off in every tier,
// for their lag (ssvgi.h); low's M cap is set for when they are on.
Settings settingsForTier(QualityTier tier) {
  Settings settings;
  switch (tier) {
    case QualityTier::High:
      break;
    case QualityTier::Medium:
      settings.volumeBricks = {96, 32, 96};
      settings.brickPoolCapacity = 8192;
      settings.probeGrid = {32, 16, 32};
      settings.probeBudget = 2048;
      settings.probeBlocksBeyondView = 16;
      break;
    case QualityTier::Low:
      settings.volumeBricks = {64, 32, 64};
      settings.brickPoolCapacity = 4096;
      settings.probeGrid = {32, 16, 32};
      settings.probeBudget = 1024;
      settings.probeBlocksBeyondView = 8;
      settings.raysPerProbe = 16;
      settings.probeHistoryCap = 64;
      settings.probeReservoirHistoryCap = 16;  // 1 new candidate per stratum and update: the same 16 updates
      break;
  }
  return settings;
}

std::span<const SettingInfo> settingInfos() {
  // Why each range: a voxel or a probe spacing under a millimetre would overflow the 32-bit voxel and probe
  // coordinates of a view 10^6 m from the origin, the farthest FrameDesc allows (Context::create also refuses volumes
  // wider than that span); the volume re-centres in steps of kScrollStepBricks and keeps the camera at a whole step
  // from its middle (multiples of twice that); the seen-through counter has 6 bits; the CPU culls probes in blocks of
  // 4 and packs a block coordinate in 10 bits (1024 blocks); a power of two up to the workgroup divides the 1024
  // directions into whole slices; m has 8 bits; a reservoir's M has 8 bits and grows by up to 3 candidates past its cap
  // in an update; a relight period past 64 frames would leave voxels stale for seconds.
  static const SettingInfo infos[] = {
      {"voxelSize", &Settings::voxelSize, kSmallestLength},
      {"volumeBricks", &Settings::volumeBricks, 1.0, kUnlimited, false, 2 * uint32_t(shader::kScrollStepBricks)},
      {"brickPoolCapacity", &Settings::brickPoolCapacity, 1.0},
      {"invalidFramesToClear", &Settings::invalidFramesToClear, 1.0, double(shader::kVoxelMaxLastHit)},
      {"emptyFramesToRelease", &Settings::emptyFramesToRelease, 1.0},
      {"allocationPixelStride", &Settings::allocationPixelStride, 1.0},
      {"occlusionCulling", &Settings::occlusionCulling},
      {"probeGrid", &Settings::probeGrid, double(shader::kProbeBlockSize), 1024.0 * shader::kProbeBlockSize, false,
       shader::kProbeBlockSize},
      {"probeSpacing", &Settings::probeSpacing, kSmallestLength},
      {"probeBudget", &Settings::probeBudget, 1.0},
      {"probeBlocksBeyondView", &Settings::probeBlocksBeyondView},
      {"raysPerProbe", &Settings::raysPerProbe, 1.0, double(shader::kProbeTraceGroupSize), false, 1, true},
      {"probeHistoryCap", &Settings::probeHistoryCap, 1.0, 255.0},
      {"probeReservoirs", &Settings::probeReservoirs},
      {"probeReservoirHistoryCap", &Settings::probeReservoirHistoryCap, 1.0, 252.0},
      {"probeSampleClamp", &Settings::probeSampleClamp, 1.0, kUnlimited, false, 1, false, true},
      {"probeChangeThreshold", &Settings::probeChangeThreshold},
      {"probeSharedChangeShare", &Settings::probeSharedChangeShare, 0.0, 1.0},
      {"settledProbeInterval", &Settings::settledProbeInterval, 1.0, 8.0},
      {"skyOnlyThroughObservedSpace", &Settings::skyOnlyThroughObservedSpace},
      {"voxelRelightPeriod", &Settings::voxelRelightPeriod, 1.0, 64.0},
  };
  return infos;
}

}  // namespace ssvgi
