#include "path_tracer.h"

#include "bvh.h"
#include "gpu_scene.h"
#include "renderer.h"
#include "ssvgi_reference_shaders.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <span>

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
    for (size_t first = 0; first + 2 < mesh.indices.size(); first += 3) {
      const renderer::Vertex& a = mesh.vertices.at(mesh.indices[first]);
      const renderer::Vertex& b = mesh.vertices.at(mesh.indices[first + 1]);
      const renderer::Vertex& c = mesh.vertices.at(mesh.indices[first + 2]);
      const glm::vec3 worldA(model * glm::vec4(a.position, 1.0f));
      const glm::vec3 worldB(model * glm::vec4(b.position, 1.0f));
      const glm::vec3 worldC(model * glm::vec4(c.position, 1.0f));
      flat.triangles.push_back({glm::vec4(worldA, 0.0f), glm::vec4(worldB - worldA, 0.0f), glm::vec4(worldC - worldA, 0.0f)});
      flat.shading.push_back({glm::vec4(normalMatrix * a.normal, a.uv.x), glm::vec4(normalMatrix * b.normal, b.uv.x),
                              glm::vec4(normalMatrix * c.normal, c.uv.x),
                              glm::vec4(a.uv.y, b.uv.y, c.uv.y, materialBits)});
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
gpu::Buffer storageBuffer(gpu::Device& device, const std::string& name, std::vector<T> values) {
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

gpu::Image storageImage(gpu::Device& device, const char* name, VkFormat format, const PathTracerSettings& settings) {
  return gpu::Image(device, {name, format, settings.width, settings.height, 1, 1, VK_IMAGE_USAGE_STORAGE_BIT});
}

glm::uvec3 pixels(const PathTracerSettings& settings) { return {settings.width, settings.height, 1}; }

}  // namespace

PathTracer::PathTracer(gpu::Device& device, const renderer::Scene& scene, const renderer::AnimatedState& state,
                       const PathTracerSettings& settings)
    : device_(device),
      settings_(settings),
      descriptors_(device),
      profiler_(device),
      primaryHitsPipeline_(device, shaders::primary_hits_comp),
      pathTracePipeline_(device, shaders::path_trace_comp),
      tonemap_(device),
      frameConstants_(device, "reference frame constants", sizeof(shader::FrameConstants),
                      VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::HostUpload),
      rayOrigins_(storageImage(device, "reference ray origins", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      normals_(storageImage(device, "reference normal", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      albedos_(storageImage(device, "reference albedo", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      primaryRadiance_(storageImage(device, "reference primary radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      directIrradiance_(storageImage(device, "reference direct irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      viewDistances_(storageImage(device, "reference view distance", VK_FORMAT_R32_SFLOAT, settings)),
      indirectSums_(storageImage(device, "reference indirect sums", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      indirectIrradiance_(storageImage(device, "reference indirect irradiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      finalRadiance_(storageImage(device, "reference final radiance", VK_FORMAT_R32G32B32A32_SFLOAT, settings)),
      tonemapped_(storageImage(device, "reference tonemapped", VK_FORMAT_R8G8B8A8_UNORM, settings)) {
  if (settings.width == 0 || settings.height == 0) throw gpu::GpuError("reference size must be at least 1×1");

  const SceneTriangles flat = flattenScene(scene, state);
  const Bvh bvh = buildBvh(flat.triangles);
  triangleCount_ = static_cast<uint32_t>(flat.triangles.size());
  bvhNodeCount_ = static_cast<uint32_t>(bvh.nodes.size());
  bvhDepth_ = bvh.depth;
  nodes_ = storageBuffer(device, "reference bvh nodes", bvh.nodes);
  triangles_ = storageBuffer(device, "reference triangles", inOrder(flat.triangles, bvh.triangleOrder));
  shading_ = storageBuffer(device, "reference triangle shading", inOrder(flat.shading, bvh.triangleOrder));
  materials_ = storageBuffer(device, "reference materials", materialsOf(scene));
  PackedTextures packed = packTextures(scene);
  textures_ = storageBuffer(device, "reference textures", std::move(packed.textures));
  texels_ = storageBuffer(device, "reference texels", std::move(packed.texels));
  lights_ = storageBuffer(device, "reference lights", lightsOf(scene));

  const shader::FrameConstants frame =
      renderer::makeFrameConstants(scene, state, settings.width, settings.height, settings.exposure);
  std::memcpy(frameConstants_.mapped(), &frame, sizeof(frame));

  submit([&](gpu::CommandList& commands) {
    commands.clearImage(indirectSums_, VkClearColorValue{});
    commands.clearImage(indirectIrradiance_, VkClearColorValue{});
    commands.clearImage(finalRadiance_, VkClearColorValue{});
    commands.clearImage(tonemapped_, VkClearColorValue{});
    auto scope = commands.scope("reference: PrimaryHits");
    commands.dispatch(primaryHitsPipeline_,
                      primaryHitBindings()
                          .image(shader::kBindPrimaryDistance, viewDistances_),
                      pixels(settings_));
  });
}

gpu::Bindings PathTracer::sceneBindings() const {
  return gpu::Bindings()
      .buffer(shader::kBindTraceFrame, frameConstants_)
      .buffer(shader::kBindTraceNodes, nodes_)
      .buffer(shader::kBindTraceTriangles, triangles_)
      .buffer(shader::kBindTraceShading, shading_)
      .buffer(shader::kBindTraceMaterials, materials_)
      .buffer(shader::kBindTraceTextures, textures_)
      .buffer(shader::kBindTraceTexels, texels_)
      .buffer(shader::kBindTraceLights, lights_);
}

gpu::Bindings PathTracer::primaryHitBindings() const {
  return sceneBindings()
      .image(shader::kBindPrimaryRayOrigin, rayOrigins_)
      .image(shader::kBindPrimaryNormal, normals_)
      .image(shader::kBindPrimaryAlbedo, albedos_)
      .image(shader::kBindPrimaryRadiance, primaryRadiance_)
      .image(shader::kBindPrimaryDirect, directIrradiance_);
}

void PathTracer::submit(const std::function<void(gpu::CommandList&)>& record) {
  descriptors_.reset();
  device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::CommandList commands(device_, commandBuffer, descriptors_, &profiler_);
    profiler_.begin(commandBuffer);
    record(commands);
  });
  for (const gpu::PassTiming& timing : profiler_.resolve()) {
    auto total = std::find_if(timings_.begin(), timings_.end(),
                              [&](const gpu::PassTiming& pass) { return pass.name == timing.name; });
    if (total == timings_.end()) {
      timings_.push_back(timing);
    } else {
      total->milliseconds += timing.milliseconds;
    }
  }
}

void PathTracer::trace(uint32_t samples, const std::function<void(uint32_t samplesPerPixel)>& progress) {
  if (samples == 0) throw gpu::GpuError("the path tracer needs at least one sample per pixel");
  const uint32_t target = samplesPerPixel_ + samples;
  while (samplesPerPixel_ < target) {
    const shader::PathTracePush push{.firstSample = samplesPerPixel_,
                                     .sampleCount = std::min(samplesPerDispatch_, target - samplesPerPixel_),
                                     .seed = settings_.seed,
                                     .maxBounces = settings_.maxBounces};
    const auto start = std::chrono::steady_clock::now();
    submit([&](gpu::CommandList& commands) {
      {
        auto scope = commands.scope("reference: PathTrace");
        commands.dispatch(pathTracePipeline_,
                          primaryHitBindings()
                              .image(shader::kBindTraceIndirectSum, indirectSums_)
                              .image(shader::kBindTraceIndirect, indirectIrradiance_)
                              .image(shader::kBindTraceFinal, finalRadiance_),
                          pixels(settings_), push);
      }
      tonemap_.record(commands, frameConstants_, finalRadiance_, tonemapped_);
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    samplesPerPixel_ += push.sampleCount;
    // Aim the next dispatch at the target time, growing at most twofold so that one fast (e.g. cold) measurement
    // cannot make a dispatch that runs far too long.
    const double secondsPerSample = std::max(seconds, 1e-6) / double(push.sampleCount);
    const double fitting = std::floor(settings_.secondsPerDispatch / secondsPerSample);
    samplesPerDispatch_ = static_cast<uint32_t>(std::clamp(fitting, 1.0, 2.0 * double(push.sampleCount)));
    if (progress) progress(samplesPerPixel_);
  }
}

renderer::FloatImage PathTracer::finalRadiance() { return renderer::readFloatImage(device_, finalRadiance_, 3); }
renderer::FloatImage PathTracer::directIrradiance() { return renderer::readFloatImage(device_, directIrradiance_, 3); }
renderer::FloatImage PathTracer::indirectIrradiance() {
  return renderer::readFloatImage(device_, indirectIrradiance_, 3);
}
renderer::FloatImage PathTracer::albedo() { return renderer::readFloatImage(device_, albedos_, 3); }
renderer::FloatImage PathTracer::normal() { return renderer::readFloatImage(device_, normals_, 3); }
renderer::FloatImage PathTracer::viewDistance() { return renderer::readFloatImage(device_, viewDistances_, 1); }

std::vector<uint8_t> PathTracer::tonemapped() {
  const auto bytes = gpu::readImage(device_, tonemapped_);
  std::vector<uint8_t> rgba(bytes.size());
  std::memcpy(rgba.data(), bytes.data(), bytes.size());
  return rgba;
}

}  // namespace ssvgi::reference
