#include "scene_geometry.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <cassert>
#include <cmath>
#include <utility>

namespace ssvgi::renderer {

namespace {

// The unit cube's faces as corner triples (0 → −0.5, 1 → +0.5 on x, y, z), counter-clockwise seen from outside.
using CubeCorner = std::array<float, 3>;
constexpr std::array<std::array<CubeCorner, 4>, 6> kCubeFaces = {{
    {{{1, 0, 1}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}}},  // +X
    {{{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}},  // −X
    {{{0, 1, 1}, {1, 1, 1}, {1, 1, 0}, {0, 1, 0}}},  // +Y
    {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}},  // −Y
    {{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},  // +Z
    {{{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}}},  // −Z
}};

// A point on a circle about +Y: angle 0 lies on +Z, a quarter turn on +X. Faces between increasing angles, listed
// bottom-then-top, are then counter-clockwise seen from outside.
glm::vec3 onCircle(float radius, float angle) { return {radius * std::sin(angle), 0.0f, radius * std::cos(angle)}; }

}  // namespace

void MeshBuilder::addBox(const glm::mat4& placement) {
  // A mirroring placement would turn the faces inside out.
  assert(glm::determinant(glm::mat3(placement)) > 0.0f);
  for (const auto& face : kCubeFaces) {
    std::array<glm::vec3, 4> corners;
    for (size_t i = 0; i < 4; ++i) {
      const glm::vec3 local = glm::vec3(face[i][0], face[i][1], face[i][2]) - 0.5f;
      corners[i] = glm::vec3(placement * glm::vec4(local, 1.0f));
    }
    addQuad(corners[0], corners[1], corners[2], corners[3]);
  }
}

void MeshBuilder::addBox(const glm::vec3& minCorner, const glm::vec3& maxCorner) {
  addBox(0.5f * (minCorner + maxCorner), maxCorner - minCorner, 0.0f);
}

void MeshBuilder::addBox(const glm::vec3& center, const glm::vec3& size, float yawRadians) {
  const glm::mat4 placed =
      glm::translate(glm::mat4(1.0f), center) * glm::rotate(glm::mat4(1.0f), yawRadians, glm::vec3(0.0f, 1.0f, 0.0f));
  addBox(glm::scale(placed, size));
}

void MeshBuilder::addCylinder(const glm::vec3& baseCenter, float radius, float height, uint32_t segments) {
  assert(segments >= 3);
  const glm::vec3 top = baseCenter + glm::vec3(0.0f, height, 0.0f);
  for (uint32_t i = 0; i < segments; ++i) {
    const float angle0 = glm::two_pi<float>() * static_cast<float>(i) / static_cast<float>(segments);
    const float angle1 = glm::two_pi<float>() * static_cast<float>(i + 1) / static_cast<float>(segments);
    const glm::vec3 rim0 = onCircle(radius, angle0);
    const glm::vec3 rim1 = onCircle(radius, angle1);
    addQuad(baseCenter + rim0, baseCenter + rim1, top + rim1, top + rim0);
    addTriangle(top, top + rim0, top + rim1);
    addTriangle(baseCenter, baseCenter + rim1, baseCenter + rim0);
  }
}

void MeshBuilder::addSphere(const glm::vec3& center, float radius, uint32_t rings, uint32_t segments) {
  assert(rings >= 2 && segments >= 3);
  // Polar angle from +Y: ring r spans [polar(r), polar(r + 1)], the first and last rings end in a pole.
  const auto point = [&](uint32_t ring, uint32_t segment) {
    const float polar = glm::pi<float>() * static_cast<float>(ring) / static_cast<float>(rings);
    const float azimuth = glm::two_pi<float>() * static_cast<float>(segment) / static_cast<float>(segments);
    return center + std::sin(polar) * onCircle(radius, azimuth) + glm::vec3(0.0f, radius * std::cos(polar), 0.0f);
  };
  for (uint32_t ring = 0; ring < rings; ++ring) {
    for (uint32_t segment = 0; segment < segments; ++segment) {
      const glm::vec3 upper0 = point(ring, segment);
      const glm::vec3 upper1 = point(ring, segment + 1);
      const glm::vec3 lower0 = point(ring + 1, segment);
      const glm::vec3 lower1 = point(ring + 1, segment + 1);
      if (ring == 0) {
        addTriangle(lower0, lower1, upper0);
      } else if (ring + 1 == rings) {
        addTriangle(lower0, upper1, upper0);
      } else {
        addQuad(lower0, lower1, upper1, upper0);
      }
    }
  }
}

Mesh MeshBuilder::build(std::string name, uint32_t material) && {
  mesh_.name = std::move(name);
  mesh_.material = material;
  return std::move(mesh_);
}

void MeshBuilder::addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  // The diagonals' cross product is the normal of a planar quad, whatever its corner angles.
  const glm::vec3 normal = glm::normalize(glm::cross(c - a, d - b));
  const auto first = static_cast<uint32_t>(mesh_.vertices.size());
  mesh_.vertices.push_back({a, normal, {0.0f, 0.0f}});
  mesh_.vertices.push_back({b, normal, {1.0f, 0.0f}});
  mesh_.vertices.push_back({c, normal, {1.0f, 1.0f}});
  mesh_.vertices.push_back({d, normal, {0.0f, 1.0f}});
  mesh_.indices.insert(mesh_.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
}

void MeshBuilder::addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
  const auto first = static_cast<uint32_t>(mesh_.vertices.size());
  mesh_.vertices.push_back({a, normal, {0.0f, 0.0f}});
  mesh_.vertices.push_back({b, normal, {1.0f, 0.0f}});
  mesh_.vertices.push_back({c, normal, {0.0f, 1.0f}});
  mesh_.indices.insert(mesh_.indices.end(), {first, first + 1, first + 2});
}

}  // namespace ssvgi::renderer
