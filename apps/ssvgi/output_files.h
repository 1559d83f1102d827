#pragma once
// What the commands that render a scene (render, reference) write, in the same form, so that any two of their output
// directories can be compared file by file: the images, stats.json and a progress bar while they work.
#include "scene_options.h"

#include "gpu_host/owned_device.h"
#include "image_io.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ssvgi::cli {

struct RenderedImages {
  renderer::FloatImage finalRadiance;       // final.exr: linear HDR radiance
  renderer::FloatImage directIrradiance;    // irradiance_direct.exr
  renderer::FloatImage indirectIrradiance;  // irradiance_indirect.exr
  renderer::FloatImage albedo;              // albedo.exr
  renderer::FloatImage normal;              // normal.exr
  renderer::FloatImage viewDistance;        // depth.exr: metres from the camera, 0 where there is no surface
  std::vector<uint8_t> tonemapped;          // final.png: RGBA8, sRGB
  // confidence.exr (render only): the GI's confidence in the E_indirect composited, one channel 0–1 (SPEC §6.4)
  std::optional<renderer::FloatImage> confidence;
  std::map<std::string, renderer::Renderer::DebugImage> debugImages;  // NAME.png (tonemapped) and NAME.exr (linear)
};

// Creates `out` if needed and checks that files can be written into it: called before any rendering work, so that a
// bad --out costs no render. Throws std::runtime_error with one line naming --out.
void prepareOutputDirectory(const std::filesystem::path& out);

// Writes the images and stats.json into `out` (prepared by prepareOutputDirectory) all or none, as
// renderer::StagedFiles does: an error half-way, or a killed process, leaves the files already there as they were.
// Throws renderer::ImageIoError naming the file that could not be written.
void writeRenderedImages(const std::filesystem::path& out, const RenderedImages& images, const nlohmann::json& stats);

// The names of what writeRenderedImages always writes, for the commands' closing line.
inline constexpr const char* kRenderedFileList =
    "final.png, final.exr, irradiance_direct.exr, irradiance_indirect.exr, albedo.exr, normal.exr, depth.exr, "
    "stats.json";

// The stats every such command reports: device, scene, image size, scene size, memory per named GPU resource.
nlohmann::json sceneStats(const gpu::OwnedDevice& device, const SceneOptions& options, const ResolvedScene& resolved);

// A JSON report (bench, scenario): printed on stdout where `out` is empty, else written to the file `out` with a line
// saying so. Throws std::runtime_error naming --out when the file cannot be written.
void writeJsonReport(const nlohmann::json& report, const std::string& out, const gpu::OwnedDevice& device);

// A progress bar on stderr, redrawn in place; nothing when stderr is not a terminal.
void drawProgress(const std::string& label, uint32_t done, uint32_t total);

}  // namespace ssvgi::cli
