// The ssvgi CLI end to end: it runs the real executable (path from CMake) at a small size, with validation on.
#include "image_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

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

fs::path freshDirectory(const std::string& name) {
  const fs::path directory = fs::temp_directory_path() / ("ssvgi-cli-test-" + name);
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
  const CliRun run = runCli("render --scene cornell --size 64x48 --frames 2 --validation --out " + out.string());
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

struct BadInvocation {
  const char* name;
  const char* arguments;
  const char* expectedInMessage;
};

// ctest lists parameterised tests with their printed parameter; print the arguments rather than raw bytes.
void PrintTo(const BadInvocation& invocation, std::ostream* stream) { *stream << '"' << invocation.arguments << '"'; }

class CliRejects : public ::testing::TestWithParam<BadInvocation> {};

TEST_P(CliRejects, withOneClearLineAndANonZeroExitCode) {
  const CliRun run = runCli(std::string(GetParam().arguments) + " --out " + freshDirectory("bad").string());
  EXPECT_NE(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find(GetParam().expectedInMessage), std::string::npos) << run.output;
  EXPECT_EQ(lineCount(run.output), 1u) << run.output;
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, CliRejects,
    ::testing::Values(BadInvocation{"missingGltf", "render --scene /nonexistent/missing.gltf", "missing.gltf"},
                      BadInvocation{"unknownScene", "render --scene no-such-scene", "not a built-in scene"},
                      BadInvocation{"malformedSize", "render --scene cornell --size 64by48", "--size 64by48"},
                      BadInvocation{"shortCamera", "render --scene cornell --camera 1,2,3", "--camera"},
                      BadInvocation{"unknownSky", "render --scene cornell --sky purple", "--sky purple"},
                      BadInvocation{"shortSun", "render --scene cornell --sun 10,20", "--sun"},
                      BadInvocation{"missingDevice", "render --scene cornell --device 42", "--device 42"}),
    [](const ::testing::TestParamInfo<BadInvocation>& info) { return std::string(info.param.name); });

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

}  // namespace
}  // namespace ssvgi
