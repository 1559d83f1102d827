// The glTF loader: the shared Cornell box files, small files written by the tests for each feature, and broken or
// hostile files, each of which must fail with one line naming the file and the object, or load with finite values.
#include "gltf_loader.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace ssvgi::renderer {
namespace {

namespace fs = std::filesystem;

constexpr float kTolerance = 1e-4f;

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = kTolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

glm::vec3 worldPosition(const glm::mat4& transform, const glm::vec3& position) {
  return glm::vec3(transform * glm::vec4(position, 1.0f));
}

// ---- The Cornell box files in the shared folder (numbers read from their JSON) ----

const fs::path kCornellFolder = fs::path(SSVGI_SHARED_DIR) / "scenes" / "cornell-box";

TEST(GltfCornellBox, loadsEveryPrimitiveMaterialAndTheCamera) {
  const Scene scene = loadGltf(kCornellFolder / "CornellBox-Original.gltf");
  // One mesh of 8 primitives, each with its own material; one node with the mesh, one with the camera.
  const std::vector<std::string> materialNames = {"floor",    "ceiling",  "backWall", "rightWall",
                                                  "leftWall", "shortBox", "tallBox",  "light"};
  ASSERT_EQ(scene.materials.size(), materialNames.size());
  for (size_t i = 0; i < materialNames.size(); ++i) EXPECT_EQ(scene.materials[i].name, materialNames[i]);
  ASSERT_EQ(scene.meshes.size(), 8u);
  ASSERT_EQ(scene.instances.size(), 8u);
  const std::vector<size_t> vertexCounts = {4, 4, 4, 4, 4, 20, 20, 4};
  const std::vector<size_t> indexCounts = {6, 6, 6, 6, 6, 30, 30, 6};
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    EXPECT_EQ(scene.meshes[i].material, i);
    EXPECT_EQ(scene.meshes[i].vertices.size(), vertexCounts[i]) << i;
    EXPECT_EQ(scene.meshes[i].indices.size(), indexCounts[i]) << i;
    EXPECT_EQ(scene.instances[i].transform, glm::mat4(1.0f));
  }
  expectNear(scene.materials[4].baseColor, {1.0f, 0.065f, 0.05f});
  expectNear(scene.materials[3].baseColor, {0.14f, 0.45f, 0.091f});
  expectNear(scene.materials[0].emission, glm::vec3(0.0f));
  expectNear(scene.materials[7].emission, glm::vec3(1.0f, 0.7058824f, 0.2352941f) * 17.0f);

  const Bounds bounds = worldBounds(scene);
  expectNear(bounds.min, {-1.02f, 0.0f, -1.04f}, 1e-3f);
  expectNear(bounds.max, {1.0f, 1.99f, 0.99f}, 1e-3f);
  EXPECT_EQ(scene.giDetailScale, 0.5f);  // a 2 m box, as the built-in cornell

  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& camera = scene.cameras[0];
  EXPECT_EQ(camera.name, "classic");
  expectNear(camera.position, {0.0f, 1.0f, 3.87f});
  expectNear(camera.target, {0.0f, 1.0f, 2.87f});
  expectNear(camera.up, {0.0f, 1.0f, 0.0f});
  EXPECT_NEAR(camera.verticalFov, 0.6859f, kTolerance);
  EXPECT_NEAR(camera.nearPlane, 0.05f, kTolerance);

  EXPECT_TRUE(scene.lights.empty());
  EXPECT_FALSE(scene.sun.enabled);
  EXPECT_EQ(scene.sky.kind, SkyKind::None);
  EXPECT_EQ(scene.name, "CornellBox-Original");
}

TEST(GltfCornellBox, pointLightVariantGivesTheLightItDeclares) {
  const Scene scene = loadGltf(kCornellFolder / "CornellBox-PointLight.gltf");
  ASSERT_EQ(scene.lights.size(), 1u);
  const LocalLight& light = scene.lights[0];
  EXPECT_EQ(light.name, "ceiling_point");
  EXPECT_EQ(light.type, LightType::Point);
  expectNear(light.position, {0.0f, 1.85f, -0.03f});
  expectNear(light.intensity, glm::vec3(1.0f, 0.85f, 0.6f) * 10.0f);
  EXPECT_EQ(light.range, 0.0f);
  EXPECT_EQ(scene.meshes.size(), 8u);
}

// ---- Files written by the tests ----

class GltfFiles : public testing::Test {
 protected:
  void SetUp() override {
    const testing::TestInfo* test = testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() / ("ssvgi_gltf_" + std::string(test->name()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path write(const std::string& name, const std::string& bytes) const {
    const fs::path path = folder_ / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  // The message of the SceneLoadError that loading `path` must throw, checked to be one line naming the file.
  static std::string loadError(const fs::path& path) {
    try {
      loadGltf(path);
    } catch (const SceneLoadError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      return message;
    }
    ADD_FAILURE() << path << " loaded";
    return {};
  }

  fs::path folder_;
};

// Little-endian bytes for a buffer.
template <typename T>
void append(std::string& bytes, std::initializer_list<T> values) {
  for (const T value : values) bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

std::string base64(const std::string& bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t group = static_cast<uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    if (i + 1 < bytes.size()) group |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) group |= static_cast<unsigned char>(bytes[i + 2]);
    for (size_t digit = 0; digit < 4; ++digit) {
      text += i + digit <= bytes.size() ? kDigits[(group >> (18 - 6 * digit)) & 63u] : '=';
    }
  }
  return text;
}

std::string dataUri(const std::string& bytes) { return "data:application/octet-stream;base64," + base64(bytes); }

// One triangle, corners (0,0,0), (1,0,0), (0,1,0) (counter-clockwise seen from +Z): 36 bytes of positions, then
// three 16-bit indices and 2 bytes of padding.
std::string triangleBuffer() {
  std::string bytes;
  append<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  append<uint16_t>(bytes, {0, 1, 2, 0});
  return bytes;
}

// A glTF document drawing the triangle (no normals, no material) with the given nodes and buffer URI; `extra` adds
// top-level members (cameras, extensions…).
std::string triangleDocument(const std::string& nodes, const std::string& bufferUri, const std::string& extra = "") {
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": )" + nodes + R"(,
  "meshes": [{"name": "triangle", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "buffers": [{"byteLength": 44, "uri": ")" +
         bufferUri + "\"}]" + extra + "}";
}

// A 2×1 8-bit greyscale PNG with the values 0 and 200, as a data URI.
const std::string kGreyPng =
    "data:image/"
    "png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAAAAADRSSBWAAAAC0lEQVR4nGNgOAEAAMsAyWnIw2wAAAAASUVORK5CYII=";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST_F(GltfFiles, flattensTheNodeHierarchyWithTrsAndMatrices) {
  // Node 0 moves by (10, 0, 0) and holds node 1, turned a quarter about +Y, which holds node 2, scaled ×2 by a matrix.
  const std::string nodes = R"([{"translation": [10, 0, 0], "children": [1]},
      {"rotation": [0, 0.7071068, 0, 0.7071068], "mesh": 0, "children": [2]},
      {"matrix": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 5, 0, 1], "mesh": 0}])";
  const Scene scene = loadGltf(write("tree.gltf", triangleDocument(nodes, dataUri(triangleBuffer()))));
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.instances[0].mesh, scene.instances[1].mesh);
  // A quarter turn about +Y takes +X to −Z.
  expectNear(worldPosition(scene.instances[0].transform, {1.0f, 0.0f, 0.0f}), {10.0f, 0.0f, -1.0f});
  expectNear(worldPosition(scene.instances[1].transform, {1.0f, 0.0f, 0.0f}), {10.0f, 5.0f, -2.0f});
  // No material: glTF's default, white.
  ASSERT_EQ(scene.materials.size(), 1u);
  expectNear(scene.materials[0].baseColor, glm::vec3(1.0f));
  EXPECT_EQ(scene.meshes[0].material, 0u);
}

TEST_F(GltfFiles, givesFlatNormalsWhenTheFileHasNone) {
  const Scene scene = loadGltf(write("flat.gltf", triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()))));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.vertices.size(), 3u);
  for (const Vertex& vertex : mesh.vertices) expectNear(vertex.normal, {0.0f, 0.0f, 1.0f});
  expectNear(mesh.vertices[mesh.indices[1]].position, {1.0f, 0.0f, 0.0f});
}

TEST_F(GltfFiles, stripsAndFansBecomeTrianglesWithTheirWinding) {
  // The unit square at z = 0 as corners (0,0), (1,0), (0,1), (1,1): a strip in that order, a fan from (0,0) by the
  // indices 0, 1, 3, 2, and the strip again without indices. Counter-clockwise seen from +Z, each triangle of them:
  // the flat normals (the file has none) come out +Z where the winding is kept, −Z where a triangle is turned.
  std::string bytes;
  append<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  append<uint16_t>(bytes, {0, 1, 2, 3, 0, 1, 3, 2});
  const std::string document =
      R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 5},
                               {"attributes": {"POSITION": 0}, "indices": 2, "mode": 6},
                               {"attributes": {"POSITION": 0}, "mode": 5}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 4, "type": "SCALAR"},
                  {"bufferView": 1, "byteOffset": 8, "componentType": 5123, "count": 4, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 16}],
    "buffers": [{"byteLength": 64, "uri": ")" + dataUri(bytes) + "\"}]}";
  const Scene scene = loadGltf(write("strips.gltf", document));
  ASSERT_EQ(scene.meshes.size(), 3u);
  for (const Mesh& mesh : scene.meshes) {
    ASSERT_EQ(mesh.indices.size(), 6u) << mesh.name;
    float area = 0.0f;
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
      const glm::vec3 a = mesh.vertices[mesh.indices[i]].position, b = mesh.vertices[mesh.indices[i + 1]].position,
                      c = mesh.vertices[mesh.indices[i + 2]].position;
      area += 0.5f * glm::cross(b - a, c - a).z;  // signed: negative for a turned triangle
      expectNear(mesh.vertices[mesh.indices[i]].normal, {0.0f, 0.0f, 1.0f});
    }
    EXPECT_NEAR(area, 1.0f, kTolerance) << mesh.name << ": the two triangles cover the square once";
  }
}

TEST_F(GltfFiles, maskedMaterialsCutOutWhereTheTexturesAlphaFallsBelowTheCutoffOverTheFactorsAlpha) {
  // glTF's MASK: no surface where baseColorFactor's alpha × the texture's is below alphaCutoff (0.5 unless given), so
  // the texture's alpha is compared with alphaCutoff / the factor's alpha. BLEND (no transparency here) is cut out
  // below one half, whatever alphaCutoff says; OPAQUE cuts nothing. A factor whose alpha no texture can lift to the
  // cutoff cuts everything out (anything above 1).
  const std::string materials = R"(, "materials": [
      {"alphaMode": "MASK", "alphaCutoff": 0.25, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5]}},
      {"alphaMode": "MASK"},
      {"alphaMode": "BLEND", "alphaCutoff": 0.7},
      {"alphaCutoff": 0.7},
      {"alphaMode": "MASK", "alphaCutoff": 0.6, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.25]}},
      {"alphaMode": "MASK", "alphaCutoff": 0},
      {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.9}}},
      {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.3}}}])";
  const std::string document = triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()), materials);
  const Scene scene = loadGltf(write("masked.gltf", document));
  ASSERT_EQ(scene.materials.size(), 9u);  // and glTF's default material, for the triangle, which names none
  EXPECT_FLOAT_EQ(scene.materials[0].alphaCutoff, 0.5f);
  EXPECT_FLOAT_EQ(scene.materials[1].alphaCutoff, 0.5f);
  EXPECT_FLOAT_EQ(scene.materials[2].alphaCutoff, 0.5f);
  EXPECT_EQ(scene.materials[3].alphaCutoff, 0.0f);
  EXPECT_GT(scene.materials[4].alphaCutoff, 1.0f);
  EXPECT_EQ(scene.materials[5].alphaCutoff, 0.0f);
  // A material that transmits more than half the light is cut out everywhere (no transparency here either).
  EXPECT_GT(scene.materials[6].alphaCutoff, 1.0f);
  EXPECT_EQ(scene.materials[7].alphaCutoff, 0.0f);
  EXPECT_EQ(scene.materials[8].alphaCutoff, 0.0f);

  const std::string unknownMode = replaced(document, R"("alphaMode": "BLEND")", R"("alphaMode": "CUTOUT")");
  const std::string message = loadError(write("unknown-mode.gltf", unknownMode));
  EXPECT_NE(message.find("materials[2].alphaMode"), std::string::npos) << message;
  const std::string negative = replaced(document, R"("alphaCutoff": 0.25)", R"("alphaCutoff": -0.25)");
  EXPECT_NE(loadError(write("negative-cutoff.gltf", negative)).find("alphaCutoff"), std::string::npos);
  const std::string overOne = replaced(document, R"("transmissionFactor": 0.9)", R"("transmissionFactor": 1.5)");
  EXPECT_NE(loadError(write("transmission.gltf", overOne)).find("materials[6].extensions.KHR_materials_transmission"),
            std::string::npos);
}

TEST_F(GltfFiles, mirroredInstanceGetsReversedWindingSoFrontFacesStayFront) {
  const std::string nodes = R"([{"children": [1, 2]}, {"mesh": 0}, {"scale": [-1, 1, 1], "mesh": 0}])";
  const Scene scene = loadGltf(write("mirror.gltf", triangleDocument(nodes, dataUri(triangleBuffer()))));
  ASSERT_EQ(scene.instances.size(), 2u);
  for (const Instance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    const glm::vec3 a = worldPosition(instance.transform, mesh.vertices[mesh.indices[0]].position);
    const glm::vec3 b = worldPosition(instance.transform, mesh.vertices[mesh.indices[1]].position);
    const glm::vec3 c = worldPosition(instance.transform, mesh.vertices[mesh.indices[2]].position);
    // The world-space winding agrees with the normal transformed to world space (inverse transpose).
    const glm::vec3 normal = glm::transpose(glm::inverse(glm::mat3(instance.transform))) * mesh.vertices[0].normal;
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), normal), 0.0f);
  }
}

// The triangle with lights and a camera. Node 1: a spot at (0, 4, 0) turned −90° about +X, which takes −Z to −Y: it
// looks down. Node 2: the sun, turned alike, shining straight down. Node 3: a camera at (0, 1, 5) looking down −Z.
std::string litDocument() {
  const std::string nodes = R"([{"mesh": 0, "children": [1, 2, 3]},
      {"translation": [0, 4, 0], "rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 0}}},
      {"rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 1}}},
      {"name": "eye", "translation": [0, 1, 5], "camera": 0}])";
  const std::string extra = R"(, "extensions": {"KHR_lights_punctual": {"lights": [
      {"name": "lamp", "type": "spot", "color": [1, 0.5, 0.25], "intensity": 8, "range": 12,
       "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
      {"type": "directional", "color": [1, 1, 0.5], "intensity": 3}]}},
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.1}}])";
  return triangleDocument(nodes, dataUri(triangleBuffer()), extra);
}

// A GLB file: the header, the JSON chunk padded with spaces and, when there is one, the binary chunk.
std::string glbFile(const std::string& json, const std::string& bin, uint32_t version = 2) {
  std::string paddedJson = json;
  while (paddedJson.size() % 4 != 0) paddedJson += ' ';
  const size_t binChunkBytes = bin.empty() ? 0 : 8 + bin.size();
  std::string glb = "glTF";
  append<uint32_t>(glb, {version, static_cast<uint32_t>(12 + 8 + paddedJson.size() + binChunkBytes)});
  append<uint32_t>(glb, {static_cast<uint32_t>(paddedJson.size()), 0x4E4F534Au});  // "JSON"
  glb += paddedJson;
  if (!bin.empty()) {
    append<uint32_t>(glb, {static_cast<uint32_t>(bin.size()), 0x004E4942u});  // "BIN"
    glb += bin;
  }
  return glb;
}

TEST_F(GltfFiles, readsPunctualLightsAndNodeCamerasInWorldSpace) {
  const Scene scene = loadGltf(write("lights.gltf", litDocument()));

  ASSERT_EQ(scene.lights.size(), 1u);
  const LocalLight& spot = scene.lights[0];
  EXPECT_EQ(spot.name, "lamp");
  EXPECT_EQ(spot.type, LightType::Spot);
  expectNear(spot.position, {0.0f, 4.0f, 0.0f});
  expectNear(spot.direction, {0.0f, -1.0f, 0.0f});
  expectNear(spot.intensity, {8.0f, 4.0f, 2.0f});
  EXPECT_FLOAT_EQ(spot.range, 12.0f);
  EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.2f);
  EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.6f);

  EXPECT_TRUE(scene.sun.enabled);
  expectNear(scene.sun.direction, {0.0f, 1.0f, 0.0f});
  expectNear(scene.sun.illuminance, {3.0f, 3.0f, 1.5f});

  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_EQ(scene.cameras[0].name, "eye");
  expectNear(scene.cameras[0].position, {0.0f, 1.0f, 5.0f});
  expectNear(scene.cameras[0].target, {0.0f, 1.0f, 4.0f});
  EXPECT_FLOAT_EQ(scene.cameras[0].verticalFov, 0.9f);
  EXPECT_FLOAT_EQ(scene.cameras[0].nearPlane, 0.1f);
}

TEST_F(GltfFiles, addsACameraFramingTheSceneWhenTheFileHasNone) {
  const Scene scene = loadGltf(write("nocamera.gltf", triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()))));
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& camera = scene.cameras[0];
  expectNear(camera.target, {0.5f, 0.5f, 0.0f});
  // The whole triangle lies inside the view cone.
  const glm::vec3 forward = glm::normalize(camera.target - camera.position);
  for (const glm::vec3 corner : {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)}) {
    const float angle = std::acos(glm::dot(glm::normalize(corner - camera.position), forward));
    EXPECT_LT(angle, 0.5f * camera.verticalFov);
  }
}

TEST_F(GltfFiles, readsInterleavedVerticesByteIndicesAndMaterialsFromGlb) {
  // A quad: position + normal interleaved with a 24-byte stride, normalized 8-bit texture coordinates with a 4-byte
  // stride, 8-bit indices. The JSON chunk references the GLB's binary chunk.
  std::string bin;
  for (const glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
    append<float>(bin, {corner.x, 0.0f, -corner.y, 0.0f, 2.0f, 0.0f});  // unnormalized normal on purpose
  }
  append<uint8_t>(bin, {0, 0, 0, 0, 255, 0, 0, 0, 255, 255, 0, 0, 0, 255, 0, 0});
  append<uint8_t>(bin, {0, 1, 2, 0, 2, 3, 0, 0});
  const std::string json =
      R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0},
                               {"attributes": {"POSITION": 0}, "mode": 0}]}],
    "materials": [{"name": "glowing", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 0.125, 1]},
                   "emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]},
                  {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC3"},
                  {"bufferView": 1, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5121, "count": 6, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96, "byteStride": 24},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 16, "byteStride": 4},
                    {"buffer": 0, "byteOffset": 112, "byteLength": 6}],
    "buffers": [{"byteLength": 120}]})";
  const Scene scene = loadGltf(write("quad.glb", glbFile(json, bin)));
  // The points primitive is skipped.
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  expectNear(mesh.vertices[2].position, {1.0f, 0.0f, -1.0f});
  expectNear(mesh.vertices[2].normal, {0.0f, 1.0f, 0.0f});
  EXPECT_FLOAT_EQ(mesh.vertices[2].uv.x, 1.0f);
  EXPECT_FLOAT_EQ(mesh.vertices[2].uv.y, 1.0f);
  EXPECT_FLOAT_EQ(mesh.vertices[1].uv.y, 0.0f);
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "glowing");
  expectNear(scene.materials[0].baseColor, {0.5f, 0.25f, 0.125f});
  expectNear(scene.materials[0].emission, {4.0f, 2.0f, 0.0f});
  EXPECT_EQ(scene.materials[0].baseColorTexture, kNoTexture);
}

TEST_F(GltfFiles, storesBaseColorTexturesAsRgba8EvenFromGreyImages) {
  std::string document =
      triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()),
                       R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
      "textures": [{"source": 0}], "images": [{"name": "grey", "uri": ")" +
                           kGreyPng + "\"}]");
  document = replaced(document, R"("indices": 1})", R"("indices": 1, "material": 0})");
  const Scene scene = loadGltf(write("textured.gltf", document));
  ASSERT_EQ(scene.textures.size(), 1u);
  const Texture& texture = scene.textures[0];
  EXPECT_EQ(texture.name, "grey");
  EXPECT_EQ(texture.width, 2u);
  EXPECT_EQ(texture.height, 1u);
  EXPECT_EQ(texture.rgba, (std::vector<uint8_t>{0, 0, 0, 255, 200, 200, 200, 255}));
  EXPECT_EQ(scene.materials[0].baseColorTexture, 0u);
}

TEST_F(GltfFiles, emissionTexturesScaleTheEmissiveFactorAndAreNotLoadedWhereNothingEmits) {
  // The same 2×1 PNG as the emissive texture of a material that emits and of one whose emissiveFactor is glTF's
  // default, black: the texture multiplies the factor, so only the first needs it.
  std::string document =
      triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()),
                       R"(, "materials": [{"emissiveFactor": [1, 0.5, 0], "emissiveTexture": {"index": 0}},
                                          {"emissiveTexture": {"index": 0}}],
      "textures": [{"source": 0}], "images": [{"name": "grey", "uri": ")" +
                           kGreyPng + "\"}]");
  document = replaced(document, R"("indices": 1})", R"("indices": 1, "material": 0})");
  const Scene scene = loadGltf(write("emissive.gltf", document));
  ASSERT_EQ(scene.textures.size(), 1u);
  expectNear(scene.materials[0].emission, {1.0f, 0.5f, 0.0f});
  EXPECT_EQ(scene.materials[0].emissionTexture, 0u);
  EXPECT_EQ(scene.materials[0].baseColorTexture, kNoTexture);
  expectNear(scene.materials[1].emission, glm::vec3(0.0f));
  EXPECT_EQ(scene.materials[1].emissionTexture, kNoTexture);
  const std::string message =
      loadError(write("missing.gltf", replaced(document, R"("emissiveTexture": {"index": 0}},)",
                                               R"("emissiveTexture": {"index": 3}},)")));
  EXPECT_NE(message.find("materials[0].emissiveTexture"), std::string::npos) << message;
}

TEST_F(GltfFiles, textureTransformsMoveTheTextureCoordinates) {
  // KHR_texture_transform: uv' = T·R·S·uv. With offset (0.5, 0), rotation π/2 and scale (2, 3), u' = 3v + 0.5 and
  // v' = −2u: the corners' (1, 0) and (0, 1) go to (0.5, −2) and (3.5, 0).
  std::string bytes;
  append<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  append<float>(bytes, {0, 0, 1, 0, 0, 1});
  append<uint16_t>(bytes, {0, 1, 2, 0});
  const std::string document =
      R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "extensionsRequired": ["KHR_texture_transform"],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
                   {"offset": [0.5, 0], "rotation": 1.5707963267948966, "scale": [2, 3]}}}}}],
    "textures": [{"source": 0}], "images": [{"uri": ")" + kGreyPng + R"("}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 60, "byteLength": 6}],
    "buffers": [{"byteLength": 68, "uri": ")" + dataUri(bytes) + "\"}]}";
  const Scene scene = loadGltf(write("transformed.gltf", document));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.vertices.size(), 3u);  // flat normals: a vertex per corner, in order
  const std::array<glm::vec2, 3> expected = {glm::vec2(0.5f, 0.0f), glm::vec2(0.5f, -2.0f), glm::vec2(3.5f, 0.0f)};
  for (size_t corner = 0; corner < 3; ++corner) {
    EXPECT_NEAR(mesh.vertices[mesh.indices[corner]].uv.x, expected[corner].x, kTolerance) << corner;
    EXPECT_NEAR(mesh.vertices[mesh.indices[corner]].uv.y, expected[corner].y, kTolerance) << corner;
  }
  // Coordinates no float holds after the transform are refused.
  const std::string huge = replaced(document, R"("scale": [2, 3])", R"("scale": [2, 3e38])");
  EXPECT_NE(loadError(write("huge.gltf", replaced(huge, R"("offset": [0.5, 0])", R"("offset": [3e38, 0])")))
                .find("KHR_texture_transform"),
            std::string::npos);
}

TEST_F(GltfFiles, vertexColoursAreReadFromRgbOrRgbaAndKeptWithinZeroToOne) {
  // COLOR_0 as normalized 8-bit RGBA (alpha not used) and as float RGB, one value above 1, which is clamped.
  std::string bytes;
  append<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  append<uint16_t>(bytes, {0, 1, 2, 0});
  append<uint8_t>(bytes, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 51, 0});
  append<float>(bytes, {0.25f, 0.5f, 0.75f, 1.5f, 0, 0, 0, 0, 1});
  const std::string document =
      R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 2}, "indices": 1},
                               {"attributes": {"POSITION": 0, "COLOR_0": 3}, "indices": 1}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
                  {"bufferView": 2, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC4"},
                  {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6},
                    {"buffer": 0, "byteOffset": 44, "byteLength": 12}, {"buffer": 0, "byteOffset": 56, "byteLength": 36}],
    "buffers": [{"byteLength": 92, "uri": ")" + dataUri(bytes) + "\"}]}";
  const Scene scene = loadGltf(write("coloured.gltf", document));
  ASSERT_EQ(scene.meshes.size(), 2u);
  // Flat normals: a vertex per corner, in order.
  const std::array<glm::vec3, 3> bytesRead = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 0.2f)};
  const std::array<glm::vec3, 3> floatsRead = {glm::vec3(0.25f, 0.5f, 0.75f), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)};
  for (size_t corner = 0; corner < 3; ++corner) {
    expectNear(scene.meshes[0].vertices[scene.meshes[0].indices[corner]].color, bytesRead[corner]);
    expectNear(scene.meshes[1].vertices[scene.meshes[1].indices[corner]].color, floatsRead[corner]);
  }
  const std::string twoComponents = replaced(document, R"("count": 3, "type": "VEC3"}],)", R"("count": 3, "type": "VEC2"}],)");
  EXPECT_NE(loadError(write("two.gltf", twoComponents)).find("COLOR_0 has 2 components"), std::string::npos);
}

TEST_F(GltfFiles, theMeshCarriesTheTextureCoordinateSetItsTextureNames) {
  // The base colour texture names TEXCOORD_1 (texCoord 1): the mesh carries that set, not TEXCOORD_0.
  std::string bytes;
  append<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  append<float>(bytes, {9, 9, 9, 9, 9, 9});
  append<float>(bytes, {0.25f, 0.5f, 0.75f, 1, 0, 0});
  append<uint16_t>(bytes, {0, 1, 2, 0});
  const std::string document =
      R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2}, "indices": 3,
                                "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}],
    "textures": [{"source": 0}], "images": [{"uri": ")" + kGreyPng + R"("}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
                  {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 60, "byteLength": 24}, {"buffer": 0, "byteOffset": 84, "byteLength": 6}],
    "buffers": [{"byteLength": 92, "uri": ")" + dataUri(bytes) + "\"}]}";
  const Scene scene = loadGltf(write("second-set.gltf", document));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  const std::array<glm::vec2, 3> expected = {glm::vec2(0.25f, 0.5f), glm::vec2(0.75f, 1.0f), glm::vec2(0.0f, 0.0f)};
  for (size_t corner = 0; corner < 3; ++corner) {
    EXPECT_FLOAT_EQ(mesh.vertices[mesh.indices[corner]].uv.x, expected[corner].x) << corner;
    EXPECT_FLOAT_EQ(mesh.vertices[mesh.indices[corner]].uv.y, expected[corner].y) << corner;
  }
}

// ---- Broken files ----

TEST_F(GltfFiles, missingFileIsAnError) {
  const std::string message = loadError(folder_ / "absent.gltf");
  EXPECT_NE(message.find("not found"), std::string::npos) << message;
}

TEST_F(GltfFiles, malformedJsonIsAnError) {
  loadError(write("malformed.gltf", R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0},)"));
}

TEST_F(GltfFiles, missingBufferFileIsAnError) {
  loadError(write("nobuffer.gltf", triangleDocument(R"([{"mesh": 0}])", "absent.bin")));
}

TEST_F(GltfFiles, bufferTooShortForAnAccessorIsAnError) {
  // The buffer file holds 20 of the 42 bytes the buffer views cover.
  write("short.bin", triangleBuffer().substr(0, 20));
  const std::string shortBuffer =
      replaced(triangleDocument(R"([{"mesh": 0}])", "short.bin"), R"("byteLength": 44)", R"("byteLength": 20)");
  const std::string message = loadError(write("short.gltf", shortBuffer));
  EXPECT_NE(message.find("bufferViews[0]"), std::string::npos) << message;
  // The buffer is whole but an accessor claims more elements than its view holds.
  const std::string longAccessor = replaced(triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer())),
                                            R"("count": 3, "type": "VEC3")", R"("count": 300, "type": "VEC3")");
  EXPECT_NE(loadError(write("long.gltf", longAccessor)).find("accessors[0]"), std::string::npos);
}

TEST_F(GltfFiles, accessorIndexOutOfRangeIsAnError) {
  const std::string document =
      replaced(triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer())), R"("POSITION": 0)", R"("POSITION": 7)");
  const std::string message = loadError(write("badaccessor.gltf", document));
  EXPECT_NE(message.find("accessors[7]"), std::string::npos) << message;
}

TEST_F(GltfFiles, indexBeyondTheVerticesIsAnError) {
  std::string buffer = triangleBuffer();
  buffer[38] = 9;  // the second index
  loadError(write("badindex.gltf", triangleDocument(R"([{"mesh": 0}])", dataUri(buffer))));
}

TEST_F(GltfFiles, glbWithABadHeaderIsAnError) {
  std::string glb = "glTX";
  append<uint32_t>(glb, {2, 64, 0, 0});
  glb.resize(64, ' ');
  loadError(write("badheader.glb", glb));
}

TEST_F(GltfFiles, fileWithoutTrianglesIsAnError) {
  const std::string points = replaced(triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer())),
                                      R"("indices": 1})", R"("indices": 1, "mode": 0})");
  const std::string message = loadError(write("points.gltf", points));
  EXPECT_NE(message.find("no triangle"), std::string::npos) << message;
}

TEST_F(GltfFiles, undecodableImageIsAnError) {
  std::string document =
      triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()),
                       R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
      "textures": [{"source": 0}], "images": [{"uri": "absent.png"}])");
  document = replaced(document, R"("indices": 1})", R"("indices": 1, "material": 0})");
  const std::string message = loadError(write("noimage.gltf", document));
  EXPECT_NE(message.find("absent.png"), std::string::npos) << message;
}

// ---- Hostile files: one line naming the object, or a scene that renders finite ----

// The triangle with a normal and texture coordinates per corner: positions (36 bytes), normals (36), texture
// coordinates (24), then three 16-bit indices and 2 bytes of padding.
std::string triangleWithAttributes(const std::array<glm::vec3, 3>& normals, const std::array<glm::vec2, 3>& uvs) {
  std::string bytes;
  append<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  for (const glm::vec3& normal : normals) append<float>(bytes, {normal.x, normal.y, normal.z});
  for (const glm::vec2& uv : uvs) append<float>(bytes, {uv.x, uv.y});
  append<uint16_t>(bytes, {0, 1, 2, 0});
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
                {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 72, "byteLength": 24}, {"buffer": 0, "byteOffset": 96, "byteLength": 6}],
  "buffers": [{"byteLength": 104, "uri": ")" +
         dataUri(bytes) + "\"}]}";
}

constexpr std::array<glm::vec2, 3> kUvs = {glm::vec2(0.0f), glm::vec2(1.0f, 0.0f), glm::vec2(0.0f, 1.0f)};
constexpr std::array<glm::vec3, 3> kNormals = {glm::vec3(0, 0, 1), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)};

// A file, and what the one line refusing it must name.
struct RefusedFile {
  std::string name;
  std::string document;
  std::string named;
};

class HostileGltfFiles : public GltfFiles {
 protected:
  void expectRefused(const std::vector<RefusedFile>& files) {
    for (const RefusedFile& file : files) {
      SCOPED_TRACE(file.name);
      const std::string message = loadError(write(file.name + ".gltf", file.document));
      EXPECT_NE(message.find(file.named), std::string::npos) << message;
    }
  }
};

TEST_F(HostileGltfFiles, valuesThatWouldRenderNonFiniteAreRefusedNamingTheObject) {
  const std::string triangle = dataUri(triangleBuffer());
  const std::string lit = litDocument();
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto withMaterial = [&](const std::string& material) {
    return triangleDocument(R"([{"mesh": 0}])", triangle, R"(, "materials": [)" + material + "]");
  };
  expectRefused({
      {"infiniteNormal", triangleWithAttributes({glm::vec3(0, 0, 1), glm::vec3(inf, 0, 0), glm::vec3(0, 0, 1)}, kUvs),
       "meshes[0].primitives[0].attributes.NORMAL (accessors[1]) element 1 is inf"},
      {"nanUv", triangleWithAttributes(kNormals, {glm::vec2(0.0f), glm::vec2(nan, 0.0f), glm::vec2(0.0f)}),
       "attributes.TEXCOORD_0 (accessors[2]) element 1 is nan"},
      {"emission", withMaterial(R"({"emissiveFactor": [1e30, 0, 0]})"), "materials[0].emissiveFactor[0] is 1e+30"},
      {"emissiveStrength",
       withMaterial(
           R"({"emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e30}}})"),
       "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength is 1e+30"},
      {"baseColour", withMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [1e30, 1, 1, 1]}})"),
       "materials[0].pbrMetallicRoughness.baseColorFactor[0] is 1e+30"},
      {"projective",
       triangleDocument(R"([{"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0]}])", triangle),
       "nodes[0].matrix is not affine"},
      {"hugeScale", triangleDocument(R"([{"mesh": 0, "scale": [1e30, 1e30, 1e30]}])", triangle),
       "nodes[0] places a vertex of mesh 'triangle' at (1e+30, 0, 0)"},
      {"overflowingScales",
       triangleDocument(R"([{"scale": [1e30, 1, 1], "children": [1]}, {"mesh": 0, "scale": [1e30, 1, 1]}])", triangle),
       "nodes[1] has a world transform that is not finite"},
      {"farAway", triangleDocument(R"([{"mesh": 0, "translation": [0, 2e5, 0]}])", triangle),
       "nodes[0] lies at (0, 200000, 0)"},
      {"beyondFloat", triangleDocument(R"([{"mesh": 0, "translation": [1e300, 0, 0]}])", triangle),
       "nodes[0].translation[0] is 1e+300"},
      {"zeroRotation", triangleDocument(R"([{"mesh": 0, "rotation": [0, 0, 0, 0]}])", triangle),
       "nodes[0].rotation has length 0"},
      {"tinyFieldOfView", replaced(lit, R"("yfov": 0.9)", R"("yfov": 1e-30)"), "cameras[0].perspective.yfov is 1e-30"},
      {"flatCamera", replaced(lit, R"("translation": [0, 1, 5], "camera": 0)", R"("scale": [1, 0, 1], "camera": 0)"),
       "nodes[3] holds a camera"},
      {"brightLight", replaced(lit, R"("intensity": 8)", R"("intensity": 1e10)"),
       "extensions.KHR_lights_punctual.lights[0].intensity is 1e+10"},
      {"flatSpot", replaced(lit, R"("translation": [0, 4, 0])", R"("scale": [1, 1, 0])"),
       "nodes[1] holds a spot light"},
  });
}

TEST_F(HostileGltfFiles, valuesGltfForbidsAreRefusedNamingTheObject) {
  const std::string lit = litDocument();
  const std::string spot = R"("spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6})";
  const std::string camera = R"("perspective": {"yfov": 0.9, "znear": 0.1})";
  expectRefused({
      {"innerBeyondOuter", replaced(lit, spot, R"("spot": {"innerConeAngle": 0.7, "outerConeAngle": 0.6})"),
       "lights[0].spot.innerConeAngle 0.7 is larger than its outerConeAngle 0.6"},
      {"innerBeyondDefaultOuter", replaced(lit, spot, R"("spot": {"innerConeAngle": 1})"),
       "lights[0].spot.innerConeAngle 1"},
      {"outerAtRightAngle", replaced(lit, spot, R"("spot": {"outerConeAngle": 1.5707963267948966})"),
       "lights[0].spot.outerConeAngle is 1.5708"},
      {"negativeIntensity", replaced(lit, R"("intensity": 8)", R"("intensity": -8)"), "lights[0].intensity is -8"},
      {"negativeColour", replaced(lit, R"("color": [1, 0.5, 0.25])", R"("color": [1, -0.5, 0.25])"),
       "lights[0].color[1] is -0.5"},
      {"zeroRange", replaced(lit, R"("range": 12)", R"("range": 0)"), "lights[0].range is 0"},
      {"zeroFieldOfView", replaced(lit, camera, R"("perspective": {"yfov": 0, "znear": 0.1})"),
       "cameras[0].perspective.yfov is 0"},
      {"negativeFieldOfView", replaced(lit, camera, R"("perspective": {"yfov": -1, "znear": 0.1})"),
       "perspective.yfov is -1"},
      {"zeroNear", replaced(lit, camera, R"("perspective": {"yfov": 0.9, "znear": 0})"),
       "cameras[0].perspective.znear is 0"},
      {"zeroAspect", replaced(lit, camera, R"("perspective": {"yfov": 0.9, "znear": 0.1, "aspectRatio": 0})"),
       "cameras[0].perspective.aspectRatio is 0"},
      {"negativeAspect", replaced(lit, camera, R"("perspective": {"yfov": 0.9, "znear": 0.1, "aspectRatio": -1.5})"),
       "perspective.aspectRatio is -1.5"},
      {"unknownRequiredExtension",
       replaced(lit, R"("asset": {"version": "2.0"},)",
                R"("asset": {"version": "2.0"}, "extensionsRequired": ["KHR_draco_mesh_compression"],)"),
       "extensionsRequired lists KHR_draco_mesh_compression"},
  });
  // An extension this loader reads may be required.
  const std::string required =
      replaced(lit, R"("asset": {"version": "2.0"},)",
               R"("asset": {"version": "2.0"}, "extensionsRequired": ["KHR_lights_punctual"],)");
  EXPECT_EQ(loadGltf(write("requiresLights.gltf", required)).lights.size(), 1u);
}

TEST_F(HostileGltfFiles, membersOfTheWrongTypeAreRefusedInsteadOfDefaulted) {
  // tinygltf turns each of these into its default without a word: no field of view, no mesh, no transform.
  const std::string lit = litDocument();
  const std::string triangle = dataUri(triangleBuffer());
  expectRefused({
      {"textFieldOfView", replaced(lit, R"("yfov": 0.9)", R"("yfov": "wide")"),
       R"(cameras[0].perspective.yfov must be a number, not "wide")"},
      {"fractionalIndex", triangleDocument(R"([{"mesh": 0.5}])", triangle), "nodes[0].mesh must be a whole number"},
      {"negativeIndex", triangleDocument(R"([{"mesh": -1}])", triangle), "nodes[0].mesh must be a whole number"},
      {"textTranslation", triangleDocument(R"([{"mesh": 0, "translation": "far"}])", triangle),
       "nodes[0].translation must be an array"},
      {"shortScale", triangleDocument(R"([{"mesh": 0, "scale": [2, 2]}])", triangle),
       "nodes[0].scale holds 2 numbers, not 3"},
      {"booleanIntensity", replaced(lit, R"("intensity": 8)", R"("intensity": true)"),
       "lights[0].intensity must be a number"},
      {"nodeNotAnObject", triangleDocument(R"([{"mesh": 0}, 7])", triangle), "nodes[1] must be an object, not 7"},
  });
}

TEST_F(HostileGltfFiles, aNodeChainTwentyThousandDeepLoads) {
  // Each node 1 mm along +X from its parent; the last holds the mesh. A recursive walk overflowed the stack.
  constexpr int kDepth = 20000;
  std::string nodes = "[";
  for (int node = 0; node + 1 < kDepth; ++node) {
    nodes += R"({"translation": [0.001, 0, 0], "children": [)" + std::to_string(node + 1) + "]},";
  }
  nodes += R"({"translation": [0.001, 0, 0], "mesh": 0}])";
  const Scene scene = loadGltf(write("chain.gltf", triangleDocument(nodes, dataUri(triangleBuffer()))));
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_NEAR(scene.instances[0].transform[3].x, 0.001f * kDepth, 1e-2f);
}

TEST_F(HostileGltfFiles, jsonNestedThirtyThousandDeepIsRefusedInGltfAndGlb) {
  // The parsers recurse once per level of nesting: this overflowed the stack inside tinygltf.
  const std::string deep = std::string(30000, '[') + std::string(30000, ']');
  const std::string document = triangleDocument(R"([{"mesh": 0, "extras": )" + deep + "}]", dataUri(triangleBuffer()));
  EXPECT_NE(loadError(write("deep.gltf", document)).find("nested more than 128 levels"), std::string::npos);
  EXPECT_NE(loadError(write("deep.glb", glbFile(document, ""))).find("nested more than 128 levels"), std::string::npos);
  // Brackets inside strings are text, not nesting.
  const std::string named = triangleDocument(R"([{"mesh": 0, "name": ")" + deep + R"("}])", dataUri(triangleBuffer()));
  EXPECT_EQ(loadGltf(write("named.gltf", named)).instances.size(), 1u);
}

TEST_F(HostileGltfFiles, glbOfAnotherVersionOrWithChunksPastItsEndIsRefused) {
  const std::string document = triangleDocument(R"([{"mesh": 0}])", dataUri(triangleBuffer()));
  EXPECT_EQ(loadGltf(write("version2.glb", glbFile(document, ""))).instances.size(), 1u);
  EXPECT_NE(loadError(write("version1.glb", glbFile(document, "", 1))).find("GLB version 1"), std::string::npos);
  EXPECT_NE(loadError(write("version3.glb", glbFile(document, "", 3))).find("GLB version 3"), std::string::npos);
  // A binary chunk that claims 4 bytes more than the file holds.
  std::string glb = glbFile(document, std::string(8, '\0'));
  const size_t binLength = glb.size() - 8 - 8;
  glb[binLength] = 12;
  EXPECT_NE(loadError(write("longbin.glb", glb)).find("second chunk of 12 bytes reaches past its end"),
            std::string::npos);
}

TEST_F(HostileGltfFiles, referencesLeadingOutOfTheFilesFolderAreRefused) {
  // A viewer of a downloaded file must not read what the file names elsewhere, even a valid buffer.
  const fs::path outside = folder_.parent_path() / ("ssvgi_outside_" + folder_.filename().string() + ".bin");
  std::ofstream(outside, std::ios::binary) << triangleBuffer();
  fs::create_directories(folder_ / "data");
  fs::create_symlink(outside, folder_ / "data" / "link.bin");
  write("data/inside.bin", triangleBuffer());
  const auto withBuffer = [](const std::string& uri) { return triangleDocument(R"([{"mesh": 0}])", uri); };
  expectRefused({
      {"passwd", withBuffer("../../../../etc/passwd"),
       "the URI '../../../../etc/passwd' leads outside the file's folder"},
      {"sibling", withBuffer("../" + outside.filename().string()), "leads outside the file's folder"},
      {"escaped", withBuffer("%2E%2E/" + outside.filename().string()), "leads outside the file's folder"},
      {"symlink", withBuffer("data/link.bin"), "the URI 'data/link.bin' leads outside the file's folder"},
      {"folder", withBuffer("data"), "the URI 'data' names " + (folder_ / "data").string() + ": is a folder"},
  });
  fs::remove(outside);
  // Files in the folder or below it are read, whichever way the URI gets there.
  EXPECT_EQ(loadGltf(write("below.gltf", withBuffer("data/inside.bin"))).instances.size(), 1u);
  EXPECT_EQ(loadGltf(write("roundabout.gltf", withBuffer("data/../data/inside.bin"))).instances.size(), 1u);
}

TEST_F(HostileGltfFiles, odderValuesLoadAsSomethingFinite) {
  // Normals of 1e30 keep their direction; a normal of zero length takes its triangle's face normal (+Z here).
  const Scene huge =
      loadGltf(write("hugeNormals.gltf",
                     triangleWithAttributes({glm::vec3(1e30f, 0, 0), glm::vec3(0, 3e38f, 0), glm::vec3(0.0f)}, kUvs)));
  ASSERT_EQ(huge.meshes.size(), 1u);
  expectNear(huge.meshes[0].vertices[0].normal, {1.0f, 0.0f, 0.0f});
  expectNear(huge.meshes[0].vertices[1].normal, {0.0f, 1.0f, 0.0f});
  expectNear(huge.meshes[0].vertices[2].normal, {0.0f, 0.0f, 1.0f});
  // A node scaled to nothing (glTF's way to hide one) is not drawn; its sibling is.
  const std::string nodes = R"([{"children": [1, 2]}, {"mesh": 0}, {"mesh": 0, "scale": [0, 1, 1]}])";
  EXPECT_EQ(loadGltf(write("hidden.gltf", triangleDocument(nodes, dataUri(triangleBuffer())))).instances.size(), 1u);
}

}  // namespace
}  // namespace ssvgi::renderer
