#pragma once
#include "scene.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ssvgi::renderer {

// The scenes generated in code (SPEC §7): "cornell", "two-rooms", "dark-room", "courtyard", and "plane-point-light"
// (a point light over a plane, the analytic test case).
std::vector<std::string> builtinSceneNames();

// The named built-in scene, or nothing when there is no scene of that name.
std::optional<Scene> makeBuiltinScene(std::string_view name);

}  // namespace ssvgi::renderer
