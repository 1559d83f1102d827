// The loaders fuzzed in-process: a mutation generator over the shared Cornell box (its .gltf and .bin, and a GLB made
// of the two) and over small EXRs of every compression. Each case must either load, with every value finite and within
// the loader's documented bounds, or throw the loader's one-line error naming the file. A crash fails the test run,
// a hang fails it at ctest's timeout, and any other exception fails the case, printing its number.
//
// The mutations mix what breaks parsers (bytes flipped, inserted, cut; GLB headers and chunk lengths; EXR header
// fields) with what breaks values (numbers replaced by 0, −1, 1e30, 1e300, 2^31…; members of the wrong type, removed
// or duplicated; indices moved; floats of the buffer replaced by NaN, infinities and extremes).
//
// Deterministic: case i draws from a generator seeded with (SSVGI_FUZZ_SEED, i), 1 by default, so a failing case is
// reproduced by its number alone. ctest runs kDefaultCases of each kind, a few seconds (docs/PERFORMANCE.md, "Tests").
// A longer campaign, best in the sanitized build, which also catches memory errors that do not crash (what the
// campaigns found: docs/QUALITY.md, "What the tests establish"):
//
//   SSVGI_FUZZ_CASES=200000 SSVGI_FUZZ_SEED=2 ./build/tests/ssvgi_cpu_tests_sanitized --gtest_filter='Fuzz*'
//
// and one case again: SSVGI_FUZZ_FIRST=1234 SSVGI_FUZZ_CASES=1 (same seed). SSVGI_FUZZ_KEEP=DIR keeps each failing
// case's files in DIR.
#include "gltf_loader.h"
#include "image_compare.h"
#include "image_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tinyexr.h>

#include <glm/gtc/constants.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

#include <unistd.h>

namespace ssvgi::renderer {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Bytes = std::vector<uint8_t>;

constexpr uint64_t kDefaultCases = 3000;

uint64_t environmentNumber(const char* name, uint64_t fallback) {
  const char* text = std::getenv(name);
  return text != nullptr ? std::strtoull(text, nullptr, 10) : fallback;
}

Bytes readBytes(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

Bytes bytesOf(const std::string& text) { return {text.begin(), text.end()}; }

// A random source with the helpers the mutations need.
class Random {
 public:
  Random(uint64_t seed, uint64_t caseIndex) {
    std::seed_seq sequence{uint32_t(seed), uint32_t(seed >> 32), uint32_t(caseIndex), uint32_t(caseIndex >> 32)};
    engine_.seed(sequence);
  }
  size_t below(size_t count) { return std::uniform_int_distribution<size_t>(0, count - 1)(engine_); }
  bool chance(double probability) { return std::bernoulli_distribution(probability)(engine_); }
  template <typename T, size_t N>
  const T& pick(const std::array<T, N>& values) {
    return values[below(N)];
  }

 private:
  std::mt19937_64 engine_;
};

// Numbers at the edges of what a loader must handle: zero, signs, float and int limits, angles near π/2.
constexpr std::array<double, 22> kEdgeNumbers = {0.0,
                                                 -0.0,
                                                 1.0,
                                                 -1.0,
                                                 0.5,
                                                 2.0,
                                                 1e-30,
                                                 -1e-30,
                                                 1e30,
                                                 -1e30,
                                                 3.5e38,
                                                 1e300,
                                                 -1e300,
                                                 65505.0,
                                                 1e10,
                                                 2147483647.0,
                                                 2147483648.0,
                                                 4294967296.0,
                                                 -2147483649.0,
                                                 1.5707963267948966,
                                                 3.141592653589793,
                                                 9007199254740993.0};
constexpr std::array<float, 10> kEdgeFloats = {std::numeric_limits<float>::quiet_NaN(),
                                               std::numeric_limits<float>::infinity(),
                                               -std::numeric_limits<float>::infinity(),
                                               std::numeric_limits<float>::max(),
                                               std::numeric_limits<float>::denorm_min(),
                                               1e30f,
                                               -1e30f,
                                               0.0f,
                                               -0.0f,
                                               1.0f};
constexpr std::array<uint32_t, 8> kEdgeWords = {0u, 1u, 2u, 3u, 0x7fffffffu, 0x80000000u, 0xffffffffu, 0x10000u};

// Byte-level mutations, for any file.
void mutateBytes(Bytes& bytes, Random& random) {
  if (bytes.empty()) {
    bytes.push_back(uint8_t(random.below(256)));
    return;
  }
  const size_t at = random.below(bytes.size());
  switch (random.below(6)) {
    case 0:  // flip a bit
      bytes[at] ^= uint8_t(1u << random.below(8));
      break;
    case 1:  // a random byte
      bytes[at] = uint8_t(random.below(256));
      break;
    case 2:  // cut short
      bytes.resize(at);
      break;
    case 3:  // remove a run
      bytes.erase(bytes.begin() + std::ptrdiff_t(at),
                  bytes.begin() + std::ptrdiff_t(std::min(bytes.size(), at + 1 + random.below(64))));
      break;
    case 4: {  // repeat a run
      const Bytes run(bytes.begin() + std::ptrdiff_t(at),
                      bytes.begin() + std::ptrdiff_t(std::min(bytes.size(), at + 1 + random.below(64))));
      bytes.insert(bytes.begin() + std::ptrdiff_t(random.below(bytes.size())), run.begin(), run.end());
      break;
    }
    default: {  // a 32-bit word at an aligned place: lengths, offsets, counts
      const size_t word = at & ~size_t{3};
      if (word + 4 <= bytes.size()) {
        const uint32_t value = random.pick(kEdgeWords);
        std::memcpy(&bytes[word], &value, sizeof(value));
      }
      break;
    }
  }
}

// A random value of the document, as a pointer into it.
Json::json_pointer randomValue(const Json& document, Random& random) {
  std::vector<Json::json_pointer> values;
  const std::function<void(const Json&, const Json::json_pointer&)> collect = [&](const Json& value,
                                                                                  const Json::json_pointer& at) {
    values.push_back(at);
    if (value.is_object()) {
      for (const auto& member : value.items()) collect(member.value(), at / member.key());
    } else if (value.is_array()) {
      for (size_t i = 0; i < value.size(); ++i) collect(value[i], at / i);
    }
  };
  collect(document, Json::json_pointer());
  return values[random.below(values.size())];
}

// Structure-aware mutations of the glTF JSON.
void mutateJson(Json& document, Random& random) {
  const Json::json_pointer at = randomValue(document, random);
  Json& value = document[at];
  switch (random.below(7)) {
    case 0:
    case 1:
      value = random.pick(kEdgeNumbers);
      break;
    case 2:
      if (value.is_number_integer()) {
        value = value.get<int64_t>() + (random.chance(0.5) ? 1 : -1);
      } else {
        value = random.pick(kEdgeNumbers) * (value.is_number() ? value.get<double>() : 1.0);
      }
      break;
    case 3: {  // another type
      static const std::array<Json, 7> kOthers = {Json("x"),
                                                  Json(true),
                                                  Json(nullptr),
                                                  Json::array(),
                                                  Json::object(),
                                                  Json::array({1, 2, 3}),
                                                  Json::object({{"a", 1}})};
      value = random.pick(kOthers);
      break;
    }
    case 4:  // gone
      if (!at.empty()) {
        Json& parent = document[at.parent_pointer()];
        if (parent.is_object()) {
          parent.erase(at.back());
        } else {
          parent.erase(std::stoul(at.back()));
        }
      }
      break;
    case 5:  // twice
      if (value.is_array() && !value.empty()) value.push_back(value[random.below(value.size())]);
      break;
    default:  // another part of the document in its place
      value = document[randomValue(document, random)];
      break;
  }
}

// A GLB made of the document (its buffer then read from the BIN chunk) and the buffer's bytes.
Bytes glbOf(Json document, const Bytes& bin) {
  if (document.contains("buffers") && document["buffers"].is_array() && !document["buffers"].empty() &&
      document["buffers"][0].is_object()) {
    document["buffers"][0].erase("uri");
  }
  std::string json = document.dump();
  while (json.size() % 4 != 0) json += ' ';
  Bytes paddedBin = bin;
  while (paddedBin.size() % 4 != 0) paddedBin.push_back(0);
  Bytes glb = {'g', 'l', 'T', 'F'};
  const auto word = [&](uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) glb.push_back(uint8_t(value >> shift));
  };
  word(2);
  word(uint32_t(12 + 8 + json.size() + 8 + paddedBin.size()));
  word(uint32_t(json.size()));
  word(0x4E4F534Au);  // JSON
  glb.insert(glb.end(), json.begin(), json.end());
  word(uint32_t(paddedBin.size()));
  word(0x004E4942u);  // BIN
  glb.insert(glb.end(), paddedBin.begin(), paddedBin.end());
  return glb;
}

// What loadGltf promises of a scene it returns (gltf_loader.h): every value finite and within its bounds.
void expectWithinTheLoadersBounds(const Scene& scene) {
  constexpr float kReach = 1e5f;
  const auto finite = [](const auto& vector) {
    for (int i = 0; i < vector.length(); ++i)
      if (!std::isfinite(vector[i])) return false;
    return true;
  };
  for (const Material& material : scene.materials) {
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(material.baseColor, glm::vec3(0.0f))) &&
                glm::all(glm::lessThanEqual(material.baseColor, glm::vec3(1.0f))))
        << material.name;
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(material.emission, glm::vec3(0.0f))) &&
                glm::all(glm::lessThanEqual(material.emission, glm::vec3(65504.0f))))
        << material.name;
  }
  for (const Instance& instance : scene.instances) {
    ASSERT_LT(instance.mesh, scene.meshes.size());
    const Mesh& mesh = scene.meshes[instance.mesh];
    ASSERT_LT(mesh.material, scene.materials.size());
    EXPECT_GE(std::abs(glm::determinant(glm::dmat3(glm::mat3(instance.transform)))), 1e-24);
    for (const uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertices.size());
    for (const Vertex& vertex : mesh.vertices) {
      const glm::vec3 world(instance.transform * glm::vec4(vertex.position, 1.0f));
      ASSERT_TRUE(glm::all(glm::lessThanEqual(glm::abs(world), glm::vec3(kReach)))) << mesh.name;
      ASSERT_NEAR(glm::length(vertex.normal), 1.0f, 1e-3f) << mesh.name;
      ASSERT_TRUE(finite(vertex.uv)) << mesh.name;
    }
  }
  for (const LocalLight& light : scene.lights) {
    EXPECT_TRUE(glm::all(glm::lessThanEqual(glm::abs(light.position), glm::vec3(kReach)))) << light.name;
    EXPECT_NEAR(glm::length(light.direction), 1.0f, 1e-3f) << light.name;
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(light.intensity, glm::vec3(0.0f))) &&
                glm::all(glm::lessThanEqual(light.intensity, glm::vec3(1e5f))))
        << light.name;
    EXPECT_TRUE(light.range >= 0.0f && std::isfinite(light.range)) << light.name;
    EXPECT_TRUE(light.innerConeAngle >= 0.0f && light.innerConeAngle <= light.outerConeAngle &&
                light.outerConeAngle < glm::half_pi<float>())
        << light.name;
  }
  if (scene.sun.enabled) {
    EXPECT_NEAR(glm::length(scene.sun.direction), 1.0f, 1e-3f);
    EXPECT_TRUE(finite(scene.sun.illuminance) && glm::all(glm::lessThanEqual(scene.sun.illuminance, glm::vec3(1e5f))));
  }
  ASSERT_FALSE(scene.cameras.empty());
  for (const Camera& camera : scene.cameras) {
    EXPECT_TRUE(glm::all(glm::lessThanEqual(glm::abs(camera.position), glm::vec3(kReach)))) << camera.name;
    EXPECT_TRUE(finite(camera.target) && finite(camera.up)) << camera.name;
    EXPECT_GT(glm::length(glm::cross(glm::normalize(camera.target - camera.position), camera.up)), 1e-4f)
        << camera.name;
    EXPECT_TRUE(camera.verticalFov >= 1e-3f && camera.verticalFov <= glm::pi<float>() - 1e-3f) << camera.name;
    EXPECT_TRUE(camera.nearPlane > 0.0f && camera.nearPlane <= kReach) << camera.name;
  }
  for (const Texture& texture : scene.textures)
    EXPECT_EQ(texture.rgba.size(), size_t{texture.width} * texture.height * 4);
}

// The cases of one kind: `runCase(random, folder)` runs one, returning "" when it kept the loader's promise and what it
// broke otherwise. Each case's files are written into a folder of the test's own.
void fuzz(const char* kind, const std::function<std::string(Random&, const fs::path&)>& runCase) {
  const uint64_t seed = environmentNumber("SSVGI_FUZZ_SEED", 1);
  const uint64_t first = environmentNumber("SSVGI_FUZZ_FIRST", 0);
  const uint64_t count = environmentNumber("SSVGI_FUZZ_CASES", kDefaultCases);
  const fs::path folder =
      fs::temp_directory_path() / ("ssvgi_fuzz_" + std::string(kind) + "_" + std::to_string(getpid()));
  fs::create_directories(folder);
  uint64_t failures = 0;
  const ::testing::TestResult& result = *::testing::UnitTest::GetInstance()->current_test_info()->result();
  for (uint64_t index = first; index < first + count && failures < 10; ++index) {
    Random random(seed, index);
    const int reportsBefore = result.total_part_count();
    std::string broken;
    try {
      broken = runCase(random, folder);
    } catch (const std::exception& error) {
      broken = std::string("threw ") + typeid(error).name() + ": " + error.what();
    }
    if (broken.empty() && result.total_part_count() == reportsBefore) continue;  // no EXPECT failed either
    ++failures;
    ADD_FAILURE() << kind << " case " << index << " (SSVGI_FUZZ_SEED=" << seed << " SSVGI_FUZZ_FIRST=" << index
                  << " SSVGI_FUZZ_CASES=1): " << (broken.empty() ? "see the failures above" : broken);
    if (const char* keep = std::getenv("SSVGI_FUZZ_KEEP")) {
      fs::copy(folder, fs::path(keep) / (std::string(kind) + "_" + std::to_string(index)),
               fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    }
  }
  fs::remove_all(folder);
}

// "" for a SceneLoadError that is one line naming the file; what is wrong with it otherwise.
std::string checkLoadError(const SceneLoadError& error, const fs::path& file) {
  const std::string message = error.what();
  if (message.find(file.filename().string()) == std::string::npos)
    return "the error does not name the file: " + message;
  if (message.find('\n') != std::string::npos) return "the error is not one line: " + message;
  return "";
}

TEST(Fuzz, gltfAndGlbMutationsOfTheCornellBoxLoadFiniteOrFailWithOneLine) {
  const fs::path cornell = fs::path(SSVGI_SHARED_DIR) / "scenes" / "cornell-box";
  const Json original = Json::parse(readBytes(cornell / "CornellBox-PointLight.gltf"));
  const Bytes originalBin = readBytes(cornell / "CornellBox-Original.bin");
  ASSERT_FALSE(originalBin.empty());

  fuzz("gltf", [&](Random& random, const fs::path& folder) -> std::string {
    Json document = original;
    for (size_t mutations = 1 + random.below(4); mutations > 0; --mutations) mutateJson(document, random);
    Bytes bin = originalBin;
    if (random.chance(0.3)) {  // floats of the buffer: positions, normals
      for (size_t floats = 1 + random.below(8); floats > 0; --floats) {
        const size_t at = 4 * random.below(bin.size() / 4);
        const float value = random.pick(kEdgeFloats);
        std::memcpy(&bin[at], &value, sizeof(value));
      }
    }
    if (random.chance(0.1)) mutateBytes(bin, random);
    const bool binary = random.chance(0.3);
    Bytes file = binary ? glbOf(document, bin) : bytesOf(document.dump());
    if (random.chance(0.2)) {
      for (size_t mutations = 1 + random.below(3); mutations > 0; --mutations) mutateBytes(file, random);
    }
    const fs::path path = folder / (binary ? "case.glb" : "case.gltf");
    writeBytes(path, file);
    writeBytes(folder / "CornellBox-Original.bin", bin);
    try {
      expectWithinTheLoadersBounds(loadGltf(path));
      return "";
    } catch (const SceneLoadError& error) {
      return checkLoadError(error, path);
    }
  });
}

// An EXR of a small image with each of tinyexr's compressions, written by tinyexr itself.
Bytes exrWithCompression(int compression, size_t channelCount) {
  constexpr int kWidth = 19;
  constexpr int kHeight = 21;  // more than one block of 16 (ZIP) or 32 (PIZ) lines
  std::vector<std::vector<float>> planes(channelCount, std::vector<float>(kWidth * kHeight));
  std::vector<uint8_t*> planePointers;
  for (size_t channel = 0; channel < channelCount; ++channel) {
    for (size_t pixel = 0; pixel < planes[channel].size(); ++pixel)
      planes[channel][pixel] = std::sin(float(pixel * 7 + channel)) * 100.0f;
    planePointers.push_back(reinterpret_cast<uint8_t*>(planes[channel].data()));
  }
  std::vector<EXRChannelInfo> channels(channelCount);
  const char* names[] = {"A", "B", "G", "R"};  // sorted, as OpenEXR lists them
  for (size_t channel = 0; channel < channelCount; ++channel) {
    std::strcpy(channels[channel].name, channelCount == 1 ? "Y" : names[channel + 4 - channelCount]);
  }
  std::vector<int> pixelTypes(channelCount, TINYEXR_PIXELTYPE_HALF);
  std::vector<int> requestedTypes(
      channelCount, compression == TINYEXR_COMPRESSIONTYPE_NONE ? TINYEXR_PIXELTYPE_FLOAT : TINYEXR_PIXELTYPE_HALF);
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = static_cast<int>(channelCount);
  header.channels = channels.data();
  header.pixel_types = pixelTypes.data();
  header.requested_pixel_types = requestedTypes.data();
  header.compression_type = compression;
  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = static_cast<int>(channelCount);
  image.width = kWidth;
  image.height = kHeight;
  image.images = planePointers.data();
  unsigned char* encoded = nullptr;
  const char* message = nullptr;
  const size_t size = SaveEXRImageToMemory(&image, &header, &encoded, &message);
  EXPECT_GT(size, 0u) << (message != nullptr ? message : "");
  Bytes bytes(encoded, encoded + size);
  std::free(encoded);
  return bytes;
}

TEST(Fuzz, exrMutationsReadAndCompareOrFailWithOneLine) {
  std::vector<Bytes> originals;
  for (const int compression : {TINYEXR_COMPRESSIONTYPE_NONE, TINYEXR_COMPRESSIONTYPE_RLE, TINYEXR_COMPRESSIONTYPE_ZIPS,
                                TINYEXR_COMPRESSIONTYPE_ZIP, TINYEXR_COMPRESSIONTYPE_PIZ}) {
    for (const size_t channels : {1, 3, 4}) originals.push_back(exrWithCompression(compression, channels));
  }
  for (const Bytes& original : originals) ASSERT_FALSE(original.empty());

  fuzz("exr", [&](Random& random, const fs::path& folder) -> std::string {
    Bytes file = originals[random.below(originals.size())];
    for (size_t mutations = 1 + random.below(4); mutations > 0; --mutations) mutateBytes(file, random);
    const fs::path path = folder / "case.exr";
    writeBytes(path, file);
    FloatImage image;
    try {
      image = readExr(path);
    } catch (const ImageIoError& error) {
      const std::string message = error.what();
      if (message.find(path.string()) == std::string::npos) return "the error does not name the file: " + message;
      if (message.find('\n') != std::string::npos) return "the error is not one line: " + message;
      return "";
    }
    if (image.width == 0 || image.height == 0 || (image.channels != 1 && image.channels != 3 && image.channels != 4) ||
        image.pixels.size() != size_t{image.width} * image.height * image.channels) {
      return "an image of " + std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
             std::to_string(image.channels) + " with " + std::to_string(image.pixels.size()) + " values";
    }
    // What `ssvgi compare` does next: finite figures, or its one-line refusal (NaN pixels, a black image).
    try {
      const reference::ImageComparison comparison = reference::compareImages(image, image, nullptr, 1);
      if (!std::isfinite(comparison.relativeMeanAbsoluteError) || !std::isfinite(comparison.rmse) ||
          !std::isfinite(comparison.ssim)) {
        return "a comparison with non-finite figures";
      }
    } catch (const reference::ImageCompareError& error) {
      if (std::string(error.what()).find('\n') != std::string::npos) return "the comparison error is not one line";
    }
    return "";
  });
}

}  // namespace
}  // namespace ssvgi::renderer
