#include "ssvgi/ssvgi.h"

namespace ssvgi {

// SPEC §4.7: the tiers differ in the voxel range, the probe budget and the rays per probe (the latter two arrive with
// the probe passes); the pool shrinks with the range.
Settings settingsForTier(QualityTier tier) {
  Settings settings;
  switch (tier) {
    case QualityTier::High:
      break;
    case QualityTier::Medium:
      settings.volumeBricks = {96, 32, 96};
      settings.brickPoolCapacity = 16384;
      break;
    case QualityTier::Low:
      settings.volumeBricks = {64, 32, 64};
      settings.brickPoolCapacity = 8192;
      break;
  }
  return settings;
}

}  // namespace ssvgi
