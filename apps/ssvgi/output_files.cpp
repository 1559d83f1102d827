#include "output_files.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace ssvgi::cli {

void prepareOutputDirectory(const std::filesystem::path& out) {
  std::error_code error;
  if (std::filesystem::exists(out, error) && !std::filesystem::is_directory(out, error))
    throw std::runtime_error("--out " + out.string() + ": is a file, not a directory");
  std::filesystem::create_directories(out, error);
  if (error) throw std::runtime_error("--out " + out.string() + ": cannot create the directory (" + error.message() + ")");
  try {
    renderer::StagedFiles probe;  // never committed: its file is removed
    probe.writeText(out / ".ssvgi-write-test", "");
  } catch (const renderer::ImageIoError& writeError) {
    throw std::runtime_error("--out " + out.string() + ": cannot write into the directory (" + writeError.what() + ")");
  }
}

void writeRenderedImages(const std::filesystem::path& out, const RenderedImages& images, const nlohmann::json& stats) {
  renderer::StagedFiles files;
  files.writePng(out / "final.png", images.finalRadiance.width, images.finalRadiance.height, images.tonemapped);
  files.writeExr(out / "final.exr", images.finalRadiance);
  files.writeExr(out / "irradiance_direct.exr", images.directIrradiance);
  files.writeExr(out / "irradiance_indirect.exr", images.indirectIrradiance);
  files.writeExr(out / "albedo.exr", images.albedo);
  files.writeExr(out / "normal.exr", images.normal);
  files.writeExr(out / "depth.exr", images.viewDistance);
  if (images.confidence) files.writeExr(out / "confidence.exr", *images.confidence);
  for (const auto& [name, debug] : images.debugImages) {
    files.writePng(out / (name + ".png"), debug.radiance.width, debug.radiance.height, debug.tonemapped);
    files.writeExr(out / (name + ".exr"), debug.radiance);
  }
  files.writeText(out / "stats.json", stats.dump(2) + "\n");
  files.commit();
}

nlohmann::json sceneStats(const gpu::OwnedDevice& device, const SceneOptions& options, const ResolvedScene& resolved) {
  nlohmann::json stats;
  stats["device"] = device.description();
  stats["scene"] = options.scene;
  stats["width"] = resolved.width;
  stats["height"] = resolved.height;
  size_t triangles = 0;
  for (const auto& instance : resolved.scene.instances)
    triangles += resolved.scene.meshes[instance.mesh].indices.size() / 3;
  stats["sceneTriangles"] = triangles;
  stats["localLights"] = resolved.scene.lights.size();
  nlohmann::json memory = nlohmann::json::object();
  VkDeviceSize total = 0;
  for (const auto& [name, bytes] : device.allocations()) {
    memory[name] = bytes;
    total += bytes;
  }
  stats["memoryBytes"] = {{"resources", memory}, {"total", total}};
  return stats;
}

void writeJsonReport(const nlohmann::json& report, const std::string& out, const gpu::OwnedDevice& device) {
  const std::string json = report.dump(2);
  if (out.empty()) {
    std::printf("%s\n", json.c_str());
    return;
  }
  std::ofstream file(out);
  if (!(file << json << "\n")) throw std::runtime_error("--out " + out + ": cannot write the file");
  std::printf("wrote %s on %s\n", out.c_str(), device.description().c_str());
}

void drawProgress(const std::string& label, uint32_t done, uint32_t total) {
  if (!isatty(STDERR_FILENO)) return;
  constexpr int kWidth = 30;
  const int filled = int(kWidth * double(done) / double(total));
  std::fprintf(stderr, "\r%s [%s%s] %u/%u", label.c_str(), std::string(size_t(filled), '#').c_str(),
               std::string(size_t(kWidth - filled), ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace ssvgi::cli
