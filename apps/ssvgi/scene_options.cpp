#include "scene_options.h"

#include "builtin_scenes.h"
#include "gltf_loader.h"
#include "renderer.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <span>
#include <variant>
#include <vector>

namespace ssvgi::cli {

namespace {

std::vector<float> parseNumbers(const std::string& text, size_t count, const std::string& option) {
  std::vector<float> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::runtime_error(option + " " + text + ": '" + item + "' is not a number");
    }
    if (!std::isfinite(values.back())) throw std::runtime_error(option + " " + text + ": '" + item + "' is not finite");
  }
  if (values.size() != count)
    throw std::runtime_error(option + " " + text + ": expected " + std::to_string(count) + " comma-separated numbers");
  return values;
}

// "cornell, two-rooms, …": the built-in scenes' names, for help texts and errors.
std::string builtinSceneList() {
  std::string names;
  for (const std::string& name : renderer::builtinSceneNames()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

renderer::Scene loadScene(const SceneOptions& options) {
  renderer::BuiltinSceneOptions builtin;
  builtin.movingObject = options.movingObject;
  builtin.sunCycle = options.sunCycle;
  if (auto scene = renderer::makeBuiltinScene(options.scene, builtin)) return *scene;
  const std::filesystem::path path(options.scene);
  const std::string extension = path.extension().string();
  if (extension != ".gltf" && extension != ".glb") {
    throw std::runtime_error("--scene " + options.scene + ": not a built-in scene (" + builtinSceneList() +
                             ") nor a .gltf/.glb file");
  }
  return renderer::loadGltf(path);
}

}  // namespace

void addSceneOptions(CLI::App& command, SceneOptions& options) {
  command.add_option("--scene", options.scene,
                     "Built-in scene (" + builtinSceneList() + ") or a glTF 2.0 file (.gltf/.glb)")
      ->capture_default_str();
  command.add_option("--size", options.size, "Image size WxH in pixels")->capture_default_str();
  command.add_option("--camera", options.camera,
                     "View PX,PY,PZ,TX,TY,TZ,VFOV_DEG: position, target (metres) and vertical field of view "
                     "(default: the scene's first camera)");
  command.add_option("--sun", options.sun,
                     "off, or AZ_DEG,EL_DEG,ILLUMINANCE: azimuth from +Z towards +X, elevation, irradiance in W/m² "
                     "(default: the scene's sun)");
  command.add_option("--sky", options.sky, "none, default (analytic clear sky) or uniform:R,G,B radiance in W/(sr·m²) "
                                           "(default: the scene's sky)");
  command.add_flag("--moving-object", options.movingObject, "Add the scene's moving object");
  command.add_flag("--sun-cycle", options.sunCycle, "Let the sun follow the scene's time-of-day cycle");
  command.add_flag("--camera-path", options.cameraPath, "Move the camera along the scene's camera path");
  command.add_option("--device", options.device, "Vulkan device: auto, gpu, cpu (lavapipe) or an index from 'ssvgi info'")
      ->capture_default_str();
  command.add_flag("--validation", options.validation, "Enable the Vulkan validation layers");
}

gpu::OwnedDevice openDevice(const gpu::DeviceDesc& desc) {
  try {
    return gpu::OwnedDevice(desc);
  } catch (const gpu::DeviceSelectionError& error) {
    throw std::runtime_error("--device " + desc.selector + ": " + error.reason() + " (see ssvgi info)");
  }
}

bool reportValidationErrors(const SceneOptions& options, const gpu::OwnedDevice& device) {
  if (!options.validation || device.validationErrorCount() == 0) return false;
  std::fprintf(stderr, "ssvgi: %u Vulkan validation errors\n", device.validationErrorCount());
  return true;
}

renderer::Camera parseCamera(const std::string& text, const std::string& option, renderer::Camera camera) {
  const auto v = parseNumbers(text, 7, option);
  camera.position = {v[0], v[1], v[2]};
  camera.target = {v[3], v[4], v[5]};
  // Below a hundredth of a degree the projection is no longer invertible in float.
  if (v[6] < 0.01f || v[6] > 179.0f)
    throw std::runtime_error(option + ": the field of view must be in [0.01, 179] degrees");
  camera.verticalFov = glm::radians(v[6]);
  if (glm::length(camera.target - camera.position) <= 0.0f)
    throw std::runtime_error(option + ": position and target must differ");
  return camera;
}

void pointSun(renderer::Scene& scene, float azimuthDegrees, float elevationDegrees) {
  scene.sun.direction = renderer::sunDirection(azimuthDegrees, elevationDegrees);
  if (scene.sunCycle) {
    scene.sunCycle->azimuthDegrees = azimuthDegrees;
    scene.sunCycle->elevationDegrees = elevationDegrees;
  }
}

ResolvedScene resolveScene(const SceneOptions& options) {
  ResolvedScene resolved;
  resolved.scene = loadScene(options);
  renderer::Scene& scene = resolved.scene;

  unsigned width = 0, height = 0;
  char separator = 0;
  std::istringstream sizeStream(options.size);
  if (!(sizeStream >> width >> separator >> height) || separator != 'x' || width == 0 || height == 0 ||
      width > 16384 || height > 16384 || sizeStream.peek() != EOF)
    throw std::runtime_error("--size " + options.size + ": expected WxH, e.g. 640x360");
  resolved.width = width;
  resolved.height = height;

  resolved.camera = scene.cameras.empty() ? renderer::Camera{} : scene.cameras.front();
  if (!options.camera.empty()) {
    resolved.camera = parseCamera(options.camera, "--camera", resolved.camera);
    scene.giDetailScale = renderer::giDetailScaleFor(renderer::worldBounds(scene), resolved.camera.position);
  }
  if (!options.cameraPath || !options.camera.empty()) scene.cameraPath.clear();

  if (options.sun == "off") {
    scene.sun.enabled = false;
    scene.sunCycle.reset();
  } else if (!options.sun.empty()) {
    const auto v = parseNumbers(options.sun, 3, "--sun");
    if (v[2] < 0.0f) throw std::runtime_error("--sun " + options.sun + ": the illuminance must not be negative");
    scene.sun.enabled = true;
    pointSun(scene, v[0], v[1]);
    scene.sun.illuminance = glm::vec3(v[2]);
  }

  if (options.sky == "none") {
    scene.sky.kind = renderer::SkyKind::None;
  } else if (options.sky == "default") {
    scene.sky.kind = renderer::SkyKind::Default;
  } else if (options.sky.rfind("uniform:", 0) == 0) {
    const auto v = parseNumbers(options.sky.substr(8), 3, "--sky uniform:");
    if (v[0] < 0.0f || v[1] < 0.0f || v[2] < 0.0f)
      throw std::runtime_error("--sky " + options.sky + ": the radiance must not be negative");
    scene.sky.kind = renderer::SkyKind::Uniform;
    scene.sky.uniformRadiance = {v[0], v[1], v[2]};
  } else if (!options.sky.empty()) {
    throw std::runtime_error("--sky " + options.sky + ": expected none, default or uniform:R,G,B");
  }
  return resolved;
}

ssvgi::QualityTier qualityTier(const std::string& tier) {
  return tier == "low"      ? ssvgi::QualityTier::Low
         : tier == "medium" ? ssvgi::QualityTier::Medium
                            : ssvgi::QualityTier::High;
}

namespace {

uint32_t parseCount(const std::string& text, const std::string& option) {
  try {
    size_t used = 0;
    const unsigned long value = std::stoul(text, &used);
    if (used == text.size() && text[0] != '-' && value <= 0xffffffffu) return uint32_t(value);
  } catch (const std::exception&) {
  }
  throw std::runtime_error(option + ": '" + text + "' is not a whole number");
}

// Sets `field` of `settings` from its --gi-set text.
void parseSetting(const ssvgi::SettingInfo& field, ssvgi::Settings& settings, const std::string& text) {
  const std::string option = std::string("--gi-set ") + field.name;
  std::visit(
      [&](auto member) {
        using Value = std::remove_reference_t<decltype(settings.*member)>;
        if constexpr (std::is_same_v<Value, float>) {
          settings.*member = parseNumbers(text, 1, option)[0];
        } else if constexpr (std::is_same_v<Value, uint32_t>) {
          settings.*member = parseCount(text, option);
        } else if constexpr (std::is_same_v<Value, bool>) {
          if (text != "true" && text != "false") throw std::runtime_error(option + ": expected true or false");
          settings.*member = text == "true";
        } else {  // three axes, X,Y,Z
          std::vector<std::string> items;
          std::stringstream stream(text);
          for (std::string item; std::getline(stream, item, ',');) items.push_back(item);
          if (items.size() != 3) throw std::runtime_error(option + " " + text + ": expected X,Y,Z");
          for (size_t axis = 0; axis < 3; ++axis) (settings.*member)[axis] = parseCount(items[axis], option);
        }
      },
      field.member);
}

}  // namespace

void addGiOptions(CLI::App& command, GiOptions& options) {
  command.add_option("--tier", options.tier, "GI quality tier (SPEC §4.7)")
      ->capture_default_str()
      ->check(CLI::IsMember({"low", "medium", "high"}));
  std::string names;
  for (const ssvgi::SettingInfo& field : ssvgi::settingInfos())
    names += std::string(names.empty() ? "" : ", ") + field.name;
  command.add_option("--gi-set", options.overrides,
                     "Override one GI setting after the tier and the scene's detail scale, as NAME=VALUE (X,Y,Z for "
                     "volumeBricks and probeGrid); may be repeated. Names: " + names);
  // The views beyond the camera (SPEC §6.3; renderer::ExtraViewSettings).
  const auto addViewSize = [&](const char* name, uint32_t& size, const std::string& what) {
    command.add_option(name, size, "Give ssvgi " + what + ", this many pixels per side; 0: none")
        ->capture_default_str()
        ->check(CLI::Range(0u, 4096u));
  };
  addViewSize("--sun-view", options.extraViews.sunViewSize,
              "the sun's view (an orthographic reflective shadow map over the voxel volume, texels a voxel wide)");
  addViewSize("--surround-views", options.extraViews.surroundViewSize,
              "a capture around the camera (six 90° views from its position)");
  addViewSize("--overhead-view", options.extraViews.overheadViewSize,
              "a view straight down over the whole voxel volume, as depth only: it observes the open space the "
              "probes' rays cross to the sky beyond the sun's view, for skyOnlyThroughObservedSpace)");
  addViewSize("--light-views", options.extraViews.lightViewSize,
              "the views of the scene's local lights (six per point light, one per spot)");
  command.add_flag("--shadow-map-views,!--no-shadow-map-views", options.extraViews.reflectiveShadowMaps,
                   "Give the sun's view as a reflective shadow map where the sun alone lights the scene (and a local "
                   "light's views where that light does): ssvgi takes what it shows hidden for shadow");
  command.add_flag("--sky-map,!--no-sky-map", options.extraViews.skyMap,
                   "Give ssvgi the sky as an equirectangular map too, for the probes' rays that leave its voxels. On "
                   "by default");
  command.add_option("--views-per-frame", options.extraViews.viewsPerFrame,
                     "Extra views rendered per frame; when there are more, they take turns")
      ->capture_default_str()
      ->check(CLI::Range(1u, ssvgi::kMaxExtraViews));
  command.add_option("--lit-frame", options.litFrame,
                     "The lit frame the renderer gives ssvgi: direct (its direct and emitted light with the albedo: the "
                     "voxels are relit from the probes) or full (its final radiance, GI included, as a host with only a "
                     "lit colour gives it)")
      ->capture_default_str()
      ->check(CLI::IsMember({"direct", "full"}));
  command.add_option("--memory-budget", options.memoryBudgetMebibytes,
                     "Limit all of ssvgi's GPU memory to this many MB (of 2^20 bytes, as SPEC §5's 30 MB), frame-size "
                     "images included: the brick pool, then the probe grid, then the voxel volume shrink to fit (stats "
                     "show what was chosen); 0: no limit")
      ->capture_default_str()
      ->check(kNonNegativeNumber);
}

uint64_t memoryBudgetBytes(const GiOptions& options) {
  return uint64_t(std::llround(options.memoryBudgetMebibytes * double(1u << 20)));
}

ssvgi::Settings giSettings(const GiOptions& options, const renderer::Scene& scene) {
  ssvgi::Settings settings = renderer::giSettingsFor(qualityTier(options.tier), scene);
  for (const std::string& assignment : options.overrides) {
    const size_t equals = assignment.find('=');
    const std::string name = assignment.substr(0, equals);
    const std::span<const ssvgi::SettingInfo> fields = ssvgi::settingInfos();
    const auto field = std::find_if(fields.begin(), fields.end(),
                                    [&](const ssvgi::SettingInfo& candidate) { return name == candidate.name; });
    if (equals == std::string::npos || field == fields.end())
      throw std::runtime_error("--gi-set " + assignment + ": expected NAME=VALUE with NAME a field of ssvgi::Settings");
    parseSetting(*field, settings, assignment.substr(equals + 1));
  }
  return settings;
}

nlohmann::json giSettingsJson(const ssvgi::Settings& settings) {
  nlohmann::json json = nlohmann::json::object();
  for (const ssvgi::SettingInfo& field : ssvgi::settingInfos())
    std::visit([&](auto member) { json[field.name] = settings.*member; }, field.member);
  return json;
}

}  // namespace ssvgi::cli
