#pragma once
// The scene, view, light, sky and device options shared by the commands that render a scene (render, and the
// reference path tracer to come), so that both see exactly the same scene for the same arguments.
#include "scene.h"
#include "ssvgi/ssvgi.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

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

// The scene with every option applied, the view to render it from and the image size. Throws std::runtime_error with
// one line naming the bad option or file.
struct ResolvedScene {
  renderer::Scene scene;
  renderer::Camera camera;
  uint32_t width = 0;
  uint32_t height = 0;
};
ResolvedScene resolveScene(const SceneOptions& options);

// The GI settings of a --tier value (low, medium, high; the option's check has already refused anything else).
ssvgi::Settings giSettingsForTier(const std::string& tier);

}  // namespace ssvgi::cli
