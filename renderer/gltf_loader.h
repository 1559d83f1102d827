#pragma once
#include "scene.h"

#include <filesystem>
#include <stdexcept>

namespace ssvgi::renderer {

// A scene file that cannot be loaded. what() is one line naming the file and the problem.
class SceneLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Loads a glTF 2.0 file (.gltf with its buffers and images, or .glb): the node hierarchy flattened into instances,
// meshes (triangles; POSITION, NORMAL, TEXCOORD_0), materials (baseColorFactor/baseColorTexture, emissiveFactor ×
// KHR_materials_emissive_strength), KHR_lights_punctual (point and spot as local lights, directional as the sun;
// intensities used as given: candela as radiant intensity in W/sr, lux as irradiance in W/m²) and cameras (the first is
// the default view; a file without one gets a camera framing the whole scene). glTF has no sky: Scene::sky is None.
// Throws SceneLoadError for a missing or malformed file.
Scene loadGltf(const std::filesystem::path& path);

}  // namespace ssvgi::renderer
