#pragma once
// The scene, view, light, sky and device options shared by the commands that render a scene (render, and the
// reference path tracer to come), so that both see exactly the same scene for the same arguments.
#include "gpu_host/owned_device.h"
#include "renderer.h"
#include "scene.h"
#include "ssvgi/ssvgi.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ssvgi::cli {

struct SceneOptions {
  std::string scene = "courtyard";
  std::string size = "1280x720";
  std::string camera;  // PX,PY,PZ,TX,TY,TZ,VFOV_DEG
  std::string sun;     // off | AZ_DEG,EL_DEG,ILLUMINANCE
  std::string sky;     // none | default | uniform:R,G,B
  std::string device = "auto";
  bool movingObject = false;
  bool sunCycle = false;
  bool cameraPath = false;
  bool validation = false;
};

void addSceneOptions(CLI::App& command, SceneOptions& options);

// The device `desc` selects (--device), as OwnedDevice creates it; a selector that picks none is reported as
// --device's problem.
gpu::OwnedDevice openDevice(const gpu::DeviceDesc& desc);

// Whether --validation was given and the layers reported errors, saying how many on stderr: the commands then exit
// with 1 (their outputs are written, for a look at what went wrong).
bool reportValidationErrors(const SceneOptions& options, const gpu::OwnedDevice& device);

// CLI11 checks for numbers that refuse NaN and infinities (CLI::Range lets NaN through: every comparison with it is
// false) and say their bound in a few characters (CLI::NonNegativeNumber prints the largest double, 309 digits).
inline CLI::Validator finiteNumber(double lowest, bool lowestAllowed, const std::string& name) {
  return CLI::Validator(
      [=](const std::string& text) {
        double value = 0.0;
        try {
          value = std::stod(text);
        } catch (const std::exception&) {
          return "not a number: " + text;
        }
        if (!std::isfinite(value)) return "not a finite number: " + text;
        if (value < lowest || (!lowestAllowed && value == lowest)) {
          char bound[32];
          std::snprintf(bound, sizeof(bound), "%g", lowest);
          return text + " is not " + (lowestAllowed ? "at least " : "above ") + bound;
        }
        return std::string();
      },
      name);
}
inline const CLI::Validator kFiniteNumber = finiteNumber(-std::numeric_limits<double>::max(), true, "FINITE");
inline const CLI::Validator kNonNegativeNumber = finiteNumber(0.0, true, "NONNEGATIVE");
inline const CLI::Validator kPositiveNumber = finiteNumber(0.0, false, "POSITIVE");

// The scene with every option applied, the view to render it from and the image size. Throws std::runtime_error with
// one line naming the bad option or file.
struct ResolvedScene {
  renderer::Scene scene;
  renderer::Camera camera;
  uint32_t width = 0;
  uint32_t height = 0;
};
ResolvedScene resolveScene(const SceneOptions& options);

// Points the scene's sun at an azimuth (from +Z towards +X) and elevation in degrees; with a time-of-day cycle, that is
// where the cycle starts (--sun, the viewer's sun controls).
void pointSun(renderer::Scene& scene, float azimuthDegrees, float elevationDegrees);

// `camera` placed by a view given as PX,PY,PZ,TX,TY,TZ,VFOV_DEG (the --camera syntax); throws std::runtime_error with
// one line naming `option` when the text is not such a view.
renderer::Camera parseCamera(const std::string& text, const std::string& option, renderer::Camera camera);

// The quality tier of a --tier value (low, medium, high; the option's check has already refused anything else).
ssvgi::QualityTier qualityTier(const std::string& tier);

// The GI options of the commands that run ssvgi: a quality tier (SPEC §4.7) and overrides of single settings.
struct GiOptions {
  std::string tier = "high";
  std::vector<std::string> overrides;  // NAME=VALUE, a field of ssvgi::Settings; X,Y,Z for the three-axis ones
  renderer::ExtraViewSettings extraViews;  // the views beyond the camera the renderer gives ssvgi (SPEC §6.3)
  std::string litFrame = "direct";  // what the renderer gives ssvgi as its lit frame (RendererSettings::litFrameDirectOnly)
  double memoryBudgetMebibytes = 0.0;  // ssvgi::ContextDesc::memoryBudgetBytes in MB of 2^20 bytes; 0: none
};

void addGiOptions(CLI::App& command, GiOptions& options);

// The tier's settings with the scene's detail scale (renderer::Scene::giDetailScale) applied to the voxel size and
// the probe spacing, then the overrides. Throws std::runtime_error with one line naming a bad override.
ssvgi::Settings giSettings(const GiOptions& options, const renderer::Scene& scene);

// ssvgi::ContextDesc::memoryBudgetBytes of the --memory-budget option (0: none).
uint64_t memoryBudgetBytes(const GiOptions& options);

// The settings as JSON, for the stats a command writes.
nlohmann::json giSettingsJson(const ssvgi::Settings& settings);

}  // namespace ssvgi::cli
