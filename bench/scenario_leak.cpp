// SPEC §7 leak ratio in `two-rooms`: a lit room and a dark room share a 0.25 m wall (x ∈ [−0.125, 0.125]) with a
// closed door. No light path leads into the dark room, so every watt of indirect light there is a leak.
//
// The setup makes a leak possible, so that a broken guard shows: the camera first sits in the lit room looking at the
// shared wall and the door (the scene's "lit room" camera), where a spot lights the door brightly. Its voxels then hold
// the lit side of the wall, and the probes near the wall — including those whose grid position (x = 0, a multiple of
// the 1 m spacing) lies inside it, which the virtual offset must push out on one side — have traced them. Then the
// camera moves to the dark room, looking at the same wall from the other side (the "dark room" camera). The lit room's
// voxels stay (occluded bricks keep their data, SPEC §4.2), its probes keep their radiance, and probes on both sides of
// the wall are one trilinear cell apart: anything that carries light through the wall (rays that pass a one-voxel
// wall, probes moved to the wrong side, gathers that weight probes behind the wall) now lights the dark room.
//
// The ratio compares the dark room after the move with the lit room before it. A pixel belongs to the room its
// surface point lies in, split at the shared wall's middle plane x = 0: every visible surface is inside one room.
#include "scenario_rendering.h"

#include <stdexcept>

namespace ssvgi::bench {

namespace {

constexpr float kSharedWallMiddleX = 0.0f;

// The mean luminance of E_indirect over the pixels whose surface lies on the chosen side of the shared wall, and their
// number.
struct RoomIrradiance {
  double mean = 0.0;
  uint64_t pixels = 0;
};

RoomIrradiance roomIrradiance(renderer::Renderer& renderer, const renderer::Camera& camera, bool darkRoom) {
  const SurfacePoints points = surfacePoints(camera, renderer.viewDistance());
  std::vector<bool> inRoom(points.isSurface.size());
  uint64_t pixels = 0;
  for (size_t pixel = 0; pixel < inRoom.size(); ++pixel) {
    inRoom[pixel] = points.isSurface[pixel] && (points.positions[pixel].x > kSharedWallMiddleX) == darkRoom;
    pixels += inRoom[pixel];
  }
  return {meanWhere(luminance(renderer.indirectIrradiance()), inRoom), pixels};
}

const renderer::Camera& cameraNamed(const renderer::Scene& scene, const std::string& name) {
  for (const renderer::Camera& camera : scene.cameras)
    if (camera.name == name) return camera;
  throw std::runtime_error("scenario leak: the scene " + scene.name + " has no camera '" + name + "'");
}

}  // namespace

LeakResult measureLeak(gpu::OwnedDevice& device, const ScenarioRendering& rendering, const renderer::Scene& twoRooms,
                       const LeakOptions& options) {
  const renderer::Camera& litView = cameraNamed(twoRooms, "lit room");
  const renderer::Camera& darkView = cameraNamed(twoRooms, "dark room");

  ScenarioRenderer renderer(device, twoRooms, rendering);
  renderer.render(litView, options.framesPerRoom);
  const RoomIrradiance lit = roomIrradiance(renderer.renderer(), litView, false);
  renderer.render(darkView, options.framesPerRoom);
  const RoomIrradiance dark = roomIrradiance(renderer.renderer(), darkView, true);
  if (lit.pixels == 0 || dark.pixels == 0 || !(lit.mean > 0.0))
    throw std::runtime_error("scenario leak: the lit room shows no indirect light, the ratio means nothing");

  LeakResult result;
  result.litRoomIrradiance = lit.mean;
  result.darkRoomIrradiance = dark.mean;
  result.leakRatio = dark.mean / lit.mean;
  result.litRoomPixels = lit.pixels;
  result.darkRoomPixels = dark.pixels;
  return result;
}

nlohmann::json toJson(const LeakResult& result) {
  return {{"leakRatio", result.leakRatio},
          {"litRoomIrradiance", result.litRoomIrradiance},
          {"darkRoomIrradiance", result.darkRoomIrradiance},
          {"litRoomPixels", result.litRoomPixels},
          {"darkRoomPixels", result.darkRoomPixels}};
}

}  // namespace ssvgi::bench
