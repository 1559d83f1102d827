#pragma once
// What the commands that render a scene (render, reference) write, in the same form, so that any two of their output
// directories can be compared file by file: the images, stats.json and a progress bar while they work.
#include "scene_options.h"

#include "gpu/device.h"
#include "image_io.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
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
};

// Writes the images and stats.json into `out` (created if needed). Throws std::runtime_error naming the directory
// when it cannot be created; image files throw renderer::ImageIoError.
void writeRenderedImages(const std::filesystem::path& out, const RenderedImages& images, const nlohmann::json& stats);

// A debug image as `out`/`name`.png (tonemapped) and `out`/`name`.exr (linear); `out` must exist.
void writeDebugImage(const std::filesystem::path& out, const std::string& name, const renderer::FloatImage& radiance,
                     const std::vector<uint8_t>& tonemapped);

// The names of what writeRenderedImages writes, for the commands' closing line.
inline constexpr const char* kRenderedFileList =
    "final.png, final.exr, irradiance_direct.exr, irradiance_indirect.exr, albedo.exr, normal.exr, depth.exr, "
    "stats.json";

// The stats every such command reports: device, scene, image size, scene size, memory per named GPU resource.
nlohmann::json sceneStats(const gpu::Device& device, const SceneOptions& options, const ResolvedScene& resolved);

// A progress bar on stderr, redrawn in place; nothing when stderr is not a terminal.
void drawProgress(const std::string& label, uint32_t done, uint32_t total);

}  // namespace ssvgi::cli
