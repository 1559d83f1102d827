#pragma once
// Closed solids (boxes, cylinders, spheres) accumulated into one triangle mesh, for the scenes generated in code.
// Every face has its own vertices with the flat face normal, pointing out of the solid, and counter-clockwise winding
// seen from outside, so that walls built from boxes have real thickness and a back face is never visible from outside.
#include "scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>

namespace ssvgi::renderer {

class MeshBuilder {
 public:
  // The unit cube [-0.5, 0.5]³ placed by `placement` (any affine map with a positive determinant: scale, rotation,
  // translation). The one box primitive every scene uses.
  void addBox(const glm::mat4& placement);
  // Axis-aligned box between two corners.
  void addBox(const glm::vec3& minCorner, const glm::vec3& maxCorner);
  // Box of `size` centred at `center`, turned by `yawRadians` about +Y (counter-clockwise seen from above).
  void addBox(const glm::vec3& center, const glm::vec3& size, float yawRadians);

  // Closed upright cylinder with a flat-shaded side of `segments` faces.
  void addCylinder(const glm::vec3& baseCenter, float radius, float height, uint32_t segments);
  // Closed flat-shaded sphere of `rings` latitude bands and `segments` longitude bands.
  void addSphere(const glm::vec3& center, float radius, uint32_t rings, uint32_t segments);

  bool empty() const { return mesh_.indices.empty(); }
  // Hands over the accumulated triangles as a mesh with the given name and material.
  Mesh build(std::string name, uint32_t material) &&;

 private:
  // Planar convex quad, corners counter-clockwise seen from the side its normal points to.
  void addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);
  void addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

  Mesh mesh_;
};

}  // namespace ssvgi::renderer
