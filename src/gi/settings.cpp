#include "ssvgi/ssvgi.h"

namespace ssvgi {

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

}  // namespace ssvgi
