#pragma once
// The voxels a GI context holds, read back from its GPU state, for tests that check what was injected.
#include "gi/context_internals.h"
#include "gpu_host/transfers.h"
#include "shared/voxel_interface.h"

#include <cstring>
#include <map>
#include <tuple>
#include <vector>

namespace ssvgi::testing {

using VoxelCoordinate = std::tuple<int, int, int>;  // world voxel coordinate

// World voxel coordinate -> its Voxel, for every occupied voxel of the first `bumpCount` bricks that are live.
inline std::map<VoxelCoordinate, shader::Voxel> occupiedVoxels(const std::vector<shader::Brick>& bricks,
                                                               const std::vector<shader::Voxel>& voxels,
                                                               uint32_t bumpCount) {
  std::map<VoxelCoordinate, shader::Voxel> occupied;
  for (uint32_t b = 0; b < bumpCount; ++b) {
    const shader::Brick& brick = bricks[b];
    if (brick.live == 0u) continue;
    for (uint32_t v = 0; v < shader::kVoxelsPerBrick; ++v) {
      const uint32_t word = v < 32 ? brick.occupancy.x : brick.occupancy.y;
      if (!(word & (1u << (v & 31u)))) continue;
      const glm::ivec3 voxel = brick.coordinate * 4 + glm::ivec3(v & 3, (v >> 2) & 3, v >> 4);
      occupied[{voxel.x, voxel.y, voxel.z}] = voxels[b * shader::kVoxelsPerBrick + v];
    }
  }
  return occupied;
}

// The same, read from a context after the host has waited for its last frame.
inline std::map<VoxelCoordinate, shader::Voxel> readOccupiedVoxels(gpu::OwnedDevice& device, const Context& context) {
  const gi::VoxelScene& scene = gi::voxelSceneOf(context);
  shader::BrickPoolState pool{};
  const auto poolWords = gpu::readBufferAs<uint32_t>(device, scene.poolState());
  std::memcpy(&pool, poolWords.data(), sizeof(pool));
  return occupiedVoxels(gpu::readBufferAs<shader::Brick>(device, scene.bricks()),
                        gpu::readBufferAs<shader::Voxel>(device, scene.voxels()), pool.bumpCount);
}

}  // namespace ssvgi::testing
