// The path tracer's BVH on the CPU: every triangle in exactly one leaf, bounds that contain what is below them, a depth
// that fits the shaders' traversal stack, and a traversal (with the shaders' own ray tests) that finds the same
// nearest hit as testing every triangle.
#include "bvh.h"
#include "scene_geometry.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

namespace ssvgi {
namespace {

using shader::BvhNode;
using shader::TraceTriangle;

TraceTriangle makeTriangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  return {a, 0u, b - a, 0u, c - a, 0u};
}

// Small triangles of random size and orientation scattered through a 20 m cube.
std::vector<TraceTriangle> randomTriangles(uint32_t count, uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> position(-10.0f, 10.0f);
  std::uniform_real_distribution<float> offset(-1.0f, 1.0f);
  std::vector<TraceTriangle> triangles;
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 a(position(random), position(random), position(random));
    const glm::vec3 b = a + glm::vec3(offset(random), offset(random), offset(random));
    const glm::vec3 c = a + glm::vec3(offset(random), offset(random), offset(random));
    triangles.push_back(makeTriangle(a, b, c));
  }
  return triangles;
}

// A closed room (x, y, z in [-2, 2]) of axis-aligned boxes with a box and a sphere inside: shared edges, coplanar
// faces, flat (zero-thickness) bounds.
std::vector<TraceTriangle> roomTriangles() {
  renderer::MeshBuilder builder;
  builder.addBox({-2.1f, -2.1f, -2.1f}, {2.1f, -2.0f, 2.1f});
  builder.addBox({-2.1f, 2.0f, -2.1f}, {2.1f, 2.1f, 2.1f});
  builder.addBox({-2.1f, -2.0f, -2.1f}, {-2.0f, 2.0f, 2.1f});
  builder.addBox({2.0f, -2.0f, -2.1f}, {2.1f, 2.0f, 2.1f});
  builder.addBox({-2.0f, -2.0f, -2.1f}, {2.0f, 2.0f, -2.0f});
  builder.addBox({-2.0f, -2.0f, 2.0f}, {2.0f, 2.0f, 2.1f});
  builder.addBox({-0.5f, -2.0f, -0.5f}, {0.5f, -1.0f, 0.5f});
  builder.addSphere({1.0f, 0.5f, 0.0f}, 0.4f, 12, 24);
  const renderer::Mesh mesh = std::move(builder).build("room", 0);
  std::vector<TraceTriangle> triangles;
  for (size_t i = 0; i < mesh.indices.size(); i += 3)
    triangles.push_back(makeTriangle(mesh.vertices[mesh.indices[i]].position, mesh.vertices[mesh.indices[i + 1]].position,
                                     mesh.vertices[mesh.indices[i + 2]].position));
  return triangles;
}

uint32_t first(const BvhNode& node) { return std::bit_cast<uint32_t>(node.boundsMinAndFirst.w); }
uint32_t count(const BvhNode& node) { return std::bit_cast<uint32_t>(node.boundsMaxAndCount.w); }
glm::vec3 lower(const BvhNode& node) { return glm::vec3(node.boundsMinAndFirst); }
glm::vec3 upper(const BvhNode& node) { return glm::vec3(node.boundsMaxAndCount); }

bool contains(const BvhNode& node, glm::vec3 point) {
  return glm::all(glm::lessThanEqual(lower(node), point)) && glm::all(glm::lessThanEqual(point, upper(node)));
}

// Walks the tree from the root, checking structure and bounds; returns how often each leaf slot is referenced.
std::vector<uint32_t> checkTree(const reference::Bvh& bvh, std::span<const TraceTriangle> triangles) {
  std::vector<uint32_t> references(triangles.size(), 0);
  std::vector<std::pair<uint32_t, uint32_t>> pending{{0u, 0u}};  // node, depth
  uint32_t visited = 0;
  while (!pending.empty()) {
    const auto [index, depth] = pending.back();
    pending.pop_back();
    ++visited;
    EXPECT_LT(depth, shader::kBvhMaxDepth);
    const BvhNode& node = bvh.nodes.at(index);
    if (count(node) > 0) {
      EXPECT_LE(count(node), shader::kBvhMaxLeafTriangles);
      for (uint32_t slot = first(node); slot < first(node) + count(node); ++slot) {
        ++references.at(slot);
        const TraceTriangle& triangle = triangles[bvh.triangleOrder.at(slot)];
        const glm::vec3 vertex0(triangle.vertex0);
        for (const glm::vec3& corner : {vertex0, vertex0 + glm::vec3(triangle.edge1), vertex0 + glm::vec3(triangle.edge2)})
          EXPECT_TRUE(contains(node, corner)) << "leaf " << index << " does not contain its triangle " << slot;
      }
      continue;
    }
    for (uint32_t child = first(node); child < first(node) + 2; ++child) {
      EXPECT_GT(child, index) << "children come after their parent: the tree has no cycles";
      const BvhNode& childNode = bvh.nodes.at(child);
      EXPECT_TRUE(contains(node, lower(childNode)) && contains(node, upper(childNode)))
          << "node " << index << " does not contain its child " << child;
      pending.push_back({child, depth + 1});
    }
  }
  EXPECT_EQ(visited, bvh.nodes.size()) << "every node is reachable from the root";
  return references;
}

void expectValidBvh(std::span<const TraceTriangle> triangles) {
  const reference::Bvh bvh = reference::buildBvh(triangles);
  ASSERT_EQ(bvh.triangleOrder.size(), triangles.size());
  std::vector<uint32_t> seen(triangles.size(), 0);
  for (uint32_t triangle : bvh.triangleOrder) ++seen.at(triangle);
  const std::vector<uint32_t> references = checkTree(bvh, triangles);
  for (size_t i = 0; i < triangles.size(); ++i) {
    EXPECT_EQ(seen[i], 1u) << "triangle " << i << " is in the leaf order " << seen[i] << " times";
    EXPECT_EQ(references[i], 1u) << "leaf slot " << i << " is in " << references[i] << " leaves";
  }
  EXPECT_LT(bvh.depth, shader::kBvhMaxDepth);
}

TEST(Bvh, holdsEveryTriangleExactlyOnceWithBoundsContainingTheirChildren) {
  expectValidBvh(randomTriangles(5000, 1));
  expectValidBvh(roomTriangles());
  expectValidBvh(randomTriangles(1, 2));
  expectValidBvh(randomTriangles(7, 3));
}

TEST(Bvh, staysWithinTheTraversalStackForDegenerateGeometry) {
  // All centroids equal: no SAH plane separates anything, the build must still split down to small leaves.
  std::vector<TraceTriangle> coincident(1000, makeTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  expectValidBvh(coincident);
  // Triangles of exponentially growing size and spacing: a split can separate only the largest few, so the tree is
  // as deep as a tree over them can get (28 levels for these, whatever the float range allows).
  std::vector<TraceTriangle> spread;
  for (int i = 0; i < 126; ++i) {
    const float x = std::ldexp(1.0f, i);
    spread.push_back(makeTriangle({x, 0, 0}, {x, 0.01f * x, 0}, {x, 0, 0.01f * x}));
  }
  expectValidBvh(spread);
}

struct Hit {
  float distance = std::numeric_limits<float>::max();
  uint32_t slot = ~0u;
};

// The nearest hit by testing every triangle (slots in leaf order, as the GPU stores them).
Hit bruteForce(std::span<const TraceTriangle> ordered, glm::vec3 origin, glm::vec3 direction) {
  Hit nearest;
  for (uint32_t slot = 0; slot < ordered.size(); ++slot) {
    const TraceTriangle& t = ordered[slot];
    const glm::vec3 tuv = shader::intersectTriangle(origin, direction, t.vertex0, t.edge1, t.edge2);
    if (tuv.x > 0.0f && tuv.x < nearest.distance) nearest = {tuv.x, slot};
  }
  return nearest;
}

// The nearest hit through the BVH: the shaders' traversal order (nearer child first, skip subtrees entered beyond
// the nearest hit so far) with the shared ray/box and ray/triangle tests.
Hit traverse(const reference::Bvh& bvh, std::span<const TraceTriangle> ordered, glm::vec3 origin, glm::vec3 direction) {
  Hit nearest;
  const glm::vec3 inverseDirection = shader::safeInverseDirection(direction);
  auto entry = [&](uint32_t index) {
    const glm::vec2 span = shader::intersectBounds(origin, inverseDirection, lower(bvh.nodes[index]), upper(bvh.nodes[index]));
    return span.x <= span.y && span.y >= 0.0f ? span.x : std::numeric_limits<float>::infinity();
  };
  std::vector<std::pair<uint32_t, float>> stack;
  if (entry(0) < nearest.distance) stack.push_back({0u, entry(0)});
  while (!stack.empty()) {
    const auto [index, enter] = stack.back();
    stack.pop_back();
    if (enter >= nearest.distance) continue;
    const BvhNode& node = bvh.nodes[index];
    if (count(node) > 0) {
      for (uint32_t slot = first(node); slot < first(node) + count(node); ++slot) {
        const TraceTriangle& t = ordered[slot];
        const glm::vec3 tuv = shader::intersectTriangle(origin, direction, t.vertex0, t.edge1, t.edge2);
        if (tuv.x > 0.0f && tuv.x < nearest.distance) nearest = {tuv.x, slot};
      }
      continue;
    }
    const float left = entry(first(node));
    const float right = entry(first(node) + 1);
    if (left <= right) {  // pushed last is popped first: the nearer child
      stack.push_back({first(node) + 1, right});
      stack.push_back({first(node), left});
    } else {
      stack.push_back({first(node), left});
      stack.push_back({first(node) + 1, right});
    }
  }
  return nearest;
}

void expectTraversalMatchesBruteForce(const std::vector<TraceTriangle>& triangles, float originSpread, uint32_t seed) {
  const reference::Bvh bvh = reference::buildBvh(triangles);
  std::vector<TraceTriangle> ordered;
  for (uint32_t index : bvh.triangleOrder) ordered.push_back(triangles[index]);
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> coordinate(-originSpread, originSpread);
  std::normal_distribution<float> gaussian;
  uint32_t hits = 0;
  for (int ray = 0; ray < 4000; ++ray) {
    const glm::vec3 origin(coordinate(random), coordinate(random), coordinate(random));
    glm::vec3 direction(gaussian(random), gaussian(random), gaussian(random));
    if (ray % 10 == 0) {  // axis-aligned: zero direction components, and rays in the planes of flat bounds
      direction = glm::vec3(0.0f);
      direction[ray % 3] = ray % 20 == 0 ? 1.0f : -1.0f;
    }
    direction = glm::normalize(direction);
    const Hit expected = bruteForce(ordered, origin, direction);
    const Hit found = traverse(bvh, ordered, origin, direction);
    ASSERT_EQ(found.slot, expected.slot) << "ray " << ray;
    ASSERT_EQ(found.distance, expected.distance) << "ray " << ray;
    hits += expected.slot != ~0u;
  }
  EXPECT_GT(hits, 1000u) << "the rays must hit often for the comparison to mean something";
}

TEST(Bvh, traversalFindsTheSameNearestHitAsTestingEveryTriangle) {
  expectTraversalMatchesBruteForce(randomTriangles(3000, 4), 12.0f, 5);
  // From inside a closed room, every ray hits; axis-aligned rays meet the flat bounds of axis-aligned walls.
  expectTraversalMatchesBruteForce(roomTriangles(), 1.5f, 6);
}

}  // namespace
}  // namespace ssvgi
