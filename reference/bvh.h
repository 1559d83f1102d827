#pragma once
// The reference path tracer's bounding volume hierarchy over world-space triangles, built on the CPU and traversed in
// the shaders (shaders/reference/scene_tracing.glsl).
#include "shared/path_tracer_interface.h"

#include <cstdint>
#include <span>
#include <vector>

namespace ssvgi::reference {

struct Bvh {
  // Flat node array in the layout of shader::BvhNode; nodes[0] is the root, an inner node's children are adjacent.
  std::vector<shader::BvhNode> nodes;
  // The triangles in leaf order: a leaf's triangles [first, first + count) are input triangles triangleOrder[first..].
  // The path tracer stores its triangles in this order, so leaves need no index indirection.
  std::vector<uint32_t> triangleOrder;
  uint32_t depth = 0;  // levels below the root, at most shader::kBvhMaxDepth - 1
};

// Candidate split planes per axis of the binned SAH build. Wald ("On fast Construction of SAH-based Bounding Volume
// Hierarchies", 2007) finds 16 bins within a few percent of the full sweep's tree quality.
inline constexpr uint32_t kBvhSahBins = 16;

// Builds a BVH over `triangles` (at least one) with the surface area heuristic, binned on all three axes: a node is
// split where the expected cost of tracing a random ray through it is lowest, and becomes a leaf when it holds at
// most shader::kBvhMaxLeafTriangles triangles and no split is cheaper than testing them all. Below a fixed depth the
// build falls back to median splits, so the tree never outgrows the shaders' traversal stack (kBvhMaxDepth).
// Node bounds are padded by a few float ulps, so that rounding in the ray/box test never loses a hit at an edge.
Bvh buildBvh(std::span<const shader::TraceTriangle> triangles);

}  // namespace ssvgi::reference
