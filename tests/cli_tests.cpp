// The ssvgi CLI end to end: it runs the real executable (path from CMake) at a small size, with validation on.
#include "image_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <regex>
#include <set>
#include <string>
#include <utility>

namespace ssvgi {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

// `environment`: VAR=value assignments for the child process only.
CliRun runCli(const std::string& arguments, const std::string& environment = "") {
  const std::string command = environment + " " + std::string(SSVGI_CLI_PATH) + " " + arguments + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), int(buffer.size()), pipe)) run.output += buffer.data();
  const int status = pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

// A directory of this process: ctest runs every test in a process of its own, several at a time, and the parameterised
// tests share names. Removed when the process's tests end.
std::set<fs::path>& processDirectories() {
  static std::set<fs::path> directories;
  return directories;
}

fs::path processDirectory(const std::string& name) {
  const fs::path directory = fs::temp_directory_path() / ("ssvgi-cli-test-" + name + "-" + std::to_string(getpid()));
  processDirectories().insert(directory);
  return directory;
}

class RemoveProcessDirectories : public ::testing::Environment {
 public:
  void TearDown() override {
    for (const fs::path& directory : processDirectories()) fs::remove_all(directory);
  }
};
[[maybe_unused]] const ::testing::Environment* const kRemoveProcessDirectories =
    ::testing::AddGlobalTestEnvironment(new RemoveProcessDirectories);

fs::path freshDirectory(const std::string& name) {
  const fs::path directory = processDirectory(name);
  fs::remove_all(directory);
  return directory;
}

size_t lineCount(const std::string& text) {
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

TEST(Cli, renderWritesEveryImageAndStatsForTheLastFrame) {
  const fs::path out = freshDirectory("render");
  const CliRun run = runCli("render --scene cornell --size 64x48 --frames 2 --gi off --validation --out " + out.string());
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_TRUE(fs::file_size(out / "final.png") > 0);
  for (const char* name : {"final.exr", "irradiance_direct.exr", "irradiance_indirect.exr", "albedo.exr", "normal.exr"}) {
    const auto image = renderer::readExr(out / name);
    EXPECT_EQ(image.width, 64u) << name;
    EXPECT_EQ(image.height, 48u) << name;
    EXPECT_EQ(image.channels, 3u) << name;
  }
  const auto depth = renderer::readExr(out / "depth.exr");
  EXPECT_EQ(depth.channels, 1u);
  const auto confidence = renderer::readExr(out / "confidence.exr");
  EXPECT_EQ(confidence.width, 64u);
  EXPECT_EQ(confidence.channels, 1u);
  for (float v : confidence.pixels) ASSERT_EQ(v, 0.0f) << "GI off: ssvgi knows nothing";

  // With GI off there is no indirect light at all, and the box's ceiling light lights something directly.
  float indirectMax = 0.0f, directMax = 0.0f, distanceMax = 0.0f;
  for (float v : renderer::readExr(out / "irradiance_indirect.exr").pixels) indirectMax = std::max(indirectMax, v);
  for (float v : renderer::readExr(out / "irradiance_direct.exr").pixels) directMax = std::max(directMax, v);
  for (float v : depth.pixels) distanceMax = std::max(distanceMax, v);
  EXPECT_EQ(indirectMax, 0.0f);
  EXPECT_GT(directMax, 0.0f);
  EXPECT_GT(distanceMax, 1.0f);  // the back wall is metres away from the camera

  std::ifstream statsFile(out / "stats.json");
  const auto stats = nlohmann::json::parse(statsFile);
  EXPECT_EQ(stats["width"], 64);
  EXPECT_EQ(stats["frames"], 2);
  for (const char* pass : {"renderer: Shadow", "renderer: GBuffer", "renderer: DirectLighting", "renderer: Composite",
                           "renderer: Tonemap"})
    EXPECT_TRUE(stats["gpuMilliseconds"]["passes"].contains(pass)) << pass;
  EXPECT_GT(stats["memoryBytes"]["total"].get<uint64_t>(), 0u);
}

TEST(Cli, renderAppliesTheTierTheScenesDetailScaleAndGiOverridesInThatOrder) {
  const fs::path out = freshDirectory("render-gi-set");
  const CliRun run = runCli("render --scene cornell --size 32x32 --frames 1 --tier low --gi-set probeBudget=300 "
                            "--gi-set volumeBricks=24,16,24 --out " + out.string());
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream statsFile(out / "stats.json");
  const auto settings = nlohmann::json::parse(statsFile)["giSettings"];
  EXPECT_EQ(settings["raysPerProbe"], 16);       // the low tier's
  EXPECT_EQ(settings["voxelSize"], 0.125);      // 0.25 m × the Cornell box's detail scale of 0.5
  EXPECT_EQ(settings["probeSpacing"], 0.5);
  EXPECT_EQ(settings["probeBudget"], 300);       // overridden
  EXPECT_EQ(settings["volumeBricks"], nlohmann::json({24, 16, 24}));
}

TEST(Cli, renderWithAMemoryBudgetReportsItAndTheSettingsItChose) {
  const fs::path out = freshDirectory("render-memory-budget");
  const CliRun run = runCli("render --scene cornell --size 32x32 --frames 1 --memory-budget 0.3 --out " + out.string());
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream statsFile(out / "stats.json");
  const auto stats = nlohmann::json::parse(statsFile);
  const uint64_t budget = std::llround(0.3 * 1048576.0);  // MB of 2^20 bytes
  EXPECT_EQ(stats["ssvgi"]["memoryBudgetBytes"].get<uint64_t>(), budget);
  EXPECT_LE(stats["ssvgi"]["memoryBytes"]["total"].get<uint64_t>(), budget);
  // The tier's settings do not fit: the pool shrank first, and the volume too, to fit so little.
  const auto& asked = stats["giSettings"];
  const auto& used = stats["ssvgi"]["settings"];
  EXPECT_LT(used["brickPoolCapacity"].get<uint32_t>(), asked["brickPoolCapacity"].get<uint32_t>());
  EXPECT_LT(used["volumeBricks"][0].get<uint32_t>(), asked["volumeBricks"][0].get<uint32_t>());
  EXPECT_EQ(used["raysPerProbe"], asked["raysPerProbe"]);  // what the budget does not size stays
}

TEST(Cli, benchReportsTheWorkOfSsvgisPassesInOneMoreFrame) {
  const fs::path out = freshDirectory("bench-work");
  fs::create_directories(out);
  const CliRun run = runCli("bench --scene cornell --size 32x32 --frames 3 --measured-frames 2 "
                            "--gi-set raysPerProbe=16 --rays 100 --repetitions 1 --pixel-rays 4 --validation --out " +
                            (out / "bench.json").string());
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream reportFile(out / "bench.json");
  const auto report = nlohmann::json::parse(reportFile);
  // Each pass's median and mean over the measured frames: of two frames, the same.
  const auto& milliseconds = report["gpuMilliseconds"];
  ASSERT_TRUE(milliseconds["passes"].contains("ssvgi: ProbeTrace"));
  for (const auto& [pass, median] : milliseconds["passes"].items())
    EXPECT_NEAR(milliseconds["passMeans"].value(pass, -1.0), median.get<double>(), 1e-9) << pass;
  ASSERT_TRUE(report.contains("work"));
  const auto& work = report["work"];
  EXPECT_EQ(work["frame"], 3);  // after the 3 timed frames
  EXPECT_EQ(work["probeLevel"], 0);
  const auto& probeTrace = work["ProbeTrace"];
  EXPECT_GT(probeTrace["probes"].get<uint32_t>(), 0u);
  EXPECT_EQ(probeTrace["rays"].get<uint32_t>(), 16 * probeTrace["probes"].get<uint32_t>());
  EXPECT_DOUBLE_EQ(probeTrace["readsPerRay"].get<double>(),
                   probeTrace["reads"].get<double>() / probeTrace["rays"].get<double>());
  for (const char* pass : {"ProbeTrace", "ProbeRelocate", "VoxelRelight", "FinalGather"})
    for (const char* count : {"rays", "reads", "readsPerRay"}) EXPECT_TRUE(work[pass].contains(count)) << pass << count;
  EXPECT_TRUE(probeTrace.contains("seedRays"));
  const uint32_t tiles = work["FinalGather"]["tiles"].get<uint32_t>();
  EXPECT_GT(tiles, 0u);
  EXPECT_LE(tiles, 8u * 8u);  // 4×4-pixel tiles of 32×32
  EXPECT_GT(work["SceneVoxelization"]["voxels"].get<uint32_t>(), 0u);
  EXPECT_EQ(work["TemporalUpsample"]["pixels"], 16 * 16);
}

TEST(Cli, debugViewsAreSeenFromTheDebugCamera) {
  // The Cornell box's voxels from its own camera, and from a camera at the same place looking away from the box, out
  // of its open side into the empty volume: there every ray leaves the volume (black).
  const fs::path own = freshDirectory("debug-own"), away = freshDirectory("debug-away");
  const std::string render = "render --scene cornell --size 32x32 --frames 4 --debug voxels --validation --out ";
  const CliRun ownRun = runCli(render + own.string());
  ASSERT_EQ(ownRun.exitCode, 0) << ownRun.output;
  const CliRun awayRun = runCli(render + away.string() + " --debug-camera 0,1,3.4,0,1,10,40");
  ASSERT_EQ(awayRun.exitCode, 0) << awayRun.output;
  float ownMax = 0.0f, awayMax = 0.0f;
  for (float v : renderer::readExr(own / "debug_voxels.exr").pixels) ownMax = std::max(ownMax, v);
  for (float v : renderer::readExr(away / "debug_voxels.exr").pixels) awayMax = std::max(awayMax, v);
  EXPECT_GT(ownMax, 0.0f);
  EXPECT_EQ(awayMax, 0.0f);
}

TEST(Cli, renderWritesTheConfidenceAndItsDebugView) {
  const fs::path out = freshDirectory("confidence");
  const CliRun run =
      runCli("render --scene cornell --size 32x32 --frames 4 --debug confidence --validation --out " + out.string());
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("confidence.exr"), std::string::npos) << run.output;
  const auto confidence = renderer::readExr(out / "confidence.exr");
  ASSERT_EQ(confidence.channels, 1u);
  float highest = 0.0f;
  for (float v : confidence.pixels) {
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
    highest = std::max(highest, v);
  }
  EXPECT_GT(highest, 0.5f);  // probes lit the box
  // The debug view: grey where a ray meets a voxel, dark blue (0, 0, 0.25) where it meets none.
  const auto debug = renderer::readExr(out / "debug_confidence.exr");
  ASSERT_EQ(debug.channels, 3u);
  uint32_t grey = 0;
  for (size_t pixel = 0; pixel < debug.pixels.size() / 3; ++pixel) {
    const float r = debug.pixels[pixel * 3], g = debug.pixels[pixel * 3 + 1], b = debug.pixels[pixel * 3 + 2];
    if (r == 0.0f && g == 0.0f && b == 0.25f) continue;
    EXPECT_EQ(r, g);
    EXPECT_EQ(g, b);
    grey += r > 0.5f ? 1u : 0u;
  }
  EXPECT_GT(grey, 0u);
}

TEST(Cli, rendersTheSharedCornellBoxGltfFromItsOwnCamera) {
  const fs::path out = freshDirectory("gltf");
  const CliRun run = runCli("render --scene " SSVGI_SHARED_DIR "/scenes/cornell-box/CornellBox-Original.gltf --gi off "
                         "--size 64x64 --validation --out " + out.string());
  ASSERT_EQ(run.exitCode, 0) << run.output;
  // Seen from its own camera the box fills the view: most pixels hold a surface.
  const auto depth = renderer::readExr(out / "depth.exr");
  size_t surface = 0;
  for (float v : depth.pixels) surface += v > 0.0f;
  EXPECT_GT(surface, depth.pixels.size() / 2);
}

// `ssvgi reference` and `ssvgi compare` end to end. The suite traces the Cornell box once and renders the same view
// with GI off (both 32x32, validation on), into directories of this process.
class CliReference : public ::testing::Test {
 public:
  static constexpr uint32_t kSize = 32;

  static fs::path referenceOut() { return processDirectory("reference"); }
  static fs::path renderOut() { return processDirectory("reference-render"); }

  static void SetUpTestSuite() {
    fs::remove_all(referenceOut());
    fs::remove_all(renderOut());
    referenceRun() = runCli("reference --scene cornell --size 32x32 --spp 8 --validation --out " + referenceOut().string());
    renderRun() = runCli("render --scene cornell --size 32x32 --gi off --validation --out " + renderOut().string());
  }

 protected:
  static CliRun& referenceRun() {
    static CliRun run;
    return run;
  }
  static CliRun& renderRun() {
    static CliRun run;
    return run;
  }
};

// Width and height from a PNG's IHDR chunk (big-endian, bytes 16 to 23).
std::pair<uint32_t, uint32_t> pngSize(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::array<unsigned char, 24> header{};
  file.read(reinterpret_cast<char*>(header.data()), header.size());
  const auto bigEndian = [&](size_t at) {
    return uint32_t(header[at]) << 24 | uint32_t(header[at + 1]) << 16 | uint32_t(header[at + 2]) << 8 | header[at + 3];
  };
  return file ? std::pair{bigEndian(16), bigEndian(20)} : std::pair{0u, 0u};
}

TEST_F(CliReference, writesTheSameEightFilesAsRenderAtTheRequestedSize) {
  ASSERT_EQ(referenceRun().exitCode, 0) << referenceRun().output;
  EXPECT_NE(referenceRun().output.find("8 samples per pixel"), std::string::npos) << referenceRun().output;
  EXPECT_EQ(pngSize(referenceOut() / "final.png"), std::pair(kSize, kSize));
  for (const char* name : {"final.exr", "irradiance_direct.exr", "irradiance_indirect.exr", "albedo.exr", "normal.exr"}) {
    const auto image = renderer::readExr(referenceOut() / name);
    EXPECT_EQ(image.width, kSize) << name;
    EXPECT_EQ(image.height, kSize) << name;
    EXPECT_EQ(image.channels, 3u) << name;
  }
  const auto depth = renderer::readExr(referenceOut() / "depth.exr");
  EXPECT_EQ(depth.width, kSize);
  EXPECT_EQ(depth.height, kSize);
  EXPECT_EQ(depth.channels, 1u);
  float distanceMax = 0.0f;
  for (float v : depth.pixels) distanceMax = std::max(distanceMax, v);
  EXPECT_GT(distanceMax, 1.0f);  // the back wall is metres away from the camera

  std::ifstream statsFile(referenceOut() / "stats.json");
  const auto stats = nlohmann::json::parse(statsFile);
  EXPECT_EQ(stats["scene"], "cornell");
  EXPECT_EQ(stats["width"], kSize);
  EXPECT_EQ(stats["height"], kSize);
  EXPECT_EQ(stats["samplesPerPixel"], 8);
  EXPECT_EQ(stats["bounces"], 32);  // reference::kDefaultMaxBounces
  EXPECT_EQ(stats["seed"], 0);
  EXPECT_EQ(stats["time"], 0.0);
  EXPECT_NE(stats["device"].get<std::string>(), "");
  EXPECT_EQ(stats["bvh"]["triangles"], stats["sceneTriangles"]);
  EXPECT_GT(stats["bvh"]["nodes"].get<uint32_t>(), 0u);
  EXPECT_GT(stats["seconds"].get<double>(), 0.0);
  EXPECT_GT(stats["samplesPerSecond"].get<double>(), 0.0);
  for (const char* pass : {"reference: PrimaryHits", "reference: PathTrace", "renderer: Tonemap"})
    EXPECT_TRUE(stats["gpuMilliseconds"]["passes"].contains(pass)) << pass;
  EXPECT_GT(stats["memoryBytes"]["total"].get<uint64_t>(), 0u);
}

TEST_F(CliReference, cornellBoxHasBounceLight) {
  // Light bounces all over the box (albedo ~0.7, a glowing ceiling panel), so E_indirect is of the order of E_direct.
  // The box is open towards the camera and there is no sky: the short box's front face sends most of its paths out of
  // the open side into black, and the floor below them lies in that box's shadow, so after 8 samples a few of its
  // pixels have found no light yet (docs/QUALITY.md, "What the tests establish"); 90 % of all surface pixels must
  // have.
  ASSERT_EQ(referenceRun().exitCode, 0) << referenceRun().output;
  const auto indirect = renderer::readExr(referenceOut() / "irradiance_indirect.exr");
  const auto direct = renderer::readExr(referenceOut() / "irradiance_direct.exr");
  const auto depth = renderer::readExr(referenceOut() / "depth.exr");
  double indirectSum = 0.0, directSum = 0.0;
  size_t surface = 0, positive = 0;
  for (size_t pixel = 0; pixel < depth.pixels.size(); ++pixel) {
    if (depth.pixels[pixel] <= 0.0f) continue;
    const float* e = &indirect.pixels[pixel * 3];
    ASSERT_TRUE(std::isfinite(e[0]) && std::isfinite(e[1]) && std::isfinite(e[2])) << "pixel " << pixel;
    ASSERT_GE(std::min({e[0], e[1], e[2]}), 0.0f) << "pixel " << pixel;
    positive += e[0] + e[1] + e[2] > 0.0f;
    indirectSum += e[0] + e[1] + e[2];
    directSum += direct.pixels[pixel * 3] + direct.pixels[pixel * 3 + 1] + direct.pixels[pixel * 3 + 2];
    ++surface;
  }
  ASSERT_GT(surface, depth.pixels.size() / 2);
  EXPECT_GT(positive, surface * 9 / 10);
  EXPECT_GT(indirectSum, 0.2 * directSum) << "indirect " << indirectSum << " direct " << directSum;
}

TEST_F(CliReference, isBitIdenticalForTheSameSeedAndNotForAnother) {
  ASSERT_EQ(referenceRun().exitCode, 0) << referenceRun().output;
  const fs::path sameSeed = processDirectory("reference-seed0"), otherSeed = processDirectory("reference-seed1");
  const std::string arguments = "reference --scene cornell --size 32x32 --spp 8 --out ";
  ASSERT_EQ(runCli(arguments + sameSeed.string() + " --seed 0").exitCode, 0);
  ASSERT_EQ(runCli(arguments + otherSeed.string() + " --seed 1").exitCode, 0);
  const auto indirect = renderer::readExr(referenceOut() / "irradiance_indirect.exr").pixels;
  EXPECT_EQ(renderer::readExr(sameSeed / "irradiance_indirect.exr").pixels, indirect);
  EXPECT_NE(renderer::readExr(otherSeed / "irradiance_indirect.exr").pixels, indirect);
  EXPECT_EQ(renderer::readExr(otherSeed / "irradiance_direct.exr").pixels,
            renderer::readExr(referenceOut() / "irradiance_direct.exr").pixels)
      << "direct light is not random";
}

TEST_F(CliReference, compareOfAnImageWithItselfIsExact) {
  ASSERT_EQ(referenceRun().exitCode, 0) << referenceRun().output;
  const std::string image = (referenceOut() / "irradiance_indirect.exr").string();
  const CliRun run = runCli("compare " + image + " " + image + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const auto result = nlohmann::json::parse(run.output);
  EXPECT_EQ(result["relativeMeanAbsoluteError"], 0.0);
  EXPECT_EQ(result["rmse"], 0.0);
  EXPECT_NEAR(result["ssim"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(result["validPixels"], kSize * kSize);
  EXPECT_EQ(result["downsample"], 1);

  // The text form, with the mask and 4x4 blocks: only blocks wholly on a surface count.
  const std::string depth = (referenceOut() / "depth.exr").string();
  const CliRun text = runCli("compare " + image + " " + image + " --mask-from " + depth + " --downsample 4");
  ASSERT_EQ(text.exitCode, 0) << text.output;
  EXPECT_NE(text.output.find("relative mean absolute error  0\n"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("(4x4 blocks; mask: depth > 0 in"), std::string::npos) << text.output;
}

TEST_F(CliReference, renderedDirectLightIsWithinFivePercentOfTheReference) {
  // Same view, same size: the renderer's E_direct against the path tracer's exact one (no noise: a shadow ray to the
  // point light, nothing sampled). They differ only (a) where the renderer's shadow map decides otherwise than a
  // shadow ray: its 2x2 PCF and normal offset move shadow edges by about a pixel, above all the edge of the thin
  // light panel's shadow on the ceiling, cast at a grazing angle; (b) at pixels whose centre falls on a box edge,
  // where the rasterizer's tie rules and the ray's nearest hit may take different faces, one lit and one not. Each
  // pixel of such an edge weighs 1/1024 of the image at 32x32, and the edges are a few per cent of the pixels.
  // docs/QUALITY.md ("What the tests establish", "Direct light") has what lavapipe gives; 5 % leaves room for other
  // rasterizers' rules and shadow-map resolutions. The mask keeps the comparison to pixels where the renderer drew a surface.
  ASSERT_EQ(referenceRun().exitCode, 0) << referenceRun().output;
  ASSERT_EQ(renderRun().exitCode, 0) << renderRun().output;
  const CliRun run = runCli("compare " + (renderOut() / "irradiance_direct.exr").string() + " " +
                            (referenceOut() / "irradiance_direct.exr").string() + " --mask-from " +
                            (renderOut() / "depth.exr").string() + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const auto result = nlohmann::json::parse(run.output);
  EXPECT_LT(result["relativeMeanAbsoluteError"].get<double>(), 0.05) << run.output;
  EXPECT_GT(result["validPixels"].get<uint64_t>(), kSize * kSize / 2) << run.output;
}

TEST_F(CliReference, compareRefusesItsOwnFinalImageCutByOneByteWithOneLine) {
  // A truncated EXR freed its image twice in tinyexr's error path (SIGABRT) before the image reader forgot it.
  ASSERT_EQ(renderRun().exitCode, 0) << renderRun().output;
  const fs::path cut = processDirectory("cut") / "final.exr";
  fs::create_directories(cut.parent_path());
  fs::copy_file(renderOut() / "final.exr", cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(cut) - 1);
  const CliRun run = runCli("compare " + cut.string() + " " + (renderOut() / "final.exr").string());
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("final.exr"), std::string::npos) << run.output;
  EXPECT_EQ(lineCount(run.output), 1u) << run.output;
}

TEST(Cli, compareOfADeviceReturnsAtOnceWithOneLine) {
  // /dev/zero never ends: read whole, it hung.
  const CliRun run = runCli("compare /dev/zero /dev/zero");
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("is not a regular file"), std::string::npos) << run.output;
}

TEST(Cli, anUnusableOutDirectoryIsRefusedBeforeAnyRendering) {
  const fs::path file = freshDirectory("out-is-a-file");
  { std::ofstream(file) << "x"; }
  const CliRun onAFile = runCli("render --scene cornell --size 8x8 --frames 1 --out " + file.string());
  EXPECT_EQ(onAFile.exitCode, 1) << onAFile.output;
  EXPECT_NE(onAFile.output.find("--out " + file.string() + ": is a file"), std::string::npos) << onAFile.output;
  EXPECT_EQ(onAFile.output.find("rendering"), std::string::npos) << "it rendered first: " << onAFile.output;
  fs::remove(file);
  const CliRun underNull = runCli("render --scene cornell --size 8x8 --frames 1 --out /dev/null/out");
  EXPECT_EQ(underNull.exitCode, 1) << underNull.output;
  EXPECT_NE(underNull.output.find("--out /dev/null/out"), std::string::npos) << underNull.output;
}

TEST(Cli, renderWritesAllItsFilesOrNoneOfThem) {
  // final.png is a directory: the render cannot place it, so it places nothing — the stats.json of an earlier render
  // stays as it was, and no staged file is left behind.
  const fs::path out = freshDirectory("all-or-none");
  fs::create_directories(out / "final.png");
  { std::ofstream(out / "stats.json") << "earlier"; }
  const CliRun run = runCli("render --scene cornell --size 8x8 --frames 1 --gi off --out " + out.string());
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("final.png"), std::string::npos) << run.output;
  std::ifstream stats(out / "stats.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(stats), {}), "earlier");
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << entry.path();
}

TEST(Cli, aGltfBufferOutsideTheFilesFolderIsRefused) {
  // A viewer of untrusted files must not read /etc/passwd as vertex data because a glTF said so.
  const fs::path directory = freshDirectory("escaping-uri");
  fs::create_directories(directory);
  std::ifstream original(SSVGI_SHARED_DIR "/scenes/cornell-box/CornellBox-Original.gltf");
  std::string text((std::istreambuf_iterator<char>(original)), {});
  const std::string uri = "CornellBox-Original.bin";
  ASSERT_NE(text.find(uri), std::string::npos);
  text.replace(text.find(uri), uri.size(), "../../../../../../etc/passwd");
  { std::ofstream(directory / "escape.gltf") << text; }
  const CliRun run = runCli("render --scene " + (directory / "escape.gltf").string() + " --size 8x8 --frames 1 --out " +
                            (directory / "out").string());
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("leads outside the file's folder"), std::string::npos) << run.output;
  EXPECT_EQ(lineCount(run.output), 1u) << run.output;
}

TEST(Cli, referenceRefusesZeroSamplesPerPixel) {
  // Not in the CliRejects table: a value outside an option's range is refused by CLI11 while parsing, and
  // CLI::App::exit (apps/ssvgi/main.cpp) adds a second line, "Run with --help for more information.". The first line
  // must name the option and the range.
  const fs::path out = freshDirectory("spp0");
  const CliRun run = runCli("reference --scene cornell --size 8x8 --spp 0 --out " + out.string());
  EXPECT_NE(run.exitCode, 0) << run.output;
  const std::string firstLine = run.output.substr(0, run.output.find('\n'));
  EXPECT_NE(firstLine.find("--spp"), std::string::npos) << run.output;
  EXPECT_NE(firstLine.find("not in range 1 to"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out)) << "nothing is written";
}

struct BadInvocation {
  const char* name;
  const char* arguments;  // FIXTURES stands for CliRejects::fixtures(); render and reference get an --out too
  const char* expectedInMessage;
};

// ctest lists parameterised tests with their printed parameter; print the arguments rather than raw bytes.
void PrintTo(const BadInvocation& invocation, std::ostream* stream) { *stream << '"' << invocation.arguments << '"'; }

class CliRejects : public ::testing::TestWithParam<BadInvocation> {
 public:
  // Small EXRs for compare's bad inputs, written once: 8x8 and 16x8 RGB images, an 8x8 black one, 8x8 and 16x8 depth
  // images (one channel, all surface). In a directory of this process, like CliReference's.
  static fs::path fixtures() { return processDirectory("fixtures"); }

  static void SetUpTestSuite() {
    fs::remove_all(fixtures());
    fs::create_directories(fixtures());
    const auto write = [](const char* name, uint32_t width, uint32_t height, uint32_t channels, float value) {
      renderer::FloatImage image{.width = width, .height = height, .channels = channels};
      image.pixels.assign(size_t{width} * height * channels, value);
      renderer::writeExr(fixtures() / name, image);
    };
    write("rgb8x8.exr", 8, 8, 3, 1.0f);
    write("rgb16x8.exr", 16, 8, 3, 1.0f);
    write("black8x8.exr", 8, 8, 3, 0.0f);
    write("depth8x8.exr", 8, 8, 1, 2.0f);
    write("depth16x8.exr", 16, 8, 1, 2.0f);
  }
};

std::string withFixtures(std::string arguments) {
  const std::string token = "FIXTURES";
  for (size_t at = arguments.find(token); at != std::string::npos; at = arguments.find(token, at))
    arguments.replace(at, token.size(), CliRejects::fixtures().string());
  return arguments;
}

TEST_P(CliRejects, withOneClearLineAndANonZeroExitCode) {
  std::string arguments = withFixtures(GetParam().arguments);
  if (!arguments.starts_with("compare ")) arguments += " --out " + freshDirectory("bad").string();
  const CliRun run = runCli(arguments);
  EXPECT_NE(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find(GetParam().expectedInMessage), std::string::npos) << run.output;
  EXPECT_EQ(lineCount(run.output), 1u) << run.output;
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, CliRejects,
    ::testing::Values(BadInvocation{"missingGltf", "render --scene /nonexistent/missing.gltf", "missing.gltf"},
                      BadInvocation{"benchPixelRaysNotAnEvenSquare",
                                    "bench --scene cornell --size 16x16 --frames 1 --rays 10 --pixel-rays 9",
                                    "--pixel-rays 9: rays per pixel must be even squares"},
                      BadInvocation{"unknownScene", "render --scene no-such-scene", "not a built-in scene"},
                      BadInvocation{"malformedSize", "render --scene cornell --size 64by48", "--size 64by48"},
                      BadInvocation{"shortCamera", "render --scene cornell --camera 1,2,3", "--camera"},
                      BadInvocation{"shortDebugCamera", "render --scene cornell --debug voxels --debug-camera 1,2,3",
                                    "--debug-camera"},
                      BadInvocation{"unknownSky", "render --scene cornell --sky purple", "--sky purple"},
                      BadInvocation{"shortSun", "render --scene cornell --sun 10,20", "--sun"},
                      BadInvocation{"nanSun", "render --scene cornell --sun 0,45,nan", "'nan' is not finite"},
                      BadInvocation{"nanSky", "render --scene cornell --sky uniform:nan,1,1", "'nan' is not finite"},
                      BadInvocation{"negativeSky", "render --scene cornell --sky uniform:1,-1,1",
                                    "the radiance must not be negative"},
                      BadInvocation{"infiniteCamera", "render --scene cornell --camera inf,1,3,0,1,0,40",
                                    "'inf' is not finite"},
                      BadInvocation{"tinyFieldOfView", "render --scene cornell --camera 0,1,3,0,1,0,1e-30",
                                    "the field of view must be in [0.01, 179] degrees"},
                      BadInvocation{"nanExposure", "render --scene cornell --exposure nan", "--exposure"},
                      BadInvocation{"negativeExposure", "render --scene cornell --exposure -1",
                                    "--exposure: -1 is not at least 0"},
                      BadInvocation{"nanReferenceTime", "reference --scene cornell --spp 1 --time nan", "--time"},
                      BadInvocation{"missingDevice", "render --scene cornell --device 42", "--device 42"},
                      BadInvocation{"unknownDevice", "render --scene cornell --device fastest",
                                    "--device fastest: must be auto, cpu, gpu or a device index"},
                      BadInvocation{"unknownGiSetting", "render --scene cornell --gi-set voxelSise=0.5",
                                    "--gi-set voxelSise=0.5"},
                      BadInvocation{"giSettingTwoAxes", "render --scene cornell --gi-set probeGrid=16,16",
                                    "--gi-set probeGrid 16,16: expected X,Y,Z"},
                      BadInvocation{"giSettingRefusedByTheLibrary",
                                    "render --scene cornell --size 8x8 --frames 1 --gi-set probeGrid=16,10,16",
                                    "Settings::probeGrid must be a multiple of 4"},
                      BadInvocation{"negativeMemoryBudget", "render --scene cornell --memory-budget -5",
                                    "--memory-budget: -5 is not at least 0"},
                      BadInvocation{"voxelSizeBelowAMillimetre",
                                    "render --scene cornell --size 8x8 --frames 1 --gi-set voxelSize=1e-6",
                                    "Settings::voxelSize must be at least 0.001"},
                      BadInvocation{"voxelVolumeWiderThanTheWorld",
                                    "render --scene cornell --size 8x8 --frames 1 --gi-set voxelSize=1e30",
                                    "Settings::voxelSize"},
                      BadInvocation{"memoryBudgetBelowTheMinimum",
                                    "render --scene cornell --size 8x8 --frames 1 --memory-budget 0.01",
                                    "ContextDesc::memoryBudgetBytes: 10486 bytes (0.01 MiB) is below the minimum of"},
                      BadInvocation{"referenceMissingGltf", "reference --scene /nonexistent/missing.gltf --spp 1",
                                    "missing.gltf"},
                      BadInvocation{"referenceUnknownScene", "reference --scene no-such-scene --spp 1",
                                    "not a built-in scene"},
                      BadInvocation{"compareMissingTest", "compare /nonexistent/missing.exr FIXTURES/rgb8x8.exr",
                                    "missing.exr"},
                      BadInvocation{"compareMissingReference", "compare FIXTURES/rgb8x8.exr /nonexistent/missing.exr",
                                    "missing.exr"},
                      BadInvocation{"compareMissingMask",
                                    "compare FIXTURES/rgb8x8.exr FIXTURES/rgb8x8.exr --mask-from /nonexistent/depth.exr",
                                    "depth.exr"},
                      BadInvocation{"compareMismatchedSizes", "compare FIXTURES/rgb16x8.exr FIXTURES/rgb8x8.exr",
                                    "the images must have the same size"},
                      BadInvocation{"compareMismatchedMask",
                                    "compare FIXTURES/rgb8x8.exr FIXTURES/rgb8x8.exr --mask-from FIXTURES/depth16x8.exr",
                                    "depth16x8.exr is 16x8"},
                      BadInvocation{"compareMismatchedChannels", "compare FIXTURES/rgb8x8.exr FIXTURES/depth8x8.exr",
                                    "the images must have the same channels"},
                      BadInvocation{"compareBlackReference", "compare FIXTURES/rgb8x8.exr FIXTURES/black8x8.exr",
                                    "is black over the valid pixels"},
                      BadInvocation{"compareDownsampleTooLarge",
                                    "compare FIXTURES/rgb8x8.exr FIXTURES/rgb8x8.exr --downsample 9",
                                    "the block size must be 1 to the shorter side"}),
    [](const ::testing::TestParamInfo<BadInvocation>& invocation) { return std::string(invocation.param.name); });

TEST(Cli, infoListsTheDeviceAndTheFeaturesSsvgiNeeds) {
  const CliRun run = runCli("info");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("usable"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("present  dynamicRendering"), std::string::npos) << run.output;
}

TEST(Cli, withoutAVulkanDriverRenderFailsWithAClearMessage) {
  const CliRun run = runCli("render --scene cornell --size 8x8 --out " + freshDirectory("nodriver").string(),
                         "VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json");
  EXPECT_NE(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("no Vulkan"), std::string::npos) << run.output;
}

// The viewer opens a window on a virtual X server: xvfb-run (package xvfb, scripts/install-deps.sh), found when the build
// was configured. Without it the viewer's tests fail, saying so, rather than pass without having run. The screen's
// depth of 24 bits is what a Vulkan swapchain on X needs (xvfb-run's default is 8 on some versions).
CliRun runViewer(const std::string& arguments) {
  const std::string xvfbRun = SSVGI_XVFB_RUN;
  if (xvfbRun.empty())
    return {-1, "xvfb-run was not found when the build was configured: install xvfb (scripts/install-deps.sh), then "
                "configure again"};
  return runCli(arguments, xvfbRun + " -a -s '-screen 0 640x480x24'");
}

struct Rgba8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // RGBA
};

Rgba8Image readPng(const fs::path& path) {
  Rgba8Image image;
  int channels = 0;
  const std::unique_ptr<stbi_uc, void (*)(void*)> decoded(
      stbi_load(path.c_str(), &image.width, &image.height, &channels, 4), stbi_image_free);
  if (decoded) image.pixels.assign(decoded.get(), decoded.get() + size_t(image.width) * image.height * 4);
  return image;
}

// The mean absolute difference of the RGB values (0–255) of two images of one size, over the pixels with x in
// [fromX, toX).
double meanAbsoluteDifference(const Rgba8Image& a, const Rgba8Image& b, int fromX, int toX) {
  double sum = 0.0;
  size_t count = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = fromX; x < toX; ++x)
      for (int c = 0; c < 3; ++c, ++count) {
        const size_t at = (size_t(y) * a.width + x) * 4 + c;
        sum += std::abs(int(a.pixels[at]) - int(b.pixels[at]));
      }
  return count ? sum / double(count) : 0.0;
}

TEST(Cli, viewScriptedRunSavesTheRenderersImageWithThePanelOverIt) {
  const fs::path out = freshDirectory("view");
  const std::string scene = "--scene cornell --size 240x120 --frames 3 --validation";
  const CliRun render = runCli("render " + scene + " --out " + out.string());
  ASSERT_EQ(render.exitCode, 0) << render.output;
  const fs::path screenshot = out / "view.png";
  const CliRun view = runViewer("view " + scene + " --screenshot " + screenshot.string());
  ASSERT_EQ(view.exitCode, 0) << view.output;

  // Where the viewer drew its panel, as it reports it: "the panel at X,Y WxH".
  std::smatch panel;
  ASSERT_TRUE(std::regex_search(view.output, panel, std::regex(R"(the panel at (\d+),(\d+) (\d+)x(\d+))")))
      << view.output;
  const int panelX = std::stoi(panel[1]), panelY = std::stoi(panel[2]);
  const int panelWidth = std::stoi(panel[3]), panelHeight = std::stoi(panel[4]);
  ASSERT_EQ(panelX, 0);  // docked on the left, full height: the rest of the window is the 3-D view
  ASSERT_EQ(panelY, 0);
  ASSERT_EQ(panelHeight, 120);
  ASSERT_LT(panelWidth, 240);

  const Rgba8Image window = readPng(screenshot), rendered = readPng(out / "final.png");
  ASSERT_EQ(window.width, 240);
  ASSERT_EQ(window.height, 120);
  ASSERT_EQ(rendered.width, 240);
  // Outside the panel the window shows the renderer's tonemapped image, copied: the same renderer, settings, view and
  // frames as render's final.png, through the same tonemap. The two processes' images can differ only where the GPU's
  // work is not deterministic — the order in which lavapipe's threads win ssvgi's atomics (which pool slot a brick
  // takes), which could move an 8-bit value by a count here and there; they were identical when this was written. A
  // mean of 1 count allows for that and no more: one frame more, or the GI off, moves this part of the view by several
  // counts (docs/QUALITY.md, "What the tests establish").
  EXPECT_LE(meanAbsoluteDifference(window, rendered, panelWidth, 240), 1.0);
  // Inside it the panel was drawn over the image.
  EXPECT_GT(meanAbsoluteDifference(window, rendered, 0, panelWidth), 10.0);
}

TEST(Cli, viewWithoutADisplayFailsWithOneLineSuggestingRender) {
  const CliRun run = runCli("view --scene cornell --size 64x48 --frames 1", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_NE(run.exitCode, 0) << run.output;
  EXPECT_EQ(lineCount(run.output), 1u) << run.output;
  EXPECT_NE(run.output.find("no display"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("ssvgi render"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace ssvgi
