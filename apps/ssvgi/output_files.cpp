#include "output_files.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace ssvgi::cli {

void writeRenderedImages(const std::filesystem::path& out, const RenderedImages& images, const nlohmann::json& stats) {
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) throw std::runtime_error("--out " + out.string() + ": cannot create the directory (" + error.message() + ")");
  renderer::writePng(out / "final.png", images.finalRadiance.width, images.finalRadiance.height, images.tonemapped);
  renderer::writeExr(out / "final.exr", images.finalRadiance);
  renderer::writeExr(out / "irradiance_direct.exr", images.directIrradiance);
  renderer::writeExr(out / "irradiance_indirect.exr", images.indirectIrradiance);
  renderer::writeExr(out / "albedo.exr", images.albedo);
  renderer::writeExr(out / "normal.exr", images.normal);
  renderer::writeExr(out / "depth.exr", images.viewDistance);
  std::ofstream(out / "stats.json") << stats.dump(2) << "\n";
}

void writeDebugImage(const std::filesystem::path& out, const std::string& name, const renderer::FloatImage& radiance,
                     const std::vector<uint8_t>& tonemapped) {
  renderer::writePng(out / (name + ".png"), radiance.width, radiance.height, tonemapped);
  renderer::writeExr(out / (name + ".exr"), radiance);
}

nlohmann::json sceneStats(const gpu::Device& device, const SceneOptions& options, const ResolvedScene& resolved) {
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

void drawProgress(const std::string& label, uint32_t done, uint32_t total) {
  if (!isatty(STDERR_FILENO)) return;
  constexpr int kWidth = 30;
  const int filled = int(kWidth * double(done) / double(total));
  std::fprintf(stderr, "\r%s [%s%s] %u/%u", label.c_str(), std::string(size_t(filled), '#').c_str(),
               std::string(size_t(kWidth - filled), ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace ssvgi::cli
