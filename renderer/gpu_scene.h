#pragma once
#include "gpu/resources.h"
#include "gpu_host/owned_device.h"
#include "scene.h"
#include "shared/renderer_interface.h"

#include <vector>

namespace ssvgi::renderer {

// A material as the shaders read it; a texture index past the scene's `textureCount` textures counts as none.
shader::GpuMaterial toGpuMaterial(const Material& material, size_t textureCount);

// One indexed draw: an instance of a mesh.
struct Draw {
  uint32_t instance;
  uint32_t material;
  uint32_t firstIndex;
  uint32_t indexCount;
  int32_t vertexOffset;
  bool cutsOut;  // its material's texture cuts the surface out in places (Material::alphaCutoff)
};

// The scene's geometry, materials and textures on the GPU, plus the per-frame instance transforms.
class GpuScene {
 public:
  GpuScene(gpu::OwnedDevice& device, const Scene& scene);

  // Sets this frame's instance transforms (the moving object's replaced), remembering last frame's for motion vectors.
  void updateInstances(const Scene& scene, const AnimatedState& state);

  const gpu::Buffer& vertices() const { return vertices_; }
  const gpu::Buffer& indices() const { return indices_; }
  const gpu::Buffer& instances() const { return instances_; }
  const gpu::Buffer& materials() const { return materials_; }
  const std::vector<Draw>& draws() const { return draws_; }
  // The base colour and the emission texture of a material (a 1×1 white one where it has none).
  const gpu::Image& baseColorTexture(uint32_t material) const;
  const gpu::Image& emissionTexture(uint32_t material) const;
  VkSampler textureSampler() const { return sampler_.handle(); }

 private:
  const gpu::Image& textureOrWhite(uint32_t texture) const;

  // A material's textures: indices into textures_, kNoTexture where it has none.
  struct MaterialTextures {
    uint32_t baseColor;
    uint32_t emission;
  };
  std::vector<gpu::Image> textures_;
  gpu::Image whiteTexture_;
  std::vector<MaterialTextures> materialTextures_;
  gpu::Sampler sampler_;
  gpu::Buffer vertices_;
  gpu::Buffer indices_;
  gpu::Buffer materials_;
  gpu::Buffer instances_;  // host-visible, rewritten every frame
  std::vector<shader::GpuInstance> instanceData_;
  bool firstFrame_ = true;
  std::vector<Draw> draws_;
};

}  // namespace ssvgi::renderer
