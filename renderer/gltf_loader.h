#pragma once
#include "scene.h"

#include <filesystem>
#include <stdexcept>

namespace ssvgi::renderer {

// A scene file that cannot be loaded. what() is one line naming the file, the object (as its JSON path, e.g.
// `nodes[12].matrix` or `materials[3].emissiveFactor[0]`) where there is one, and the problem.
class SceneLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Loads a glTF 2.0 file (.gltf with its buffers and images, or .glb): the node hierarchy flattened into instances,
// meshes (triangles, strips and fans; points and lines are not drawn; POSITION, NORMAL, COLOR_0 and the TEXCOORD_n the
// base colour texture names), materials (baseColorFactor/baseColorTexture with its KHR_texture_transform, alphaMode
// MASK as Material::alphaCutoff — BLEND cut out below half, and a KHR_materials_transmission factor above half
// everywhere —, emissiveFactor × KHR_materials_emissive_strength × emissiveTexture), KHR_lights_punctual (point and
// spot as local lights, directional as the sun; intensities used as given: candela as radiant intensity in W/sr, lux as
// irradiance in W/m²) and cameras (the first is the default view; a file without one gets a camera framing the whole
// scene). glTF has no sky: Scene::sky is None.
//
// The file may come from anyone: it gives either a scene whose every number is finite and within the bounds below,
// which the renderer draws finite, or a SceneLoadError; never a crash, a hang or a NaN. What is refused:
// - Size and structure: the file, and each file it refers to, must be a regular file of at most 1 GiB; JSON nested
//   at most 128 levels deep (glTF's own structure needs about 10; the parsers recurse once per level); a GLB of
//   version 2 whose chunks lie inside it; images of at most 8192 × 8192 pixels.
// - References: a buffer or image URI (other than a data: URI) must resolve, symbolic links followed, to a file in the
//   glTF file's folder or below it. A viewer of a downloaded file must not read ~/.ssh/id_rsa or /etc/passwd because
//   the file names them; a scene's own files sit beside it. The working directory is never searched.
// - extensionsRequired may list only the extensions read here: KHR_lights_punctual, KHR_materials_emissive_strength,
//   KHR_materials_transmission, KHR_mesh_quantization and KHR_texture_transform.
// - Every member the loader reads must have its JSON type: tinygltf would turn a "yfov" given as a string, or an index
//   given as -1 or 1.5, into its default without a word. Indices are whole numbers from 0; every number is finite as a
//   float.
// - Colours: baseColorFactor, emissiveFactor and a light's color in [0, 1], as glTF specifies (an albedo above 1 would
//   make the GI's bounces add light). emissiveStrength in [0, 65504]: the renderer's G-buffer holds emission as half
//   floats, whose largest value that is. alphaMode one of OPAQUE, MASK and BLEND; alphaCutoff at least 0;
//   transmissionFactor in [0, 1].
// - Lights: intensity in [0, 1e5] (W/sr, or W/m² for the sun; the noon sun gives about 1,000 W/m², and 1e5 leaves room
//   for candela and lux used as they are, while 1e10 overflows the half floats of the GI); range > 0 where given;
//   spot cones with 0 ≤ innerConeAngle ≤ outerConeAngle < π/2.
// - Cameras: yfov in [0.001, π − 0.001] radians (a projection's scale 1/tan(yfov/2) stays below 2,000), znear in
//   [1e-4, 1e5] m, zfar and aspectRatio > 0 where given.
// - Transforms: a matrix must be affine (bottom row 0, 0, 0, 1), a rotation a quaternion of non-zero length (it is
//   normalised). Every node's world transform must be finite, its origin within 1e5 m of the world's (float keeps
//   positions there to 1 cm). A camera's view and up directions, and a spot or directional light's direction, must not
//   collapse under it. A mesh under a degenerate transform (|determinant| < 1e-24, such as glTF's scale of 0 that hides
//   a node) is not drawn: its normals could not be transformed.
// - Geometry: positions, normals and texture coordinates finite (also under KHR_texture_transform); every drawn vertex
//   within 1e5 m of the origin in world space. A normal of zero length is replaced by its first triangle's face
//   normal; other normals are normalised.
Scene loadGltf(const std::filesystem::path& path);

}  // namespace ssvgi::renderer
