#include "bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <limits>
#include <numeric>

namespace ssvgi::reference {

namespace {

// SAH cost of visiting a node relative to one ray/triangle test (Wald 2007 uses ratios around 1).
constexpr float kTraversalCost = 1.0f;
// From this depth on, nodes split at the median: each level halves the triangle count, so no leaf ends deeper than
// kMedianSplitDepth + log2(2^32) = kBvhMaxDepth levels even for adversarial geometry.
constexpr uint32_t kMedianSplitDepth = shader::kBvhMaxDepth - 32u;
// Padding of node bounds relative to their largest coordinate: ~8 float ulps.
constexpr float kBoundsPadding = 1e-6f;

struct Box {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{std::numeric_limits<float>::lowest()};

  void grow(const glm::vec3& point) {
    min = glm::min(min, point);
    max = glm::max(max, point);
  }
  void grow(const Box& box) {
    min = glm::min(min, box.min);
    max = glm::max(max, box.max);
  }
  // Half the surface area: the SAH only compares areas, so the factor 2 does not matter.
  float halfArea() const {
    const glm::vec3 size = glm::max(max - min, glm::vec3(0.0f));
    return size.x * size.y + size.y * size.z + size.z * size.x;
  }
};

struct Primitive {
  Box bounds;
  glm::vec3 centroid;
};

struct Split {
  uint32_t axis = 0;
  uint32_t bin = 0;  // triangles in bins [0, bin) go left
  float cost = std::numeric_limits<float>::max();
};

class Builder {
 public:
  explicit Builder(std::span<const shader::TraceTriangle> triangles) {
    primitives_.reserve(triangles.size());
    for (const shader::TraceTriangle& triangle : triangles) {
      const glm::vec3 vertex0(triangle.vertex0);
      Primitive primitive;
      primitive.bounds.grow(vertex0);
      primitive.bounds.grow(vertex0 + glm::vec3(triangle.edge1));
      primitive.bounds.grow(vertex0 + glm::vec3(triangle.edge2));
      primitive.centroid = 0.5f * (primitive.bounds.min + primitive.bounds.max);
      primitives_.push_back(primitive);
    }
    bvh_.triangleOrder.resize(triangles.size());
    std::iota(bvh_.triangleOrder.begin(), bvh_.triangleOrder.end(), 0u);
  }

  Bvh build() && {
    bvh_.nodes.resize(1);
    buildNode(0, 0, static_cast<uint32_t>(primitives_.size()), 0);
    return std::move(bvh_);
  }

 private:
  void buildNode(uint32_t node, uint32_t begin, uint32_t end, uint32_t depth) {
    Box bounds, centroidBounds;
    for (uint32_t i = begin; i < end; ++i) {
      const Primitive& primitive = primitives_[bvh_.triangleOrder[i]];
      bounds.grow(primitive.bounds);
      centroidBounds.grow(primitive.centroid);
    }
    bvh_.depth = std::max(bvh_.depth, depth);
    const uint32_t count = end - begin;
    const bool sahSplits = depth < kMedianSplitDepth;
    const Split split = sahSplits && count > 1 ? findSahSplit(begin, end, bounds, centroidBounds) : Split{};
    if (count <= shader::kBvhMaxLeafTriangles && (!sahSplits || split.cost >= float(count))) {
      writeNode(node, bounds, begin, count);
      return;
    }
    uint32_t middle = begin;
    if (split.cost < std::numeric_limits<float>::max()) middle = partition(begin, end, split, centroidBounds);
    if (middle == begin || middle == end) middle = splitAtMedian(begin, end, centroidBounds);

    const auto firstChild = static_cast<uint32_t>(bvh_.nodes.size());
    bvh_.nodes.resize(bvh_.nodes.size() + 2);
    writeNode(node, bounds, firstChild, 0);
    buildNode(firstChild, begin, middle, depth + 1);
    buildNode(firstChild + 1, middle, end, depth + 1);
  }

  static uint32_t binOf(const glm::vec3& centroid, const Box& centroidBounds, uint32_t axis) {
    const float extent = centroidBounds.max[axis] - centroidBounds.min[axis];
    const float position = (centroid[axis] - centroidBounds.min[axis]) * (float(kBvhSahBins) / extent);
    return std::min(kBvhSahBins - 1, static_cast<uint32_t>(position));
  }

  // The cheapest of the (kBvhSahBins - 1) planes between bins on each axis along which the centroids spread; cost
  // max() when there is none (all centroids coincide).
  Split findSahSplit(uint32_t begin, uint32_t end, const Box& bounds, const Box& centroidBounds) const {
    Split best;
    const float inverseArea = 1.0f / std::max(bounds.halfArea(), std::numeric_limits<float>::min());
    for (uint32_t axis = 0; axis < 3; ++axis) {
      if (!(centroidBounds.max[axis] > centroidBounds.min[axis])) continue;
      std::array<Box, kBvhSahBins> binBounds;
      std::array<uint32_t, kBvhSahBins> binCounts{};
      for (uint32_t i = begin; i < end; ++i) {
        const Primitive& primitive = primitives_[bvh_.triangleOrder[i]];
        const uint32_t bin = binOf(primitive.centroid, centroidBounds, axis);
        binBounds[bin].grow(primitive.bounds);
        ++binCounts[bin];
      }
      // Sweep from the right to know each plane's right side, then from the left.
      std::array<float, kBvhSahBins> rightCosts{};
      Box right;
      uint32_t rightCount = 0;
      for (uint32_t bin = kBvhSahBins - 1; bin > 0; --bin) {
        right.grow(binBounds[bin]);
        rightCount += binCounts[bin];
        rightCosts[bin] = rightCount ? float(rightCount) * right.halfArea() : 0.0f;
      }
      Box left;
      uint32_t leftCount = 0;
      for (uint32_t bin = 1; bin < kBvhSahBins; ++bin) {
        left.grow(binBounds[bin - 1]);
        leftCount += binCounts[bin - 1];
        if (leftCount == 0 || leftCount == end - begin) continue;
        const float cost = kTraversalCost + (float(leftCount) * left.halfArea() + rightCosts[bin]) * inverseArea;
        if (cost < best.cost) best = {axis, bin, cost};
      }
    }
    return best;
  }

  uint32_t partition(uint32_t begin, uint32_t end, const Split& split, const Box& centroidBounds) {
    const auto middle = std::partition(
        bvh_.triangleOrder.begin() + begin, bvh_.triangleOrder.begin() + end, [&](uint32_t triangle) {
          return binOf(primitives_[triangle].centroid, centroidBounds, split.axis) < split.bin;
        });
    return static_cast<uint32_t>(middle - bvh_.triangleOrder.begin());
  }

  // Halves the range along the centroids' longest axis (in any order when they all coincide).
  uint32_t splitAtMedian(uint32_t begin, uint32_t end, const Box& centroidBounds) {
    const glm::vec3 extent = centroidBounds.max - centroidBounds.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(bvh_.triangleOrder.begin() + begin, bvh_.triangleOrder.begin() + middle,
                     bvh_.triangleOrder.begin() + end, [&](uint32_t a, uint32_t b) {
                       return primitives_[a].centroid[axis] < primitives_[b].centroid[axis];
                     });
    return middle;
  }

  void writeNode(uint32_t node, const Box& bounds, uint32_t first, uint32_t count) {
    const glm::vec3 magnitude = glm::max(glm::abs(bounds.min), glm::abs(bounds.max));
    const float padding = kBoundsPadding * (1.0f + std::max({magnitude.x, magnitude.y, magnitude.z}));
    bvh_.nodes[node].boundsMinAndFirst = glm::vec4(bounds.min - padding, std::bit_cast<float>(first));
    bvh_.nodes[node].boundsMaxAndCount = glm::vec4(bounds.max + padding, std::bit_cast<float>(count));
  }

  std::vector<Primitive> primitives_;
  Bvh bvh_;
};

}  // namespace

Bvh buildBvh(std::span<const shader::TraceTriangle> triangles) {
  assert(!triangles.empty() && triangles.size() < std::numeric_limits<uint32_t>::max());
  return Builder(triangles).build();
}

}  // namespace ssvgi::reference
