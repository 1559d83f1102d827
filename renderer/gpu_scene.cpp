#include "gpu_scene.h"

#include "gpu_host/transfers.h"

#include <cstring>

namespace ssvgi::renderer {

namespace {

template <typename T>
std::span<const std::byte> bytesOf(const std::vector<T>& values) {
  return std::as_bytes(std::span(values));
}

VkSamplerCreateInfo repeatingLinearSampler() {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = VK_FILTER_LINEAR;
  info.minFilter = VK_FILTER_LINEAR;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  info.maxLod = 0.0f;
  return info;
}

gpu::Image makeTexture(gpu::OwnedDevice& device, const std::string& name, uint32_t width, uint32_t height,
                       std::span<const std::byte> rgba) {
  gpu::Image image(device, {name, VK_FORMAT_R8G8B8A8_SRGB, width, height, 1, 1, VK_IMAGE_USAGE_SAMPLED_BIT});
  gpu::uploadImage(device, image, rgba);
  return image;
}

}  // namespace

shader::GpuMaterial toGpuMaterial(const Material& material, size_t textureCount) {
  const auto known = [&](uint32_t texture) { return texture < textureCount ? texture : kNoTexture; };
  return shader::GpuMaterial{.baseColor = material.baseColor,
                             .baseColorTexture = known(material.baseColorTexture),
                             .emission = material.emission,
                             .alphaCutoff = material.alphaCutoff,
                             .emissionTexture = known(material.emissionTexture)};
}

GpuScene::GpuScene(gpu::OwnedDevice& device, const Scene& scene)
    : sampler_(device, repeatingLinearSampler(), "scene texture sampler") {
  for (const Texture& texture : scene.textures)
    textures_.push_back(makeTexture(device, "texture " + texture.name, texture.width, texture.height,
                                    bytesOf(texture.rgba)));
  const std::vector<uint8_t> white{255, 255, 255, 255};
  whiteTexture_ = makeTexture(device, "white texture", 1, 1, bytesOf(white));

  std::vector<shader::GpuMaterial> materials;
  for (const Material& material : scene.materials) {
    materials.push_back(toGpuMaterial(material, scene.textures.size()));
    materialTextures_.push_back({materials.back().baseColorTexture, materials.back().emissionTexture});
  }
  if (materials.empty()) throw gpu::GpuError("scene '" + scene.name + "' has no materials");

  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> meshFirstIndex;
  std::vector<int32_t> meshVertexOffset;
  for (const Mesh& mesh : scene.meshes) {
    meshFirstIndex.push_back(static_cast<uint32_t>(indices.size()));
    meshVertexOffset.push_back(static_cast<int32_t>(vertices.size()));
    vertices.insert(vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
  }
  if (indices.empty()) throw gpu::GpuError("scene '" + scene.name + "' has no triangles");
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Mesh& mesh = scene.meshes.at(scene.instances[i].mesh);
    draws_.push_back({i, mesh.material, meshFirstIndex[scene.instances[i].mesh],
                      static_cast<uint32_t>(mesh.indices.size()), meshVertexOffset[scene.instances[i].mesh],
                      scene.materials.at(mesh.material).alphaCutoff > 0.0f});
  }

  vertices_ = gpu::Buffer(device, "scene vertices", vertices.size() * sizeof(Vertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  indices_ = gpu::Buffer(device, "scene indices", indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  materials_ = gpu::Buffer(device, "scene materials", materials.size() * sizeof(shader::GpuMaterial),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu::uploadBuffer(device, vertices_, bytesOf(vertices));
  gpu::uploadBuffer(device, indices_, bytesOf(indices));
  gpu::uploadBuffer(device, materials_, bytesOf(materials));

  instanceData_.resize(scene.instances.size());
  instances_ = gpu::Buffer(device, "scene instances", std::max<size_t>(1, instanceData_.size()) * sizeof(shader::GpuInstance),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::HostUpload);
}

void GpuScene::updateInstances(const Scene& scene, const AnimatedState& state) {
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    glm::mat4 model = scene.instances[i].transform;
    if (state.movingObjectTransform && scene.movingObject && scene.movingObject->instance == i)
      model = *state.movingObjectTransform;
    shader::GpuInstance& instance = instanceData_[i];
    instance.previousModel = firstFrame_ ? model : instance.model;
    instance.model = model;
    instance.normalMatrix = glm::transpose(glm::inverse(model));
  }
  firstFrame_ = false;
  std::memcpy(instances_.mapped(), instanceData_.data(), instanceData_.size() * sizeof(shader::GpuInstance));
}

const gpu::Image& GpuScene::baseColorTexture(uint32_t material) const {
  return textureOrWhite(materialTextures_.at(material).baseColor);
}

const gpu::Image& GpuScene::emissionTexture(uint32_t material) const {
  return textureOrWhite(materialTextures_.at(material).emission);
}

const gpu::Image& GpuScene::textureOrWhite(uint32_t texture) const {
  return texture == kNoTexture ? whiteTexture_ : textures_[texture];
}

}  // namespace ssvgi::renderer
