#include "gltf_loader.h"

#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <string_view>
#include <utility>

namespace ssvgi::renderer {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, std::string_view problem) {
  // tinygltf reports each problem on its own line; SceneLoadError promises one line.
  std::string line;
  for (const char c : problem) {
    if (c == '\n' || c == '\r') {
      if (!line.empty() && !line.ends_with("; ")) line += "; ";
    } else {
      line += c;
    }
  }
  while (line.ends_with(' ') || line.ends_with(';')) line.pop_back();
  throw SceneLoadError(path.string() + ": " + line);
}

// Reads a value from a byte address that need not be aligned (a corrupt file can put an accessor anywhere).
template <typename T>
T loadUnaligned(const unsigned char* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

glm::vec3 normalizedOr(const glm::vec3& v, const glm::vec3& fallback) {
  const float length = glm::length(v);
  return length > 1e-20f ? v / length : fallback;
}

// The first three numbers of a glTF colour (RGB or RGBA), or `fallback` when the file gives none.
glm::vec3 rgbOr(const std::vector<double>& colour, const glm::vec3& fallback) {
  if (colour.size() < 3) return fallback;
  return {static_cast<float>(colour[0]), static_cast<float>(colour[1]), static_cast<float>(colour[2])};
}

// An accessor's elements, checked to lie inside their buffer.
struct AccessorView {
  const unsigned char* first = nullptr;
  size_t count = 0;
  size_t stride = 0;  // bytes from one element to the next
  int componentType = 0;
  int componentCount = 0;
  bool normalized = false;
};

// The glTF model turned into our scene: the default scene's nodes flattened into instances, with meshes, materials,
// textures, lights and cameras. Every index and byte range in the file is checked before use, so a corrupt file fails
// with a SceneLoadError instead of reading out of bounds.
class GltfConverter {
 public:
  GltfConverter(const tinygltf::Model& model, std::filesystem::path path)
      : model_(model), path_(std::move(path)), visited_(model.nodes.size(), false) {}

  Scene convert() {
    convertMaterials();
    for (const int root : rootNodes()) visitNode(root, glm::mat4(1.0f));
    if (scene_.instances.empty()) fail(path_, "no triangle meshes in the scene");
    // Cameras and lights come in the order their nodes are visited (the scene's nodes, depth first).
    if (scene_.cameras.empty()) scene_.cameras.push_back(cameraFraming(worldBounds(scene_)));
    return std::move(scene_);
  }

 private:
  void checkIndex(int index, size_t size, std::string_view what, std::string_view user) const {
    if (index < 0 || static_cast<size_t>(index) >= size) {
      fail(path_, std::string(user) + " refers to " + std::string(what) + " " + std::to_string(index) +
                      ", but the file has " + std::to_string(size));
    }
  }

  std::vector<int> rootNodes() const {
    if (model_.scenes.empty()) {
      // No scene listed: show every node that is no other node's child.
      std::vector<bool> isChild(model_.nodes.size(), false);
      for (const tinygltf::Node& node : model_.nodes) {
        for (const int child : node.children) {
          checkIndex(child, model_.nodes.size(), "node", "node '" + node.name + "'");
          isChild[static_cast<size_t>(child)] = true;
        }
      }
      std::vector<int> roots;
      for (size_t i = 0; i < model_.nodes.size(); ++i) {
        if (!isChild[i]) roots.push_back(static_cast<int>(i));
      }
      return roots;
    }
    const int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    checkIndex(sceneIndex, model_.scenes.size(), "scene", "the default scene");
    return model_.scenes[static_cast<size_t>(sceneIndex)].nodes;
  }

  glm::mat4 localTransform(const tinygltf::Node& node) const {
    const auto wrongLength = [&](const std::vector<double>& values, size_t length) {
      return !values.empty() && values.size() != length;
    };
    if (wrongLength(node.matrix, 16) || wrongLength(node.translation, 3) || wrongLength(node.rotation, 4) ||
        wrongLength(node.scale, 3)) {
      fail(path_, "node '" + node.name + "' has a transform of the wrong length");
    }
    if (!node.matrix.empty()) {
      glm::mat4 matrix;  // column-major, as glTF stores it
      std::transform(node.matrix.begin(), node.matrix.end(), glm::value_ptr(matrix),
                     [](double value) { return static_cast<float>(value); });
      return matrix;
    }
    glm::mat4 transform(1.0f);
    if (!node.translation.empty()) {
      transform[3] = glm::vec4(glm::vec3(glm::make_vec3(node.translation.data())), 1.0f);
    }
    if (!node.rotation.empty()) {
      const glm::dvec4 xyzw = glm::make_vec4(node.rotation.data());
      transform *= glm::mat4_cast(glm::normalize(glm::quat(static_cast<float>(xyzw.w), static_cast<float>(xyzw.x),
                                                           static_cast<float>(xyzw.y), static_cast<float>(xyzw.z))));
    }
    if (!node.scale.empty()) {
      const glm::vec3 scale(glm::make_vec3(node.scale.data()));
      transform[0] *= scale.x;
      transform[1] *= scale.y;
      transform[2] *= scale.z;
    }
    return transform;
  }

  void visitNode(int index, const glm::mat4& parentTransform) {
    checkIndex(index, model_.nodes.size(), "node", "the node hierarchy");
    // glTF nodes form a tree: a node reached twice means a cycle or a shared child.
    if (visited_[static_cast<size_t>(index)]) {
      fail(path_, "node " + std::to_string(index) + " is reached twice; the node hierarchy must be a tree");
    }
    visited_[static_cast<size_t>(index)] = true;
    const tinygltf::Node& node = model_.nodes[static_cast<size_t>(index)];
    const glm::mat4 world = parentTransform * localTransform(node);

    if (node.mesh >= 0) {
      checkIndex(node.mesh, model_.meshes.size(), "mesh", "node '" + node.name + "'");
      const bool mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
      for (const uint32_t mesh : meshesFor(node.mesh, mirrored)) scene_.instances.push_back({mesh, world});
    }
    if (node.camera >= 0) {
      checkIndex(node.camera, model_.cameras.size(), "camera", "node '" + node.name + "'");
      addCamera(model_.cameras[static_cast<size_t>(node.camera)], node, world);
    }
    if (const auto light = node.extensions.find("KHR_lights_punctual"); light != node.extensions.end()) {
      const tinygltf::Value& extension = light->second;
      if (!extension.IsObject() || !extension.Get("light").IsNumber()) {
        fail(path_, "node '" + node.name + "' has a KHR_lights_punctual extension without a light index");
      }
      const int lightIndex = extension.Get("light").GetNumberAsInt();
      checkIndex(lightIndex, model_.lights.size(), "light", "node '" + node.name + "'");
      addLight(model_.lights[static_cast<size_t>(lightIndex)], node, world);
    }
    for (const int child : node.children) visitNode(child, world);
  }

  // Our meshes for a glTF mesh, one per triangle primitive, converted on first use. A mirroring node transform turns
  // counter-clockwise faces clockwise (glTF spec 3.7.4), so mirrored instances get a copy with the winding reversed.
  const std::vector<uint32_t>& meshesFor(int gltfMesh, bool mirrored) {
    const auto key = std::make_pair(gltfMesh, mirrored);
    if (const auto cached = meshCache_.find(key); cached != meshCache_.end()) return cached->second;
    std::vector<uint32_t> meshes;
    if (mirrored) {
      for (const uint32_t original : meshesFor(gltfMesh, false)) {
        Mesh flipped = scene_.meshes[original];
        for (size_t i = 0; i + 2 < flipped.indices.size(); i += 3)
          std::swap(flipped.indices[i + 1], flipped.indices[i + 2]);
        meshes.push_back(addMesh(std::move(flipped)));
      }
    } else {
      const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(gltfMesh)];
      for (size_t i = 0; i < mesh.primitives.size(); ++i) {
        // Points, lines, strips and fans are not drawn.
        if (mesh.primitives[i].mode != TINYGLTF_MODE_TRIANGLES) continue;
        const std::string name = mesh.primitives.size() > 1 ? mesh.name + "#" + std::to_string(i) : mesh.name;
        meshes.push_back(addMesh(convertPrimitive(mesh.primitives[i], name)));
      }
    }
    return meshCache_.emplace(key, std::move(meshes)).first->second;
  }

  uint32_t addMesh(Mesh mesh) {
    scene_.meshes.push_back(std::move(mesh));
    return static_cast<uint32_t>(scene_.meshes.size() - 1);
  }

  Mesh convertPrimitive(const tinygltf::Primitive& primitive, const std::string& name) {
    const std::string user = "mesh '" + name + "'";
    const auto attribute = [&](const char* semantic) {
      const auto found = primitive.attributes.find(semantic);
      return found == primitive.attributes.end() ? -1 : found->second;
    };
    const int positionAccessor = attribute("POSITION");
    if (positionAccessor < 0) fail(path_, user + " has no POSITION attribute");
    const std::vector<float> positions = readFloats(positionAccessor, 3, user + " POSITION");
    const size_t vertexCount = positions.size() / 3;

    const auto readOptional = [&](const char* semantic, int components) {
      const int accessor = attribute(semantic);
      if (accessor < 0) return std::vector<float>();
      std::vector<float> values = readFloats(accessor, components, user + " " + semantic);
      if (values.size() != vertexCount * static_cast<size_t>(components)) {
        fail(path_, user + " has " + std::to_string(values.size() / static_cast<size_t>(components)) + " " + semantic +
                        " values for " + std::to_string(vertexCount) + " vertices");
      }
      return values;
    };
    const std::vector<float> normals = readOptional("NORMAL", 3);
    const std::vector<float> uvs = readOptional("TEXCOORD_0", 2);

    Mesh mesh;
    mesh.name = name;
    mesh.material = materialFor(primitive.material, user);
    mesh.vertices.resize(vertexCount);
    for (size_t v = 0; v < vertexCount; ++v) {
      Vertex& vertex = mesh.vertices[v];
      vertex.position = glm::make_vec3(&positions[3 * v]);
      if (!normals.empty()) vertex.normal = normalizedOr(glm::make_vec3(&normals[3 * v]), vertex.normal);
      if (!uvs.empty()) vertex.uv = glm::make_vec2(&uvs[2 * v]);
    }
    if (primitive.indices >= 0) {
      mesh.indices = readIndices(primitive.indices, vertexCount, user);
    } else {
      mesh.indices.resize(vertexCount);
      for (size_t v = 0; v < vertexCount; ++v) mesh.indices[v] = static_cast<uint32_t>(v);
    }
    if (mesh.indices.size() % 3 != 0) {
      fail(path_, user + " has " + std::to_string(mesh.indices.size()) + " triangle corners, not a multiple of 3");
    }
    if (normals.empty()) giveFlatNormals(mesh);
    return mesh;
  }

  // glTF: "When normals are not specified, client implementations MUST calculate flat normals." Each triangle gets its
  // own three vertices carrying its face normal.
  static void giveFlatNormals(Mesh& mesh) {
    std::vector<Vertex> corners;
    corners.reserve(mesh.indices.size());
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
      const Vertex& a = mesh.vertices[mesh.indices[i]];
      const Vertex& b = mesh.vertices[mesh.indices[i + 1]];
      const Vertex& c = mesh.vertices[mesh.indices[i + 2]];
      const glm::vec3 normal =
          normalizedOr(glm::cross(b.position - a.position, c.position - a.position), glm::vec3(0.0f, 1.0f, 0.0f));
      for (const Vertex* corner : {&a, &b, &c}) corners.push_back({corner->position, normal, corner->uv});
    }
    mesh.vertices = std::move(corners);
    for (size_t i = 0; i < mesh.indices.size(); ++i) mesh.indices[i] = static_cast<uint32_t>(i);
  }

  AccessorView viewAccessor(int index, const std::string& user) const {
    checkIndex(index, model_.accessors.size(), "accessor", user);
    const tinygltf::Accessor& accessor = model_.accessors[static_cast<size_t>(index)];
    const std::string name = "accessor " + std::to_string(index);
    if (accessor.sparse.isSparse) fail(path_, name + " is sparse, which is not supported");
    checkIndex(accessor.bufferView, model_.bufferViews.size(), "bufferView", name);
    const tinygltf::BufferView& view = model_.bufferViews[static_cast<size_t>(accessor.bufferView)];
    const std::string viewName = "bufferView " + std::to_string(accessor.bufferView);
    checkIndex(view.buffer, model_.buffers.size(), "buffer", viewName);
    const std::vector<unsigned char>& buffer = model_.buffers[static_cast<size_t>(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
      fail(path_, viewName + " (" + std::to_string(view.byteLength) + " bytes at " + std::to_string(view.byteOffset) +
                      ") reaches past the end of buffer " + std::to_string(view.buffer) + " (" +
                      std::to_string(buffer.size()) + " bytes)");
    }
    const int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
    const int componentCount = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
    if (componentSize <= 0 || componentCount <= 0) fail(path_, name + " has an unknown type or component type");
    const size_t elementSize = static_cast<size_t>(componentSize) * static_cast<size_t>(componentCount);
    const size_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
    if (stride < elementSize) fail(path_, viewName + " has a byteStride smaller than the elements of " + name);
    if (accessor.count > 0) {
      // The last element must end inside the view; written to avoid overflow with a huge count or offset.
      const bool fits = accessor.byteOffset <= view.byteLength &&
                        view.byteLength - accessor.byteOffset >= elementSize &&
                        (accessor.count - 1) <= (view.byteLength - accessor.byteOffset - elementSize) / stride;
      if (!fits) {
        fail(path_, name + " (" + std::to_string(accessor.count) + " elements at byte " +
                        std::to_string(accessor.byteOffset) + ") reaches past the end of " + viewName + " (" +
                        std::to_string(view.byteLength) + " bytes)");
      }
    }
    return {buffer.data() + view.byteOffset + accessor.byteOffset,
            accessor.count,
            stride,
            accessor.componentType,
            componentCount,
            accessor.normalized};
  }

  // `components` floats per element. Integer components (KHR_mesh_quantization, or normalized texture coordinates)
  // are converted as glTF specifies: normalized ones to [0,1] or [−1,1], others as their value.
  std::vector<float> readFloats(int accessorIndex, int components, const std::string& user) const {
    const AccessorView view = viewAccessor(accessorIndex, user);
    if (view.componentCount != components) {
      fail(path_, user + " uses accessor " + std::to_string(accessorIndex) + " with " +
                      std::to_string(view.componentCount) + " components where " + std::to_string(components) +
                      " are needed");
    }
    float (*read)(const unsigned char*, bool) = nullptr;
    switch (view.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        read = [](const unsigned char* at, bool) { return loadUnaligned<float>(at); };
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        read = [](const unsigned char* at, bool normalized) {
          const float value = loadUnaligned<uint8_t>(at);
          return normalized ? value / 255.0f : value;
        };
        break;
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        read = [](const unsigned char* at, bool normalized) {
          const float value = loadUnaligned<int8_t>(at);
          return normalized ? std::max(value / 127.0f, -1.0f) : value;
        };
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        read = [](const unsigned char* at, bool normalized) {
          const float value = loadUnaligned<uint16_t>(at);
          return normalized ? value / 65535.0f : value;
        };
        break;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        read = [](const unsigned char* at, bool normalized) {
          const float value = loadUnaligned<int16_t>(at);
          return normalized ? std::max(value / 32767.0f, -1.0f) : value;
        };
        break;
      default:
        fail(path_, user + " uses accessor " + std::to_string(accessorIndex) + " with an unsupported component type");
    }
    const size_t componentSize =
        static_cast<size_t>(tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(view.componentType)));
    std::vector<float> values(view.count * static_cast<size_t>(components));
    for (size_t element = 0; element < view.count; ++element) {
      const unsigned char* at = view.first + element * view.stride;
      for (size_t c = 0; c < static_cast<size_t>(components); ++c) {
        values[element * static_cast<size_t>(components) + c] = read(at + c * componentSize, view.normalized);
      }
    }
    return values;
  }

  std::vector<uint32_t> readIndices(int accessorIndex, size_t vertexCount, const std::string& user) const {
    const std::string what = user + " indices";
    const AccessorView view = viewAccessor(accessorIndex, what);
    if (view.componentCount != 1) fail(path_, what + " are not scalars");
    std::vector<uint32_t> indices(view.count);
    for (size_t i = 0; i < view.count; ++i) {
      const unsigned char* at = view.first + i * view.stride;
      switch (view.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          indices[i] = loadUnaligned<uint8_t>(at);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
          indices[i] = loadUnaligned<uint16_t>(at);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          indices[i] = loadUnaligned<uint32_t>(at);
          break;
        default:
          fail(path_, what + " are not unsigned 8, 16 or 32-bit integers");
      }
      if (indices[i] >= vertexCount) {
        fail(path_, what + " refer to vertex " + std::to_string(indices[i]) + ", but it has " +
                        std::to_string(vertexCount) + " vertices");
      }
    }
    return indices;
  }

  void convertMaterials() {
    for (const tinygltf::Material& source : model_.materials) {
      Material material;
      material.name = source.name;
      material.baseColor = rgbOr(source.pbrMetallicRoughness.baseColorFactor, glm::vec3(1.0f));
      material.baseColorTexture =
          textureFor(source.pbrMetallicRoughness.baseColorTexture, "material '" + source.name + "'");
      float strength = 1.0f;
      if (const auto extension = source.extensions.find("KHR_materials_emissive_strength");
          extension != source.extensions.end() && extension->second.IsObject() &&
          extension->second.Get("emissiveStrength").IsNumber()) {
        strength = static_cast<float>(extension->second.Get("emissiveStrength").GetNumberAsDouble());
      }
      material.emission = rgbOr(source.emissiveFactor, glm::vec3(0.0f)) * strength;
      scene_.materials.push_back(std::move(material));
    }
  }

  // The primitive's material, or a white one (glTF's default material) shared by all primitives without one.
  uint32_t materialFor(int material, const std::string& user) {
    if (material >= 0) {
      checkIndex(material, model_.materials.size(), "material", user);
      return static_cast<uint32_t>(material);
    }
    if (!defaultMaterial_) {
      scene_.materials.push_back({.name = "default"});
      defaultMaterial_ = static_cast<uint32_t>(scene_.materials.size() - 1);
    }
    return *defaultMaterial_;
  }

  uint32_t textureFor(const tinygltf::TextureInfo& info, const std::string& user) {
    if (info.index < 0) return kNoTexture;
    checkIndex(info.index, model_.textures.size(), "texture", user);
    const int imageIndex = model_.textures[static_cast<size_t>(info.index)].source;
    const std::string textureName = "texture " + std::to_string(info.index);
    // A texture without a source names its image only through an extension (KTX2, WebP…), which we cannot decode.
    if (imageIndex < 0) fail(path_, textureName + " has no image in a format we can read (PNG or JPEG)");
    checkIndex(imageIndex, model_.images.size(), "image", textureName);
    if (const auto cached = textureCache_.find(imageIndex); cached != textureCache_.end()) return cached->second;

    const tinygltf::Image& image = model_.images[static_cast<size_t>(imageIndex)];
    const std::string imageName = "image " + std::to_string(imageIndex) + " ('" +
                                  (image.uri.empty() || image.uri.starts_with("data:") ? image.name : image.uri) + "')";
    if (image.image.empty() || image.width <= 0 || image.height <= 0) {
      fail(path_, imageName + " could not be read or decoded");
    }
    if (image.bits != 8)
      fail(path_, imageName + " has " + std::to_string(image.bits) + "-bit channels; only 8-bit is supported");
    // tinygltf's image loader expands grey, grey+alpha and RGB images to RGBA.
    const auto width = static_cast<uint32_t>(image.width);
    const auto height = static_cast<uint32_t>(image.height);
    if (image.component != 4 || image.image.size() != size_t{width} * height * 4) {
      fail(path_, imageName + " was not decoded to 8-bit RGBA");
    }
    scene_.textures.push_back(
        {.name = image.name.empty() ? image.uri : image.name, .width = width, .height = height, .rgba = image.image});
    const auto texture = static_cast<uint32_t>(scene_.textures.size() - 1);
    textureCache_.emplace(imageIndex, texture);
    return texture;
  }

  void addCamera(const tinygltf::Camera& source, const tinygltf::Node& node, const glm::mat4& world) {
    // Our renderer draws perspective views only.
    if (source.type != "perspective") return;
    Camera camera;
    camera.name = source.name.empty() ? node.name : source.name;
    camera.position = glm::vec3(world[3]);
    camera.target =
        camera.position + normalizedOr(glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f), {0.0f, 0.0f, -1.0f});
    camera.up = normalizedOr(glm::mat3(world) * glm::vec3(0.0f, 1.0f, 0.0f), {0.0f, 1.0f, 0.0f});
    if (source.perspective.yfov > 0.0) camera.verticalFov = static_cast<float>(source.perspective.yfov);
    if (source.perspective.znear > 0.0) camera.nearPlane = static_cast<float>(source.perspective.znear);
    scene_.cameras.push_back(std::move(camera));
  }

  // KHR_lights_punctual: lights shine along the node's −Z. Intensities are used as given (candela as W/sr, lux as
  // W/m²).
  void addLight(const tinygltf::Light& source, const tinygltf::Node& node, const glm::mat4& world) {
    const glm::vec3 intensity = rgbOr(source.color, glm::vec3(1.0f)) * static_cast<float>(source.intensity);
    const glm::vec3 forward = normalizedOr(glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f), {0.0f, 0.0f, -1.0f});
    const std::string name = source.name.empty() ? node.name : source.name;
    if (source.type == "directional") {
      // The scene has one sun: the first directional light.
      if (!scene_.sun.enabled) scene_.sun = {.enabled = true, .direction = -forward, .illuminance = intensity};
      return;
    }
    LocalLight light{.name = name,
                     .position = glm::vec3(world[3]),
                     .direction = forward,
                     .intensity = intensity,
                     .range = static_cast<float>(source.range)};
    if (source.type == "spot") {
      light.type = LightType::Spot;
      light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
      light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
    } else if (source.type != "point") {
      fail(path_, "light '" + name + "' has the unknown type '" + source.type + "'");
    }
    scene_.lights.push_back(std::move(light));
  }

  // A view of the whole scene from its front (+Z) and a little above, for files without a camera.
  static Camera cameraFraming(const Bounds& bounds) {
    Camera camera;
    camera.name = "framing";
    const glm::vec3 center = 0.5f * (bounds.min + bounds.max);
    const float radius = std::max(0.5f * glm::length(bounds.max - bounds.min), 1e-3f);
    const float distance = radius / std::sin(0.5f * camera.verticalFov);
    camera.target = center;
    camera.position = center + glm::normalize(glm::vec3(0.0f, 0.35f, 1.0f)) * distance;
    camera.nearPlane = std::min(camera.nearPlane, 0.01f * distance);
    return camera;
  }

  const tinygltf::Model& model_;
  const std::filesystem::path path_;
  Scene scene_;
  std::vector<bool> visited_;
  std::map<std::pair<int, bool>, std::vector<uint32_t>> meshCache_;  // (glTF mesh, mirrored) → our meshes
  std::map<int, uint32_t> textureCache_;                             // glTF image → Scene::textures
  std::optional<uint32_t> defaultMaterial_;
};

}  // namespace

Scene loadGltf(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) fail(path, "file not found");
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string problems;
  std::string warnings;  // unknown extensions, unused data: the file still loads
  bool loaded = false;
  if (extension == ".glb") {
    loaded = loader.LoadBinaryFromFile(&model, &problems, &warnings, path.string());
  } else if (extension == ".gltf") {
    loaded = loader.LoadASCIIFromFile(&model, &problems, &warnings, path.string());
  } else {
    fail(path, "not a glTF file (expected .gltf or .glb)");
  }
  if (!loaded) fail(path, problems.empty() ? "could not be parsed" : problems);

  Scene scene = GltfConverter(model, path).convert();
  scene.name = path.stem().string();
  return scene;
}

}  // namespace ssvgi::renderer
