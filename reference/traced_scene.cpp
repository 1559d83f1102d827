#include "traced_scene.h"

#include "bvh.h"
#include "gpu_host/transfers.h"
#include "gpu_scene.h"
#include "renderer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <span>
#include <vector>

namespace ssvgi::reference {

namespace {

// The scene's triangles in world space, every instance flattened, in the order of the BVH's leaves.
struct SceneTriangles {
  std::vector<shader::TraceTriangle> triangles;
  std::vector<shader::TriangleShading> shading;
};

SceneTriangles flattenScene(const renderer::Scene& scene, const renderer::AnimatedState& state) {
  SceneTriangles flat;
  for (uint32_t instanceIndex = 0; instanceIndex < scene.instances.size(); ++instanceIndex) {
    const renderer::Instance& instance = scene.instances[instanceIndex];
    const bool moving = state.movingObjectTransform && scene.movingObject && scene.movingObject->instance == instanceIndex;
    const glm::mat4 model = moving ? *state.movingObjectTransform : instance.transform;
    // As the G-buffer's vertex shader transforms normals (GpuScene::updateInstances' normal matrix).
    const glm::mat3 normalMatrix(glm::transpose(glm::inverse(model)));
    const renderer::Mesh& mesh = scene.meshes.at(instance.mesh);
    if (mesh.material >= scene.materials.size())
      throw gpu::GpuError("scene '" + scene.name + "': mesh '" + mesh.name + "' has no material " +
                          std::to_string(mesh.material));
    const float materialBits = std::bit_cast<float>(mesh.material);
    const uint32_t cutsOut = scene.materials[mesh.material].alphaCutoff > 0.0f ? 1u : 0u;
    for (size_t first = 0; first + 2 < mesh.indices.size(); first += 3) {
      const renderer::Vertex& a = mesh.vertices.at(mesh.indices[first]);
      const renderer::Vertex& b = mesh.vertices.at(mesh.indices[first + 1]);
      const renderer::Vertex& c = mesh.vertices.at(mesh.indices[first + 2]);
      const glm::vec3 worldA(model * glm::vec4(a.position, 1.0f));
      const glm::vec3 worldB(model * glm::vec4(b.position, 1.0f));
      const glm::vec3 worldC(model * glm::vec4(c.position, 1.0f));
      flat.triangles.push_back({worldA, cutsOut, worldB - worldA, 0u, worldC - worldA, 0u});
      flat.shading.push_back({.normal0AndU0 = glm::vec4(normalMatrix * a.normal, a.uv.x),
                              .normal1AndU1 = glm::vec4(normalMatrix * b.normal, b.uv.x),
                              .normal2AndU2 = glm::vec4(normalMatrix * c.normal, c.uv.x),
                              .texcoordVAndMaterial = glm::vec4(a.uv.y, b.uv.y, c.uv.y, materialBits),
                              .color0 = a.color,
                              .color1 = b.color,
                              .color2 = c.color});
    }
  }
  if (flat.triangles.empty()) throw gpu::GpuError("scene '" + scene.name + "' has no triangles");
  return flat;
}

template <typename T>
std::vector<T> inOrder(const std::vector<T>& values, const std::vector<uint32_t>& order) {
  std::vector<T> ordered;
  ordered.reserve(order.size());
  for (uint32_t index : order) ordered.push_back(values[index]);
  return ordered;
}

// A device-local storage buffer holding `values` (at least one element: Vulkan has no empty buffers).
template <typename T>
gpu::Buffer storageBuffer(gpu::OwnedDevice& device, const std::string& name, std::vector<T> values) {
  if (values.empty()) values.resize(1);
  gpu::Buffer buffer(device, name, values.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device, buffer, std::as_bytes(std::span(values)));
  return buffer;
}

std::vector<shader::GpuMaterial> materialsOf(const renderer::Scene& scene) {
  if (scene.materials.empty()) throw gpu::GpuError("scene '" + scene.name + "' has no materials");
  std::vector<shader::GpuMaterial> materials;
  for (const renderer::Material& material : scene.materials)
    materials.push_back(renderer::toGpuMaterial(material, scene.textures.size()));
  return materials;
}

// Every texture's RGBA8 texels, back to back, one uint each.
struct PackedTextures {
  std::vector<shader::PackedTexture> textures;
  std::vector<uint32_t> texels;
};

PackedTextures packTextures(const renderer::Scene& scene) {
  PackedTextures packed;
  for (const renderer::Texture& texture : scene.textures) {
    const size_t texelCount = size_t(texture.width) * texture.height;
    if (texelCount == 0 || texture.rgba.size() != texelCount * 4)
      throw gpu::GpuError("texture '" + texture.name + "' has no texels or the wrong number of bytes");
    packed.textures.push_back({static_cast<uint32_t>(packed.texels.size()), texture.width, texture.height, 0});
    const size_t first = packed.texels.size();
    packed.texels.resize(first + texelCount);
    std::memcpy(packed.texels.data() + first, texture.rgba.data(), texture.rgba.size());
  }
  return packed;
}

// The table the paths sample emitters from (shader::EmissiveTriangle), over triangles and shading in BVH order, and
// its total power. A triangle is chosen in proportion to its power: area × shader::emissionLuminance of its emission
// (the shader's own definition, with which a path finds the density of a point it hits). A triangle without power adds
// nothing where a path hits it, so NEE need not sample it either.
struct EmitterTable {
  std::vector<shader::EmissiveTriangle> entries;
  double totalPower = 0.0;
};

EmitterTable emissiveTriangles(const std::vector<shader::TraceTriangle>& triangles,
                               const std::vector<shader::TriangleShading>& shading,
                               const std::vector<shader::GpuMaterial>& materials) {
  EmitterTable table;
  std::vector<double> powers;
  for (uint32_t index = 0; index < triangles.size(); ++index) {
    const uint32_t material = std::bit_cast<uint32_t>(shading[index].texcoordVAndMaterial.w);
    const double luminance = shader::emissionLuminance(glm::vec3(materials.at(material).emission));
    const double area = 0.5 * glm::length(glm::cross(glm::dvec3(triangles[index].edge1), glm::dvec3(triangles[index].edge2)));
    const double power = area * luminance;
    if (!(power > 0.0)) continue;
    table.entries.push_back({.triangle = index});
    powers.push_back(power);
    table.totalPower += power;
  }
  double cumulativePower = 0.0;
  for (size_t entry = 0; entry < table.entries.size(); ++entry) {
    cumulativePower += powers[entry];
    table.entries[entry].selectionProbability = static_cast<float>(powers[entry] / table.totalPower);
    table.entries[entry].cumulativeProbability = static_cast<float>(cumulativePower / table.totalPower);
  }
  // Rounding must not leave a uniform number just below 1 past the end of the table.
  if (!table.entries.empty()) table.entries.back().cumulativeProbability = 1.0f;
  return table;
}

std::vector<shader::GpuLight> lightsOf(const renderer::Scene& scene) {
  std::vector<shader::GpuLight> lights;
  for (const renderer::LocalLight& light : scene.lights) {
    shader::GpuLight gpuLight = renderer::toGpuLight(light);
    // The path tracer has no shadow layers: w only says whether the light casts shadows at all.
    gpuLight.intensityAndShadow.w = std::bit_cast<float>(light.castsShadow ? 0u : shader::kNoShadow);
    lights.push_back(gpuLight);
  }
  return lights;
}

}  // namespace

gpu::SpecializationConstants sceneTracingConstants(const renderer::Scene& scene) {
  const bool cutsOut = std::any_of(scene.materials.begin(), scene.materials.end(),
                                   [](const renderer::Material& material) { return material.alphaCutoff > 0.0f; });
  return {cutsOut ? 1u : 0u};
}

TracedScene::TracedScene(gpu::OwnedDevice& device, const renderer::Scene& scene, const renderer::AnimatedState& state,
                         uint32_t width, uint32_t height, float exposure)
    : frameConstants_(device, "reference frame constants", sizeof(shader::FrameConstants),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload) {
  const SceneTriangles flat = flattenScene(scene, state);
  const Bvh bvh = buildBvh(flat.triangles);
  triangleCount_ = static_cast<uint32_t>(flat.triangles.size());
  bvhNodeCount_ = static_cast<uint32_t>(bvh.nodes.size());
  bvhDepth_ = bvh.depth;
  const std::vector<shader::TraceTriangle> orderedTriangles = inOrder(flat.triangles, bvh.triangleOrder);
  const std::vector<shader::TriangleShading> orderedShading = inOrder(flat.shading, bvh.triangleOrder);
  const std::vector<shader::GpuMaterial> materials = materialsOf(scene);
  EmitterTable emitters = emissiveTriangles(orderedTriangles, orderedShading, materials);
  emitterCount_ = static_cast<uint32_t>(emitters.entries.size());
  emittedPower_ = static_cast<float>(emitters.totalPower);
  nodes_ = storageBuffer(device, "reference bvh nodes", bvh.nodes);
  triangles_ = storageBuffer(device, "reference triangles", orderedTriangles);
  shading_ = storageBuffer(device, "reference triangle shading", orderedShading);
  materials_ = storageBuffer(device, "reference materials", materials);
  emitters_ = storageBuffer(device, "reference emissive triangles", std::move(emitters.entries));
  PackedTextures packed = packTextures(scene);
  textures_ = storageBuffer(device, "reference textures", std::move(packed.textures));
  texels_ = storageBuffer(device, "reference texels", std::move(packed.texels));
  lights_ = storageBuffer(device, "reference lights", lightsOf(scene));

  const shader::FrameConstants frame = renderer::makeFrameConstants(scene, state, width, height, exposure);
  std::memcpy(frameConstants_.mapped(), &frame, sizeof(frame));
}

uint32_t DispatchPacer::nextUnits(uint32_t remaining) const { return std::min(unitsPerDispatch_, remaining); }

void DispatchPacer::measured(uint32_t units, double seconds) {
  // Aim the next dispatch at the target time, growing at most twofold so that one fast (e.g. cold) measurement
  // cannot make a dispatch that runs far too long.
  const double secondsPerUnit = std::max(seconds, 1e-6) / double(units);
  const double fitting = std::floor(secondsPerDispatch_ / secondsPerUnit);
  unitsPerDispatch_ = static_cast<uint32_t>(std::clamp(fitting, 1.0, 2.0 * double(units)));
}

gpu::Bindings TracedScene::bindings() const {
  return gpu::Bindings()
      .buffer(shader::kBindTraceFrame, frameConstants_)
      .buffer(shader::kBindTraceNodes, nodes_)
      .buffer(shader::kBindTraceTriangles, triangles_)
      .buffer(shader::kBindTraceShading, shading_)
      .buffer(shader::kBindTraceMaterials, materials_)
      .buffer(shader::kBindTraceTextures, textures_)
      .buffer(shader::kBindTraceTexels, texels_)
      .buffer(shader::kBindTraceLights, lights_)
      .buffer(shader::kBindTraceEmitters, emitters_);
}

}  // namespace ssvgi::reference
