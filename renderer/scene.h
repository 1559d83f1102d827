#pragma once
// The host renderer's scene model: what the built-in scenes and the glTF loader produce and what the renderer and the
// reference path tracer draw. Units are metres, right-handed, +Y up (SPEC §2). Radiometric quantities are used as given:
// a light's intensity is radiant intensity (W/sr per colour channel), the sun's is irradiance on a surface facing it
// (W/m², glTF's "lux"), emission is radiance (W/(sr·m²)).
#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ssvgi::renderer {

struct Vertex {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec2 uv{0.0f};
  glm::vec3 color{1.0f};  // linear, in [0, 1]: multiplies the material's base colour (glTF's COLOR_0)
};

// 8-bit RGBA texture, sRGB-encoded colour (glTF base colour textures are sRGB).
struct Texture {
  std::string name;
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4 bytes, rows top to bottom
};

inline constexpr uint32_t kNoTexture = ~0u;

// Lambertian material. The albedo at a point is baseColor × texture (texture decoded from sRGB to linear).
struct Material {
  std::string name;
  glm::vec3 baseColor{1.0f};       // linear
  uint32_t baseColorTexture = kNoTexture;
  // Emitted radiance, W/(sr·m²): emission (emissiveFactor × emissive_strength) times the emission texture (decoded
  // from sRGB) where there is one.
  glm::vec3 emission{0.0f};
  uint32_t emissionTexture = kNoTexture;
  // Where the base colour texture's alpha (1 without one) is below this, there is no surface (foliage, fences, clear
  // glass): for glTF's MASK its alphaCutoff over the base colour factor's alpha (gltf_loader.h says the rest).
  // 0: opaque.
  float alphaCutoff = 0.0f;
};

// A triangle mesh in its own object space, one material.
struct Mesh {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;  // triangle list, counter-clockwise front faces
  uint32_t material = 0;
};

struct Instance {
  uint32_t mesh = 0;
  glm::mat4 transform{1.0f};  // object to world
};

enum class LightType { Point, Spot };

struct LocalLight {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // spot axis, unit length, pointing away from the light
  glm::vec3 intensity{1.0f};               // radiant intensity, W/sr per channel (colour × glTF intensity)
  float range = 0.0f;                      // 0: unlimited (inverse-square falloff only)
  float innerConeAngle = 0.0f;             // spot: radians from the axis, full intensity inside
  float outerConeAngle = 0.7853982f;       // spot: radians from the axis, zero intensity outside
  bool castsShadow = true;
};

struct Sun {
  bool enabled = false;
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // unit vector from the scene towards the sun
  glm::vec3 illuminance{0.0f};            // irradiance on a surface facing the sun, W/m² per channel
};

enum class SkyKind { None, Default, Uniform };

struct Sky {
  SkyKind kind = SkyKind::None;
  glm::vec3 uniformRadiance{0.0f};  // SkyKind::Uniform: the same radiance from every direction, W/(sr·m²)
  float intensity = 1.0f;           // multiplies the analytic sky (SkyKind::Default)
};

struct Camera {
  std::string name;
  glm::vec3 position{0.0f, 1.0f, 5.0f};
  glm::vec3 target{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float verticalFov = 0.8726646f;  // radians
  float nearPlane = 0.05f;         // metres; the far plane is infinite (reversed-Z)
};

// A looping camera path through key poses, linear in between.
struct CameraKey {
  float time = 0.0f;  // seconds
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f};
};

// An optional object that moves back and forth along a straight segment, so that tests and views see dynamic geometry.
struct MovingObject {
  uint32_t instance = 0;            // index into Scene::instances
  glm::vec3 offset{0.0f};           // displacement at the far end of the motion, metres
  float period = 4.0f;              // seconds for a full back-and-forth
};

// A time-of-day sun: the sun's direction follows azimuth/elevation over the day.
struct SunCycle {
  float azimuthDegrees = 0.0f;     // where the sun stands at time 0
  float elevationDegrees = 45.0f;
  float azimuthDegreesPerSecond = 0.0f;
  float elevationDegreesPerSecond = 0.0f;
};

struct Scene {
  std::string name;
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<LocalLight> lights;
  Sun sun;
  Sky sky;
  std::vector<Camera> cameras;  // the first is the default view
  std::vector<CameraKey> cameraPath;             // empty: the camera stays still
  std::optional<MovingObject> movingObject;
  std::optional<SunCycle> sunCycle;              // empty: the sun stays where `sun` says
  // The GI's voxel size and probe spacing for this scene relative to its quality tier's (ssvgi::Settings); the loaders
  // set it from the scene's size (giDetailScaleFor).
  float giDetailScale = 1.0f;
};

struct Bounds {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
};

// World-space bounds of all instances' vertices (all zero for a scene without geometry).
Bounds worldBounds(const Scene& scene);

// Scene::giDetailScale for a scene of these bounds seen from `viewpoint` (its first camera). The tiers' sizes (0.25 m
// voxels, 1 m probes) suit rooms and streets; in a smaller scene most of its probes would sit in its walls, and the few
// left inside could not resolve its light (docs/QUALITY.md, "A scene's GI detail follows its size"). So the scale
// halves, down to a sixteenth, until the bounds' middle extent spans at least kGiProbeSpacingsAcrossScene spacings of
// the tiers' 1 m probes: two probes or more inside the scene along its two larger axes. The middle extent, not the
// smallest: a wide, flat scene keeps the tiers' volume. But not so far that the scene's centre lies more than
// kGiProbeSpacingsToViewpoint spacings from the viewpoint: the finest probes (a grid of 32 or more spacings around the
// camera) and the voxel volume must still reach it (docs/QUALITY.md, "Tabletop scenes").
constexpr float kGiProbeSpacingsAcrossScene = 3.0f;
constexpr float kGiProbeSpacingsToViewpoint = 32.0f;
float giDetailScaleFor(const Bounds& bounds, const glm::vec3& viewpoint);

// Unit vector towards the sun. Azimuth is measured in the horizontal plane from +Z towards +X (0° → +Z, 90° → +X),
// elevation above the horizon: (cos(el)·sin(az), sin(el), cos(el)·cos(az)).
glm::vec3 sunDirection(float azimuthDegrees, float elevationDegrees);

// The state of the scene's animation at a time: the camera on its path, the moving object's transform and the sun.
// The camera path repeats every `cameraPath.back().time` seconds (repeat the first pose as the last key for a seamless
// loop); the camera keeps baseCamera's up vector, field of view and near plane. The moving object starts at rest at its
// instance's transform and reaches `offset` at half the period. With a SunCycle the sun turns, keeping its illuminance.
struct AnimatedState {
  Camera camera;
  std::optional<glm::mat4> movingObjectTransform;  // replaces instances[movingObject->instance].transform
  Sun sun;
};
AnimatedState evaluateAnimation(const Scene& scene, const Camera& baseCamera, float seconds);

}  // namespace ssvgi::renderer
