#include "gltf_loader.h"

#include "image_io.h"

#include <nlohmann/json.hpp>
#include <stb/stb_image.h>
#include <tiny_gltf.h>

#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <span>
#include <string_view>
#include <utility>

namespace ssvgi::renderer {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// The bounds of loadGltf's header comment, which says why each is what it is.
constexpr uint64_t kMaxFileBytes = uint64_t{1} << 30;
constexpr size_t kMaxJsonDepth = 128;
constexpr uint64_t kMaxTexturePixels = uint64_t{8192} * 8192;
constexpr float kMaxCoordinate = 1e5f;  // metres from the origin
constexpr double kMinDeterminant = 1e-24;
constexpr double kMinDirectionSine = 1e-3;  // a camera's view and up directions may not be closer than this
constexpr std::array<std::string_view, 5> kReadExtensions = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                                                             "KHR_materials_transmission", "KHR_mesh_quantization",
                                                             "KHR_texture_transform"};

[[noreturn]] void fail(const fs::path& path, std::string_view problem) {
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

// A number as people write it (1e+30, not 309 digits).
std::string numberText(double value) {
  std::array<char, 32> text;
  std::snprintf(text.data(), text.size(), "%g", value);
  return text.data();
}

// `where`.`name`, or `name` at the top of the document.
std::string memberPath(const std::string& where, std::string_view name) {
  return where.empty() ? std::string(name) : where + "." + std::string(name);
}

std::string pointText(const glm::vec3& point) {
  return "(" + numberText(point.x) + ", " + numberText(point.y) + ", " + numberText(point.z) + ")";
}

// Within kMaxCoordinate of the origin along every axis (false for NaN).
bool withinReach(const glm::vec3& point) {
  return glm::all(glm::lessThanEqual(glm::abs(point), glm::vec3(kMaxCoordinate)));
}
constexpr const char* kReachText = "beyond the 1e+05 m from the origin that is drawn";

std::string elementPath(const std::string& where, size_t index) { return where + "[" + std::to_string(index) + "]"; }

// Refuses JSON nested deeper than kMaxJsonDepth before any parser sees it: the parsers recurse once per level, and
// 30,000 levels overflow the stack.
void checkJsonNesting(const fs::path& path, std::string_view text) {
  size_t depth = 0;
  bool inString = false;
  bool escaped = false;
  for (const char c : text) {
    if (inString) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        fail(path, "the JSON is nested more than " + std::to_string(kMaxJsonDepth) + " levels deep");
      }
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

uint32_t loadLittleEndian32(std::span<const uint8_t> bytes, size_t at) {
  return uint32_t{bytes[at]} | uint32_t{bytes[at + 1]} << 8 | uint32_t{bytes[at + 2]} << 16 |
         uint32_t{bytes[at + 3]} << 24;
}

// The JSON chunk of a GLB file, once the layout is checked: version 2, and the chunks inside the file (tinygltf reads
// a BIN chunk's 8-byte header and data without checking that they fit).
std::string_view glbJsonChunk(const fs::path& path, std::span<const uint8_t> bytes) {
  constexpr size_t kHeaderBytes = 12;
  constexpr size_t kChunkHeaderBytes = 8;
  constexpr uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
  if (bytes.size() < kHeaderBytes + kChunkHeaderBytes || std::memcmp(bytes.data(), "glTF", 4) != 0) {
    fail(path, "not a GLB file (no glTF binary header)");
  }
  const uint32_t version = loadLittleEndian32(bytes, 4);
  if (version != 2) fail(path, "GLB version " + std::to_string(version) + "; only version 2 is read");
  const uint32_t length = loadLittleEndian32(bytes, 8);
  if (length > bytes.size() || length < kHeaderBytes + kChunkHeaderBytes) {
    fail(path, "the GLB header gives a length of " + std::to_string(length) + " bytes for a file of " +
                   std::to_string(bytes.size()));
  }
  const uint32_t jsonLength = loadLittleEndian32(bytes, kHeaderBytes);
  if (loadLittleEndian32(bytes, kHeaderBytes + 4) != kJsonChunk) fail(path, "the first GLB chunk is not JSON");
  const size_t jsonStart = kHeaderBytes + kChunkHeaderBytes;
  if (jsonLength > length - jsonStart) {
    fail(path, "the GLB's JSON chunk of " + std::to_string(jsonLength) + " bytes reaches past its end");
  }
  const size_t binStart = jsonStart + jsonLength;
  if (binStart < length) {
    if (length - binStart < kChunkHeaderBytes) fail(path, "the GLB's second chunk has no room for its header");
    const uint32_t binLength = loadLittleEndian32(bytes, binStart);
    if (binLength > length - binStart - kChunkHeaderBytes) {
      fail(path, "the GLB's second chunk of " + std::to_string(binLength) + " bytes reaches past its end");
    }
  }
  return {reinterpret_cast<const char*>(bytes.data()) + jsonStart, jsonLength};
}

// An allowed range of a number, with the words that say it in an error.
struct Interval {
  double min;
  double max;
  const char* text;
};

constexpr double kAboveZero = std::numeric_limits<double>::denorm_min();
constexpr double kBelowHalfPi = 1.5707963267948963;  // the double just below π/2
constexpr double kPi = 3.141592653589793;
constexpr Interval kFloat{-FLT_MAX, FLT_MAX, "a finite float"};
constexpr Interval kPositive{kAboveZero, FLT_MAX, "a finite float above 0"};
constexpr Interval kUnitInterval{0.0, 1.0, "in [0, 1]"};
constexpr Interval kAlphaCutoff{0.0, FLT_MAX, "a finite float of at least 0"};
constexpr Interval kEmissiveStrength{0.0, 65504.0, "in [0, 65504] (the largest half float)"};
constexpr Interval kLightIntensity{0.0, 1e5, "in [0, 1e+05]"};
constexpr Interval kLightRange{1e-3, FLT_MAX, "a finite float of at least 0.001 m"};
constexpr Interval kInnerConeAngle{0.0, kBelowHalfPi, "an angle from 0 to below pi/2 radians"};
constexpr Interval kOuterConeAngle{kAboveZero, kBelowHalfPi, "an angle above 0 and below pi/2 radians"};
constexpr Interval kFieldOfView{1e-3, kPi - 1e-3, "in [0.001, pi - 0.001] radians"};
constexpr Interval kNearPlane{1e-4, kMaxCoordinate, "in [0.0001, 1e+05] m"};

// The JSON checked before tinygltf reads it: tinygltf replaces a member of the wrong type by its default without a
// word (a "yfov" given as a string becomes 0, a "mesh" of -1 or 1.5 no mesh) and keeps numbers no float can hold. So
// every member the converter uses is checked here for its type and, where glTF or the renderer bounds it, its range;
// and extensionsRequired for extensions we do not read.
class DocumentCheck {
 public:
  explicit DocumentCheck(const fs::path& path) : path_(path) {}

  void run(const Json& document) const {
    if (!document.is_object()) fail(path_, "the JSON is not an object, so not a glTF document");
    if (const Json* required = array(document, "extensionsRequired", "")) {
      for (size_t i = 0; i < required->size(); ++i) {
        const Json& name = (*required)[i];
        if (!name.is_string()) wrongType(elementPath("extensionsRequired", i), name, "a string");
        if (std::find(kReadExtensions.begin(), kReadExtensions.end(), name.get<std::string>()) ==
            kReadExtensions.end()) {
          fail(path_, "extensionsRequired lists " + name.get<std::string>() + ", which this loader does not read");
        }
      }
    }
    index(document, "scene", "");
    objects(document, "scenes", "",
            [&](const Json& scene, const std::string& where) { indices(scene, "nodes", where); });
    objects(document, "nodes", "", [&](const Json& node, const std::string& where) { checkNode(node, where); });
    objects(document, "meshes", "", [&](const Json& mesh, const std::string& where) {
      string(mesh, "name", where);
      objects(mesh, "primitives", where, [&](const Json& primitive, const std::string& at) {
        if (const Json* attributes = object(primitive, "attributes", at)) {
          for (const auto& attribute : attributes->items())
            index(*attributes, attribute.key(), memberPath(at, "attributes"));
        }
        index(primitive, "indices", at);
        index(primitive, "material", at);
        index(primitive, "mode", at);
      });
    });
    objects(document, "materials", "",
            [&](const Json& material, const std::string& where) { checkMaterial(material, where); });
    objects(document, "accessors", "", [&](const Json& accessor, const std::string& where) {
      index(accessor, "bufferView", where);
      size(accessor, "byteOffset", where);
      index(accessor, "componentType", where);
      size(accessor, "count", where);
      string(accessor, "type", where);
      boolean(accessor, "normalized", where);
      object(accessor, "sparse", where);
    });
    objects(document, "bufferViews", "", [&](const Json& view, const std::string& where) {
      index(view, "buffer", where);
      size(view, "byteOffset", where);
      size(view, "byteLength", where);
      size(view, "byteStride", where);
    });
    objects(document, "buffers", "", [&](const Json& buffer, const std::string& where) {
      string(buffer, "uri", where);
      size(buffer, "byteLength", where);
    });
    objects(document, "textures", "",
            [&](const Json& texture, const std::string& where) { index(texture, "source", where); });
    objects(document, "images", "", [&](const Json& image, const std::string& where) {
      string(image, "name", where);
      string(image, "uri", where);
      index(image, "bufferView", where);
      string(image, "mimeType", where);
    });
    objects(document, "cameras", "", [&](const Json& camera, const std::string& where) {
      string(camera, "name", where);
      string(camera, "type", where);
      if (const Json* perspective = object(camera, "perspective", where)) {
        const std::string at = memberPath(where, "perspective");
        number(*perspective, "yfov", at, kFieldOfView);
        number(*perspective, "znear", at, kNearPlane);
        number(*perspective, "zfar", at, kPositive);
        number(*perspective, "aspectRatio", at, kPositive);
      }
    });
    if (const Json* extensions = object(document, "extensions", "")) {
      if (const Json* lights = object(*extensions, "KHR_lights_punctual", "extensions")) {
        objects(*lights, "lights", "extensions.KHR_lights_punctual",
                [&](const Json& light, const std::string& where) { checkLight(light, where); });
      }
    }
  }

 private:
  void checkNode(const Json& node, const std::string& where) const {
    string(node, "name", where);
    index(node, "mesh", where);
    index(node, "camera", where);
    indices(node, "children", where);
    numbers(node, "matrix", where, 16, kFloat);
    numbers(node, "translation", where, 3, kFloat);
    numbers(node, "rotation", where, 4, kFloat);
    numbers(node, "scale", where, 3, kFloat);
    if (const Json* extensions = object(node, "extensions", where)) {
      const std::string at = memberPath(where, "extensions");
      if (const Json* light = object(*extensions, "KHR_lights_punctual", at)) {
        index(*light, "light", memberPath(at, "KHR_lights_punctual"));
      }
    }
  }

  void checkMaterial(const Json& material, const std::string& where) const {
    string(material, "name", where);
    string(material, "alphaMode", where);
    number(material, "alphaCutoff", where, kAlphaCutoff);
    numbers(material, "emissiveFactor", where, 3, kUnitInterval);
    if (const Json* texture = object(material, "emissiveTexture", where))
      checkTextureInfo(*texture, memberPath(where, "emissiveTexture"));
    if (const Json* pbr = object(material, "pbrMetallicRoughness", where)) {
      const std::string at = memberPath(where, "pbrMetallicRoughness");
      numbers(*pbr, "baseColorFactor", at, 4, kUnitInterval);
      if (const Json* texture = object(*pbr, "baseColorTexture", at))
        checkTextureInfo(*texture, memberPath(at, "baseColorTexture"));
    }
    if (const Json* extensions = object(material, "extensions", where)) {
      const std::string at = memberPath(where, "extensions");
      if (const Json* strength = object(*extensions, "KHR_materials_emissive_strength", at)) {
        number(*strength, "emissiveStrength", memberPath(at, "KHR_materials_emissive_strength"), kEmissiveStrength);
      }
      if (const Json* transmission = object(*extensions, "KHR_materials_transmission", at)) {
        number(*transmission, "transmissionFactor", memberPath(at, "KHR_materials_transmission"), kUnitInterval);
      }
    }
  }

  void checkTextureInfo(const Json& texture, const std::string& where) const {
    index(texture, "index", where);
    index(texture, "texCoord", where);
    if (const Json* extensions = object(texture, "extensions", where)) {
      const std::string at = memberPath(where, "extensions");
      if (const Json* transform = object(*extensions, "KHR_texture_transform", at)) {
        const std::string transformPath = memberPath(at, "KHR_texture_transform");
        numbers(*transform, "offset", transformPath, 2, kFloat);
        number(*transform, "rotation", transformPath, kFloat);
        numbers(*transform, "scale", transformPath, 2, kFloat);
      }
    }
  }

  void checkLight(const Json& light, const std::string& where) const {
    string(light, "name", where);
    string(light, "type", where);
    numbers(light, "color", where, 3, kUnitInterval);
    number(light, "intensity", where, kLightIntensity);
    number(light, "range", where, kLightRange);
    if (const Json* spot = object(light, "spot", where)) {
      const std::string at = memberPath(where, "spot");
      number(*spot, "innerConeAngle", at, kInnerConeAngle);
      number(*spot, "outerConeAngle", at, kOuterConeAngle);
    }
  }

  [[noreturn]] void wrongType(const std::string& where, const Json& value, std::string_view expected) const {
    std::string shown = value.dump();
    if (shown.size() > 40) shown = shown.substr(0, 37) + "...";
    fail(path_, where + " must be " + std::string(expected) + ", not " + shown);
  }

  // parent[name], or null when it is absent; `isKind` checks its JSON type, `expected` says it in an error.
  template <typename IsKind>
  const Json* member(const Json& parent, const std::string& name, const std::string& where, IsKind isKind,
                     std::string_view expected) const {
    const auto found = parent.find(name);
    if (found == parent.end()) return nullptr;
    if (!isKind(*found)) wrongType(memberPath(where, name), *found, expected);
    return &*found;
  }

  const Json* object(const Json& parent, const std::string& name, const std::string& where) const {
    return member(
        parent, name, where, [](const Json& value) { return value.is_object(); }, "an object");
  }

  const Json* array(const Json& parent, const std::string& name, const std::string& where) const {
    return member(
        parent, name, where, [](const Json& value) { return value.is_array(); }, "an array");
  }

  void string(const Json& parent, const std::string& name, const std::string& where) const {
    member(
        parent, name, where, [](const Json& value) { return value.is_string(); }, "a string");
  }

  void boolean(const Json& parent, const std::string& name, const std::string& where) const {
    member(
        parent, name, where, [](const Json& value) { return value.is_boolean(); }, "true or false");
  }

  static bool isWholeNumberUpTo(const Json& value, uint64_t max) {
    if (value.is_number_unsigned()) return value.get<uint64_t>() <= max;
    return value.is_number_integer() && value.get<int64_t>() >= 0 && static_cast<uint64_t>(value.get<int64_t>()) <= max;
  }

  // An index into one of the document's arrays (tinygltf holds them as int).
  void index(const Json& parent, const std::string& name, const std::string& where) const {
    member(
        parent, name, where, [](const Json& value) { return isWholeNumberUpTo(value, INT_MAX); },
        "a whole number from 0 to 2147483647");
  }

  // A byte count or offset.
  void size(const Json& parent, const std::string& name, const std::string& where) const {
    member(
        parent, name, where, [](const Json& value) { return isWholeNumberUpTo(value, uint64_t{1} << 53); },
        "a whole number from 0");
  }

  void indices(const Json& parent, const std::string& name, const std::string& where) const {
    if (const Json* values = array(parent, name, where)) {
      for (size_t i = 0; i < values->size(); ++i) {
        if (!isWholeNumberUpTo((*values)[i], INT_MAX)) {
          wrongType(elementPath(memberPath(where, name), i), (*values)[i], "a whole number from 0 to 2147483647");
        }
      }
    }
  }

  void checkNumber(const Json& value, const std::string& where, const Interval& allowed) const {
    if (!value.is_number()) wrongType(where, value, "a number");
    const double number = value.get<double>();
    if (!(number >= allowed.min && number <= allowed.max)) {
      fail(path_, where + " is " + numberText(number) + "; it must be " + allowed.text);
    }
  }

  void number(const Json& parent, const std::string& name, const std::string& where, const Interval& allowed) const {
    if (const auto found = parent.find(name); found != parent.end())
      checkNumber(*found, memberPath(where, name), allowed);
  }

  void numbers(const Json& parent, const std::string& name, const std::string& where, size_t count,
               const Interval& allowed) const {
    const Json* values = array(parent, name, where);
    if (values == nullptr) return;
    const std::string at = memberPath(where, name);
    if (values->size() != count)
      fail(path_, at + " holds " + std::to_string(values->size()) + " numbers, not " + std::to_string(count));
    for (size_t i = 0; i < count; ++i) checkNumber((*values)[i], elementPath(at, i), allowed);
  }

  // Each element of the array parent[name], which must be an object, checked by `check(element, its path)`.
  template <typename Check>
  void objects(const Json& parent, const std::string& name, const std::string& where, Check check) const {
    const Json* elements = array(parent, name, where);
    if (elements == nullptr) return;
    for (size_t i = 0; i < elements->size(); ++i) {
      const std::string at = elementPath(memberPath(where, name), i);
      if (!(*elements)[i].is_object()) wrongType(at, (*elements)[i], "an object");
      check((*elements)[i], at);
    }
  }

  const fs::path& path_;
};

// The files a glTF file refers to, read by tinygltf through these callbacks under loadGltf's policy: in the file's
// folder or below it, regular files of a bounded size.
struct ReferencedFiles {
  std::string folder;   // canonical, ending in '/'
  std::string refusal;  // why the first refused reference was refused; empty while none was

  void refuse(std::string problem) {
    if (refusal.empty()) refusal = std::move(problem);
  }
};

// tinygltf looks a URI up in the folder it is given, then in the working directory: only the first is searched, so
// that what a file refers to does not depend on where the viewer was started.
bool referenceExists(const std::string& path, void* context) {
  const auto& files = *static_cast<const ReferencedFiles*>(context);
  std::error_code ignored;
  return path.starts_with(files.folder) && fs::exists(path, ignored);
}

std::string expandNothing(const std::string& path, void*) { return path; }  // no ~ or $VARIABLE in a URI

bool readReference(std::vector<unsigned char>* bytes, std::string* problem, const std::string& path, void* context) {
  auto& files = *static_cast<ReferencedFiles*>(context);
  const std::string uri = path.substr(files.folder.size());
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(path, error);
  const fs::path relative = resolved.lexically_relative(files.folder);
  if (error || relative.empty() || *relative.begin() == "..") {
    files.refuse("the URI '" + uri + "' leads outside the file's folder, and a glTF file may refer only to files in " +
                 "its folder or below it");
  } else {
    try {
      *bytes = readFileBytes(resolved, kMaxFileBytes);
      return true;
    } catch (const ImageIoError& readError) {
      files.refuse("the URI '" + uri + "' names " + readError.what());
    }
  }
  *problem += files.refusal;
  return false;
}

// tinygltf's decoder (stb_image), after a look at the image's size: a few bytes of PNG header can claim gigabytes.
bool decodeImage(tinygltf::Image* image, int index, std::string* problem, std::string* warning, int width, int height,
                 const unsigned char* bytes, int size, void*) {
  int fileWidth = 0;
  int fileHeight = 0;
  int channels = 0;
  if (stbi_info_from_memory(bytes, size, &fileWidth, &fileHeight, &channels) != 0 &&
      uint64_t(std::max(fileWidth, 0)) * uint64_t(std::max(fileHeight, 0)) > kMaxTexturePixels) {
    *problem += "images[" + std::to_string(index) + "] is " + std::to_string(fileWidth) + "x" +
                std::to_string(fileHeight) + " pixels, more than the 8192x8192 read\n";
    return false;
  }
  return tinygltf::LoadImageData(image, index, problem, warning, width, height, bytes, size, nullptr);
}

// Reads a value from a byte address that need not be aligned (a corrupt file can put an accessor anywhere).
template <typename T>
T loadUnaligned(const unsigned char* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

// `v` scaled to unit length, in double so that a float vector of 1e30 keeps its direction; nullopt when it has none.
std::optional<glm::vec3> unitVector(const glm::dvec3& v) {
  const double length = glm::length(v);
  if (!(length > 1e-30) || !std::isfinite(length)) return std::nullopt;
  return glm::vec3(v / length);
}

glm::vec3 faceNormal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 origin(a);
  return unitVector(glm::cross(glm::dvec3(b) - origin, glm::dvec3(c) - origin)).value_or(glm::vec3(0.0f, 1.0f, 0.0f));
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
// with a SceneLoadError instead of reading out of bounds; the types and ranges of the JSON's members were checked by
// DocumentCheck, the values computed from them (transforms, vertices) are checked here.
class GltfConverter {
 public:
  GltfConverter(const tinygltf::Model& model, fs::path path)
      : model_(model), path_(std::move(path)), visited_(model.nodes.size(), false) {}

  Scene convert() {
    convertMaterials();
    visitNodes();
    if (scene_.instances.empty()) fail(path_, "no triangle meshes in the scene");
    checkWorldExtent();
    const Bounds bounds = worldBounds(scene_);
    // Cameras and lights come in the order their nodes are visited (the scene's nodes, depth first).
    if (scene_.cameras.empty()) scene_.cameras.push_back(cameraFraming(bounds));
    scene_.giDetailScale = giDetailScaleFor(bounds, scene_.cameras.front().position);
    return std::move(scene_);
  }

 private:
  void checkIndex(int index, size_t size, std::string_view array, const std::string& user) const {
    if (index < 0 || static_cast<size_t>(index) >= size) {
      fail(path_, user + " refers to " + std::string(array) + "[" + std::to_string(index) + "], but the file has " +
                      std::to_string(size));
    }
  }

  static std::string nodePath(int index) { return "nodes[" + std::to_string(index) + "]"; }

  // The roots to draw, and where the file lists them.
  std::pair<std::vector<int>, std::string> rootNodes() const {
    if (model_.scenes.empty()) {
      // No scene listed: show every node that is no other node's child.
      std::vector<bool> isChild(model_.nodes.size(), false);
      for (size_t node = 0; node < model_.nodes.size(); ++node) {
        for (const int child : model_.nodes[node].children) {
          checkIndex(child, model_.nodes.size(), "nodes", nodePath(static_cast<int>(node)) + ".children");
          isChild[static_cast<size_t>(child)] = true;
        }
      }
      std::vector<int> roots;
      for (size_t i = 0; i < model_.nodes.size(); ++i) {
        if (!isChild[i]) roots.push_back(static_cast<int>(i));
      }
      return {roots, "the nodes that are no node's children"};
    }
    const int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    checkIndex(sceneIndex, model_.scenes.size(), "scenes", "scene");
    return {model_.scenes[static_cast<size_t>(sceneIndex)].nodes, "scenes[" + std::to_string(sceneIndex) + "].nodes"};
  }

  // Depth first, each node before its children, without recursion: a chain of 20,000 nodes is a valid file.
  void visitNodes() {
    struct Visit {
      int node;
      glm::mat4 parentTransform;
      std::string listedIn;  // where the file lists the node, for an index out of range
    };
    const auto [roots, rootsListedIn] = rootNodes();
    std::vector<Visit> pending;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root)
      pending.push_back({*root, glm::mat4(1.0f), rootsListedIn});
    while (!pending.empty()) {
      const Visit visit = std::move(pending.back());
      pending.pop_back();
      checkIndex(visit.node, model_.nodes.size(), "nodes", visit.listedIn);
      const glm::mat4 world = visitNode(visit.node, visit.parentTransform);
      const std::vector<int>& children = model_.nodes[static_cast<size_t>(visit.node)].children;
      for (auto child = children.rbegin(); child != children.rend(); ++child) {
        pending.push_back({*child, world, nodePath(visit.node) + ".children"});
      }
    }
  }

  glm::mat4 localTransform(const tinygltf::Node& node, const std::string& where) const {
    // DocumentCheck has checked the arrays' lengths and that every number is a finite float.
    if (!node.matrix.empty()) {
      glm::dmat4 matrix = glm::make_mat4(node.matrix.data());  // column-major, as glTF stores it
      const glm::dvec4 bottomRow(matrix[0][3], matrix[1][3], matrix[2][3], matrix[3][3]);
      // Exporters write the row as exact decimals; a little rounding is forgiven.
      if (glm::any(glm::greaterThan(glm::abs(bottomRow - glm::dvec4(0.0, 0.0, 0.0, 1.0)), glm::dvec4(1e-6)))) {
        fail(path_, where + ".matrix is not affine: its bottom row is " + numberText(bottomRow.x) + ", " +
                        numberText(bottomRow.y) + ", " + numberText(bottomRow.z) + ", " + numberText(bottomRow.w) +
                        " instead of 0, 0, 0, 1");
      }
      matrix = glm::row(matrix, 3, glm::dvec4(0.0, 0.0, 0.0, 1.0));
      return glm::mat4(matrix);
    }
    glm::mat4 transform(1.0f);
    if (!node.translation.empty()) {
      transform[3] = glm::vec4(glm::vec3(glm::make_vec3(node.translation.data())), 1.0f);
    }
    if (!node.rotation.empty()) {
      const glm::dvec4 xyzw = glm::make_vec4(node.rotation.data());
      const double length = glm::length(xyzw);
      if (!(length > 1e-6))
        fail(path_, where + ".rotation has length " + numberText(length) + "; it must be a unit quaternion");
      const glm::dvec4 unit = xyzw / length;
      transform *= glm::mat4_cast(glm::quat(static_cast<float>(unit.w), static_cast<float>(unit.x),
                                            static_cast<float>(unit.y), static_cast<float>(unit.z)));
    }
    if (!node.scale.empty()) {
      const glm::vec3 scale(glm::make_vec3(node.scale.data()));
      transform[0] *= scale.x;
      transform[1] *= scale.y;
      transform[2] *= scale.z;
    }
    return transform;
  }

  // Adds what node `index` holds; returns its world transform.
  glm::mat4 visitNode(int index, const glm::mat4& parentTransform) {
    const std::string where = nodePath(index);
    // glTF nodes form a tree: a node reached twice means a cycle or a shared child.
    if (visited_[static_cast<size_t>(index)]) {
      fail(path_, where + " is reached twice; the node hierarchy must be a tree");
    }
    visited_[static_cast<size_t>(index)] = true;
    const tinygltf::Node& node = model_.nodes[static_cast<size_t>(index)];
    const glm::mat4 world = parentTransform * localTransform(node, where);
    for (int column = 0; column < 4; ++column) {
      if (glm::any(glm::isnan(world[column])) || glm::any(glm::isinf(world[column]))) {
        fail(path_, where +
                        " has a world transform that is not finite (its and its parents' scales and "
                        "translations multiply beyond any float)");
      }
    }
    if (!withinReach(glm::vec3(world[3]))) {
      fail(path_, where + " lies at " + pointText(glm::vec3(world[3])) + ", " + kReachText);
    }

    if (node.mesh >= 0) {
      checkIndex(node.mesh, model_.meshes.size(), "meshes", where + ".mesh");
      const double determinant = glm::determinant(glm::dmat3(glm::mat3(world)));
      if (std::abs(determinant) >= kMinDeterminant) {
        for (const uint32_t mesh : meshesFor(node.mesh, determinant < 0.0)) {
          scene_.instances.push_back({mesh, world});
          instanceNodes_.push_back(index);
        }
      }
    }
    if (node.camera >= 0) {
      checkIndex(node.camera, model_.cameras.size(), "cameras", where + ".camera");
      addCamera(model_.cameras[static_cast<size_t>(node.camera)], node, where, world);
    }
    if (const auto light = node.extensions.find("KHR_lights_punctual"); light != node.extensions.end()) {
      const tinygltf::Value& extension = light->second;
      const std::string at = where + ".extensions.KHR_lights_punctual";
      if (!extension.IsObject() || !extension.Get("light").IsNumber()) fail(path_, at + " has no light index");
      const int lightIndex = extension.Get("light").GetNumberAsInt();
      checkIndex(lightIndex, model_.lights.size(), "extensions.KHR_lights_punctual.lights", at + ".light");
      addLight(lightIndex, node, where, world);
    }
    return world;
  }

  // Every drawn vertex within kMaxCoordinate of the origin, so that the renderer's matrices and the GI's volumes stay
  // finite and precise.
  void checkWorldExtent() const {
    for (size_t i = 0; i < scene_.instances.size(); ++i) {
      const Instance& instance = scene_.instances[i];
      for (const Vertex& vertex : scene_.meshes[instance.mesh].vertices) {
        const glm::vec3 position(instance.transform * glm::vec4(vertex.position, 1.0f));
        if (!withinReach(position)) {
          fail(path_, nodePath(instanceNodes_[i]) + " places a vertex of mesh '" + scene_.meshes[instance.mesh].name +
                          "' at " + pointText(position) + ", " + kReachText);
        }
      }
    }
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
        // Points and lines are not drawn.
        if (!drawsTriangles(mesh.primitives[i].mode)) continue;
        const std::string name = mesh.primitives.size() > 1 ? mesh.name + "#" + std::to_string(i) : mesh.name;
        const std::string where = "meshes[" + std::to_string(gltfMesh) + "].primitives[" + std::to_string(i) + "]";
        Mesh converted = convertPrimitive(mesh.primitives[i], name, where);
        // A strip or a fan of fewer than three corners has no triangle.
        if (!converted.indices.empty()) meshes.push_back(addMesh(std::move(converted)));
      }
    }
    return meshCache_.emplace(key, std::move(meshes)).first->second;
  }

  uint32_t addMesh(Mesh mesh) {
    scene_.meshes.push_back(std::move(mesh));
    return static_cast<uint32_t>(scene_.meshes.size() - 1);
  }

  // The floats of an attribute, each checked to be finite.
  std::vector<float> readAttribute(int accessor, int components, const std::string& where) const {
    std::vector<float> values = readFloats(accessor, components, where);
    for (size_t i = 0; i < values.size(); ++i) {
      if (!std::isfinite(values[i])) {
        fail(path_, where + " (accessors[" + std::to_string(accessor) + "]) element " +
                        std::to_string(i / static_cast<size_t>(components)) + " is " + numberText(values[i]));
      }
    }
    return values;
  }

  Mesh convertPrimitive(const tinygltf::Primitive& primitive, const std::string& name, const std::string& where) {
    const auto attribute = [&](const char* semantic) {
      const auto found = primitive.attributes.find(semantic);
      return found == primitive.attributes.end() ? -1 : found->second;
    };
    const int positionAccessor = attribute("POSITION");
    if (positionAccessor < 0) fail(path_, where + " has no POSITION attribute");
    const std::vector<float> positions = readAttribute(positionAccessor, 3, where + ".attributes.POSITION");
    const size_t vertexCount = positions.size() / 3;

    const auto readOptional = [&](const char* semantic, int components) {
      const int accessor = attribute(semantic);
      if (accessor < 0) return std::vector<float>();
      const std::string at = where + ".attributes." + semantic;
      std::vector<float> values = readAttribute(accessor, components, at);
      if (values.size() != vertexCount * static_cast<size_t>(components)) {
        fail(path_, at + " has " + std::to_string(values.size() / static_cast<size_t>(components)) + " values for " +
                        std::to_string(vertexCount) + " vertices");
      }
      return values;
    };
    const std::vector<float> normals = readOptional("NORMAL", 3);
    // The coordinate set the mesh's texture names (texCoord).
    const tinygltf::TextureInfo* texture = meshTexture(primitive.material);
    const std::string texcoords = "TEXCOORD_" + std::to_string(texture != nullptr ? texture->texCoord : 0);
    const std::vector<float> uvs = readOptional(texcoords.c_str(), 2);
    // COLOR_0 is RGB or RGBA (its alpha is not used).
    const int colorAccessor = attribute("COLOR_0");
    const int colorComponents =
        colorAccessor < 0 ? 3 : viewAccessor(colorAccessor, where + ".attributes.COLOR_0").componentCount;
    if (colorComponents != 3 && colorComponents != 4)
      fail(path_, where + ".attributes.COLOR_0 has " + std::to_string(colorComponents) + " components, not 3 or 4");
    const std::vector<float> colors = readOptional("COLOR_0", colorComponents);

    Mesh mesh;
    mesh.name = name;
    mesh.material = materialFor(primitive.material, where + ".material");
    const glm::dmat3 uvTransform = textureTransform(texture);
    mesh.vertices.resize(vertexCount);
    std::vector<bool> lacksNormal(normals.empty() ? 0 : vertexCount, false);
    for (size_t v = 0; v < vertexCount; ++v) {
      Vertex& vertex = mesh.vertices[v];
      vertex.position = glm::make_vec3(&positions[3 * v]);
      if (!normals.empty()) {
        const std::optional<glm::vec3> normal = unitVector(glm::dvec3(glm::make_vec3(&normals[3 * v])));
        lacksNormal[v] = !normal;
        vertex.normal = normal.value_or(vertex.normal);
      }
      if (!uvs.empty()) vertex.uv = glm::vec2(uvTransform * glm::dvec3(glm::make_vec2(&uvs[2 * v]), 1.0));
      // Clamped as glTF bounds it: a colour above 1 would make an albedo that adds light.
      if (!colors.empty())
        vertex.color = glm::clamp(glm::make_vec3(&colors[colorComponents * v]), glm::vec3(0.0f), glm::vec3(1.0f));
      if (!std::isfinite(vertex.uv.x) || !std::isfinite(vertex.uv.y))
        fail(path_, where + ".attributes." + texcoords + " is not finite under its material's KHR_texture_transform");
    }
    if (primitive.indices >= 0) {
      mesh.indices = readIndices(primitive.indices, vertexCount, where + ".indices");
    } else {
      mesh.indices.resize(vertexCount);
      for (size_t v = 0; v < vertexCount; ++v) mesh.indices[v] = static_cast<uint32_t>(v);
    }
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES) {
      mesh.indices = triangleList(mesh.indices, primitive.mode);
    } else if (mesh.indices.size() % 3 != 0) {
      fail(path_, where + " has " + std::to_string(mesh.indices.size()) + " triangle corners, not a multiple of 3");
    }
    if (normals.empty()) {
      giveFlatNormals(mesh);
    } else {
      giveFaceNormals(mesh, lacksNormal);
    }
    return mesh;
  }

  static bool drawsTriangles(int mode) {
    return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           mode == TINYGLTF_MODE_TRIANGLE_FAN;
  }

  // The triangles of a strip or a fan as a list (glTF 2.0, 3.7.2.1): triangle i of a strip is (v_i, v_{i+1+i%2},
  // v_{i+2-i%2}) — every other one turned so that all keep the strip's winding — and of a fan (v_{i+1}, v_{i+2}, v_0).
  static std::vector<uint32_t> triangleList(const std::vector<uint32_t>& corners, int mode) {
    std::vector<uint32_t> triangles;
    for (size_t i = 0; i + 2 < corners.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        triangles.insert(triangles.end(), {corners[i], corners[i + 1 + i % 2], corners[i + 2 - i % 2]});
      } else {
        triangles.insert(triangles.end(), {corners[i + 1], corners[i + 2], corners[0]});
      }
    }
    return triangles;
  }

  // The texture whose coordinates a primitive's mesh carries: its material's base colour texture, else its emission
  // texture (a mesh has one set of coordinates for both); null where the material has neither.
  const tinygltf::TextureInfo* meshTexture(int material) const {
    if (material < 0 || static_cast<size_t>(material) >= model_.materials.size()) return nullptr;
    const tinygltf::Material& source = model_.materials[static_cast<size_t>(material)];
    if (source.pbrMetallicRoughness.baseColorTexture.index >= 0) return &source.pbrMetallicRoughness.baseColorTexture;
    if (source.emissiveTexture.index >= 0) return &source.emissiveTexture;
    return nullptr;
  }

  // A texture's KHR_texture_transform as one matrix on its texture coordinates, uv' = T·R·S·uv.
  glm::dmat3 textureTransform(const tinygltf::TextureInfo* texture) const {
    if (texture == nullptr) return glm::dmat3(1.0);
    const auto found = texture->extensions.find("KHR_texture_transform");
    if (found == texture->extensions.end() || !found->second.IsObject()) return glm::dmat3(1.0);
    const tinygltf::Value& transform = found->second;
    const auto pair = [&](const char* name, glm::dvec2 fallback) {
      const tinygltf::Value& value = transform.Get(name);
      if (!value.IsArray() || value.ArrayLen() != 2) return fallback;
      return glm::dvec2(value.Get(0).GetNumberAsDouble(), value.Get(1).GetNumberAsDouble());
    };
    const glm::dvec2 offset = pair("offset", glm::dvec2(0.0)), scale = pair("scale", glm::dvec2(1.0));
    const double rotation = transform.Get("rotation").IsNumber() ? transform.Get("rotation").GetNumberAsDouble() : 0.0;
    // Column-major, as the extension's matrices: translation × rotation × scale.
    const double c = std::cos(rotation), s = std::sin(rotation);
    return glm::dmat3(glm::dvec3(c * scale.x, -s * scale.x, 0.0), glm::dvec3(s * scale.y, c * scale.y, 0.0),
                      glm::dvec3(offset, 1.0));
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
      const glm::vec3 normal = faceNormal(a.position, b.position, c.position);
      for (const Vertex* corner : {&a, &b, &c})
        corners.push_back({corner->position, normal, corner->uv, corner->color});
    }
    mesh.vertices = std::move(corners);
    for (size_t i = 0; i < mesh.indices.size(); ++i) mesh.indices[i] = static_cast<uint32_t>(i);
  }

  // A vertex whose normal in the file has no direction (zero length) takes the face normal of its first triangle.
  static void giveFaceNormals(Mesh& mesh, std::vector<bool>& lacksNormal) {
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
      const std::array<uint32_t, 3> corners = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
      if (!lacksNormal[corners[0]] && !lacksNormal[corners[1]] && !lacksNormal[corners[2]]) continue;
      const glm::vec3 normal = faceNormal(mesh.vertices[corners[0]].position, mesh.vertices[corners[1]].position,
                                          mesh.vertices[corners[2]].position);
      for (const uint32_t corner : corners) {
        if (lacksNormal[corner]) mesh.vertices[corner].normal = normal;
        lacksNormal[corner] = false;
      }
    }
  }

  AccessorView viewAccessor(int index, const std::string& user) const {
    checkIndex(index, model_.accessors.size(), "accessors", user);
    const tinygltf::Accessor& accessor = model_.accessors[static_cast<size_t>(index)];
    const std::string name = "accessors[" + std::to_string(index) + "]";
    if (accessor.sparse.isSparse) fail(path_, name + " is sparse, which is not supported");
    checkIndex(accessor.bufferView, model_.bufferViews.size(), "bufferViews", name + ".bufferView");
    const tinygltf::BufferView& view = model_.bufferViews[static_cast<size_t>(accessor.bufferView)];
    const std::string viewName = "bufferViews[" + std::to_string(accessor.bufferView) + "]";
    checkIndex(view.buffer, model_.buffers.size(), "buffers", viewName + ".buffer");
    const std::vector<unsigned char>& buffer = model_.buffers[static_cast<size_t>(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
      fail(path_, viewName + " (" + std::to_string(view.byteLength) + " bytes at " + std::to_string(view.byteOffset) +
                      ") reaches past the end of buffers[" + std::to_string(view.buffer) + "] (" +
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
      fail(path_, user + " uses accessors[" + std::to_string(accessorIndex) + "] with " +
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
        fail(path_, user + " uses accessors[" + std::to_string(accessorIndex) + "] with an unsupported component type");
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

  std::vector<uint32_t> readIndices(int accessorIndex, size_t vertexCount, const std::string& where) const {
    const AccessorView view = viewAccessor(accessorIndex, where);
    const std::string what = where + " (accessors[" + std::to_string(accessorIndex) + "])";
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

  // Material::alphaCutoff of a glTF material: for MASK, where baseColorFactor's alpha × the texture's is below
  // alphaCutoff — the texture's alpha below alphaCutoff over the factor's (kCutsOutEverywhere where no alpha passes).
  // The renderer has no transparency: BLEND is cut out where the alpha is below one half (kBlendCutoff), so that a
  // window's glass, mostly clear, lets the light through and a decal, mostly opaque, stays; and so is a material that
  // transmits more than half the light (KHR_materials_transmission's factor; its texture is not read), everywhere.
  float alphaCutoff(const tinygltf::Material& source, const std::string& where) const {
    constexpr float kCutsOutEverywhere = 2.0f;  // above any alpha
    constexpr double kBlendCutoff = 0.5;
    if (const auto extension = source.extensions.find("KHR_materials_transmission");
        extension != source.extensions.end() && extension->second.IsObject() &&
        extension->second.Get("transmissionFactor").IsNumber() &&
        extension->second.Get("transmissionFactor").GetNumberAsDouble() > kBlendCutoff)
      return kCutsOutEverywhere;
    if (source.alphaMode == "OPAQUE") return 0.0f;
    if (source.alphaMode != "MASK" && source.alphaMode != "BLEND")
      fail(path_, where + ".alphaMode '" + source.alphaMode + "' is not OPAQUE, MASK or BLEND");
    const double cutoff = source.alphaMode == "BLEND" ? kBlendCutoff : source.alphaCutoff;
    const std::vector<double>& factor = source.pbrMetallicRoughness.baseColorFactor;
    const double factorAlpha = factor.size() == 4 ? factor[3] : 1.0;
    if (cutoff <= 0.0) return 0.0f;
    if (factorAlpha * kCutsOutEverywhere <= cutoff) return kCutsOutEverywhere;
    return static_cast<float>(cutoff / factorAlpha);
  }

  void convertMaterials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& source = model_.materials[i];
      const std::string where = "materials[" + std::to_string(i) + "]";
      Material material;
      material.name = source.name;
      material.baseColor = rgbOr(source.pbrMetallicRoughness.baseColorFactor, glm::vec3(1.0f));
      material.baseColorTexture =
          textureFor(source.pbrMetallicRoughness.baseColorTexture, where + ".pbrMetallicRoughness.baseColorTexture");
      float strength = 1.0f;
      if (const auto extension = source.extensions.find("KHR_materials_emissive_strength");
          extension != source.extensions.end() && extension->second.IsObject() &&
          extension->second.Get("emissiveStrength").IsNumber()) {
        strength = static_cast<float>(extension->second.Get("emissiveStrength").GetNumberAsDouble());
      }
      material.emission = rgbOr(source.emissiveFactor, glm::vec3(0.0f)) * strength;
      if (material.emission != glm::vec3(0.0f))
        material.emissionTexture = textureFor(source.emissiveTexture, where + ".emissiveTexture");
      material.alphaCutoff = alphaCutoff(source, where);
      scene_.materials.push_back(std::move(material));
    }
  }

  // The primitive's material, or a white one (glTF's default material) shared by all primitives without one.
  uint32_t materialFor(int material, const std::string& user) {
    if (material >= 0) {
      checkIndex(material, model_.materials.size(), "materials", user);
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
    checkIndex(info.index, model_.textures.size(), "textures", user + ".index");
    const int imageIndex = model_.textures[static_cast<size_t>(info.index)].source;
    const std::string textureName = "textures[" + std::to_string(info.index) + "]";
    // A texture without a source names its image only through an extension (KTX2, WebP…), which we cannot decode.
    if (imageIndex < 0) fail(path_, textureName + " has no image in a format we can read (PNG or JPEG)");
    checkIndex(imageIndex, model_.images.size(), "images", textureName + ".source");
    if (const auto cached = textureCache_.find(imageIndex); cached != textureCache_.end()) return cached->second;

    const tinygltf::Image& image = model_.images[static_cast<size_t>(imageIndex)];
    const std::string imageName = "images[" + std::to_string(imageIndex) + "] ('" +
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

  void addCamera(const tinygltf::Camera& source, const tinygltf::Node& node, const std::string& where,
                 const glm::mat4& world) {
    // Our renderer draws perspective views only.
    if (source.type != "perspective") return;
    const glm::dmat3 rotation{glm::mat3(world)};
    const std::optional<glm::vec3> forward = unitVector(rotation * glm::dvec3(0.0, 0.0, -1.0));
    const std::optional<glm::vec3> up = unitVector(rotation * glm::dvec3(0.0, 1.0, 0.0));
    if (!forward || !up || glm::length(glm::cross(glm::dvec3(*forward), glm::dvec3(*up))) < kMinDirectionSine) {
      fail(path_, where + " holds a camera, but its transform collapses the view and up directions into one");
    }
    Camera camera;
    camera.name = source.name.empty() ? node.name : source.name;
    camera.position = glm::vec3(world[3]);
    camera.target = camera.position + *forward;
    camera.up = *up;
    // DocumentCheck has bounded yfov and znear; tinygltf gives 0 for an absent one.
    if (source.perspective.yfov > 0.0) camera.verticalFov = static_cast<float>(source.perspective.yfov);
    if (source.perspective.znear > 0.0) camera.nearPlane = static_cast<float>(source.perspective.znear);
    scene_.cameras.push_back(std::move(camera));
  }

  // KHR_lights_punctual: lights shine along the node's −Z. Intensities are used as given (candela as W/sr, lux as
  // W/m²); DocumentCheck has bounded them, the colours and the cone angles.
  void addLight(int lightIndex, const tinygltf::Node& node, const std::string& where, const glm::mat4& world) {
    const tinygltf::Light& source = model_.lights[static_cast<size_t>(lightIndex)];
    const std::string lightPath = "extensions.KHR_lights_punctual.lights[" + std::to_string(lightIndex) + "]";
    const glm::vec3 intensity = rgbOr(source.color, glm::vec3(1.0f)) * static_cast<float>(source.intensity);
    const std::string name = source.name.empty() ? node.name : source.name;
    if (source.type != "directional" && source.type != "spot" && source.type != "point") {
      fail(path_, lightPath + " has the unknown type '" + source.type + "'");
    }
    const std::optional<glm::vec3> forward = unitVector(glm::dmat3(glm::mat3(world)) * glm::dvec3(0.0, 0.0, -1.0));
    if (!forward && source.type != "point") {
      fail(path_, where + " holds a " + source.type + " light, but its transform collapses the light's direction");
    }
    if (source.type == "directional") {
      // The scene has one sun: the first directional light.
      if (!scene_.sun.enabled) scene_.sun = {.enabled = true, .direction = -*forward, .illuminance = intensity};
      return;
    }
    LocalLight light{.name = name,
                     .position = glm::vec3(world[3]),
                     .direction = forward.value_or(glm::vec3(0.0f, 0.0f, -1.0f)),
                     .intensity = intensity,
                     .range = static_cast<float>(source.range)};
    if (source.type == "spot") {
      if (source.spot.innerConeAngle > source.spot.outerConeAngle) {
        fail(path_, lightPath + ".spot.innerConeAngle " + numberText(source.spot.innerConeAngle) +
                        " is larger than its outerConeAngle " + numberText(source.spot.outerConeAngle));
      }
      light.type = LightType::Spot;
      light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
      light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
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
  const fs::path path_;
  Scene scene_;
  std::vector<int> instanceNodes_;  // the node of each of scene_.instances
  std::vector<bool> visited_;
  std::map<std::pair<int, bool>, std::vector<uint32_t>> meshCache_;  // (glTF mesh, mirrored) → our meshes
  std::map<int, uint32_t> textureCache_;                             // glTF image → Scene::textures
  std::optional<uint32_t> defaultMaterial_;
};

}  // namespace

Scene loadGltf(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::error_code error;
  if (!fs::exists(path, error)) fail(path, "file not found");
  if (extension != ".gltf" && extension != ".glb") fail(path, "not a glTF file (expected .gltf or .glb)");
  std::vector<uint8_t> bytes;
  try {
    bytes = readFileBytes(path, kMaxFileBytes);
  } catch (const ImageIoError& readError) {
    throw SceneLoadError(readError.what());
  }

  const bool binary = extension == ".glb";
  const std::string_view json =
      binary ? glbJsonChunk(path, bytes) : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  checkJsonNesting(path, json);
  try {
    DocumentCheck(path).run(Json::parse(json));
  } catch (const Json::exception& parseError) {
    // nlohmann's what() starts with its own "[json.exception.parse_error.101] ".
    const std::string_view message = parseError.what();
    fail(path, "not valid JSON: " + std::string(message.substr(message.find("] ") + 2)));
  }

  ReferencedFiles files;
  files.folder = fs::canonical(fs::absolute(path).parent_path(), error).string();
  if (error) fail(path, "cannot resolve its folder: " + error.message());
  if (!files.folder.ends_with('/')) files.folder += '/';
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&referenceExists, &expandNothing, &readReference, nullptr, &files});
  loader.SetImageLoader(&decodeImage, nullptr);
  tinygltf::Model model;
  std::string problems;
  std::string warnings;  // unknown extensions, unused data: the file still loads
  const bool loaded = binary ? loader.LoadBinaryFromMemory(&model, &problems, &warnings, bytes.data(),
                                                           static_cast<unsigned int>(bytes.size()), files.folder)
                             : loader.LoadASCIIFromString(&model, &problems, &warnings, json.data(),
                                                          static_cast<unsigned int>(json.size()), files.folder);
  // A refused reference fails the load even where tinygltf goes on without it (an image it could not read).
  if (!files.refusal.empty()) fail(path, files.refusal);
  if (!loaded) fail(path, problems.empty() ? "could not be parsed" : problems);

  Scene scene = GltfConverter(model, path).convert();
  scene.name = path.stem().string();
  return scene;
}

}  // namespace ssvgi::renderer
