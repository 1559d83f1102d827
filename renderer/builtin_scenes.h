#pragma once
#include "scene.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ssvgi::renderer {

// The scenes generated in code (SPEC §7): "cornell", "two-rooms", "dark-room", "courtyard", "gallery" (a shaded
// gallery lit by a sunlit wall behind the camera), "hall" (a closed hall lit by the sky through roof openings the
// camera does not see), "panel-room" (a closed room lit only by emissive panels) and "plane-point-light" (a point
// light over a plane, the analytic test case).
std::vector<std::string> builtinSceneNames();

struct BuiltinSceneOptions {
  bool movingObject = false;  // add the scene's moving object (Scene::movingObject) and its geometry
  bool sunCycle = false;      // let the sun follow a time-of-day cycle (Scene::sunCycle) where the scene has a sun
};

// The named built-in scene, or nothing when there is no scene of that name.
std::optional<Scene> makeBuiltinScene(std::string_view name, const BuiltinSceneOptions& options = {});

}  // namespace ssvgi::renderer
