#include "commands.h"
#include "output_files.h"
#include "rendering_options.h"
#include "scene_options.h"

#include "gpu_host/owned_device.h"
#include "renderer.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ssvgi::cli {

namespace {

struct RenderOptions {
  SceneOptions scene;
  uint32_t frames = 32;  // enough for the GI of a still view to settle (SPEC §4.5: probes converge over updates)
  RenderingOptions rendering;
  std::vector<std::string> debugViews;  // names of debugViewsByName()
  std::string debugCamera;              // PX,PY,PZ,TX,TY,TZ,VFOV_DEG; empty: the rendering camera
  std::string out = "out";
};

nlohmann::json giStatsJson(const ssvgi::Stats& gi) {
  nlohmann::json memory = nlohmann::json::object();
  for (const auto& resource : gi.memory) memory[resource.name] = resource.bytes;
  return {{"memoryBytes", {{"resources", memory}, {"total", gi.totalBytes}}},
          {"memoryBudgetBytes", gi.memoryBudgetBytes},
          {"settings", giSettingsJson(gi.settings)},
          {"brickPoolCapacity", gi.brickPoolCapacity},
          {"bricksLive", gi.bricksLive},
          {"bricksFree", gi.bricksFree},
          {"bricksNeverUsed", gi.bricksNeverUsed},
          {"bricksDroppedLastFrame", gi.bricksDroppedLastFrame},
          {"bricksDroppedTotal", gi.bricksDroppedTotal},
          {"bricksAllocatedLastFrame", gi.bricksAllocatedLastFrame},
          {"bricksReleasedLastFrame", gi.bricksReleasedLastFrame},
          {"bricksInjectedLastFrame", gi.bricksVisibleLastFrame},
          {"voxelsValid", gi.voxelsValid},
          {"probesUpdatedLastFrame", gi.probesUpdatedLastFrame},
          {"probesWatchedForChange", gi.probesWatchedForChange},
          {"probesCutByChange", gi.probesCutByChange},
          {"sharedChangeRecovery", gi.sharedChangeRecovery},
          {"probesLeaning", gi.probesLeaning},
          {"probesLeaningError", gi.probesLeaningError},
          {"probesLoopGap", gi.probesLoopGap},
          {"sharedDrift", gi.sharedDrift},
          {"voxelVolume", {{"min", gi.voxelVolume.min}, {"max", gi.voxelVolume.max}}}};
}

nlohmann::json statsJson(const gpu::OwnedDevice& device, const RenderOptions& options, const ResolvedScene& resolved,
                         const renderer::RendererSettings& settings, renderer::Renderer& renderer) {
  nlohmann::json stats = sceneStats(device, options.scene, resolved);
  stats["frames"] = options.frames;
  stats["gi"] = options.rendering.gi;
  stats["tier"] = options.rendering.giOptions.tier;
  if (settings.gi) stats["giSettings"] = giSettingsJson(*settings.gi);
  stats["unshadowedLocalLights"] = renderer.unshadowedLightCount();
  double frameMilliseconds = 0.0;
  nlohmann::json passes = nlohmann::json::object();
  for (const auto& timing : renderer.passTimings()) {
    passes[timing.name] = timing.milliseconds;
    frameMilliseconds += timing.milliseconds;
  }
  stats["gpuMilliseconds"] = {{"passes", passes}, {"frame", frameMilliseconds}};
  if (const auto gi = renderer.giStats()) stats["ssvgi"] = giStatsJson(*gi);
  return stats;
}

int runRender(const RenderOptions& options) {
  const ResolvedScene resolved = resolveScene(options.scene);
  std::optional<renderer::Camera> debugCamera;
  if (!options.debugCamera.empty()) debugCamera = parseCamera(options.debugCamera, "--debug-camera", resolved.camera);

  prepareOutputDirectory(options.out);

  gpu::OwnedDevice device = openDevice(gpu::DeviceDesc{options.scene.device, options.scene.validation});
  // ssvgi runs for its indirect light, or only for the debug views of its voxels (--gi off: no indirect light).
  const renderer::RendererSettings settings = rendererSettings(options.rendering, resolved, !options.debugViews.empty());
  renderer::Renderer renderer(device, resolved.scene, settings);

  const std::string label = "rendering " + resolved.scene.name;
  for (uint32_t frame = 0; frame < options.frames; ++frame) {
    renderer.render(renderer::evaluateAnimation(resolved.scene, resolved.camera, float(frame) * kFrameSeconds));
    drawProgress(label, frame + 1, options.frames);
  }

  // The stats before the debug views, whose passes are not the frame's.
  const nlohmann::json stats = statsJson(device, options, resolved, settings, renderer);
  RenderedImages images{renderer.finalRadiance(), renderer.directIrradiance(), renderer.indirectIrradiance(),
                        renderer.albedo(),        renderer.normal(),           renderer.viewDistance(),
                        renderer.tonemapped()};
  images.confidence = renderer.confidence();
  for (const std::string& name : options.debugViews) {
    images.debugImages["debug_" + name] = renderer.giDebugView(debugViewsByName().at(name), debugCamera);
  }
  writeRenderedImages(options.out, images, stats);

  if (reportValidationErrors(options.scene, device)) return 1;
  std::printf("wrote %s (%s, confidence.exr) on %s\n", options.out.c_str(), kRenderedFileList,
              device.description().c_str());
  return 0;
}

}  // namespace

CommandRunner addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Render a scene and write the last frame's images and stats.json");
  addSceneOptions(*command, options->scene);
  command->add_option("--frames", options->frames, "Frames to render, the animation advancing 1/30 s per frame")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  addRenderingOptions(*command, options->rendering);
  command->add_option("--debug", options->debugViews,
                      "Also write ssvgi's view of the last frame, ray-traced through its voxels from the camera: "
                      "voxels (stored radiance), bricks (a colour per brick) or probes (level-0 probes as spheres lit "
                      "by their SH; magenta invalid, yellow just offset) or confidence (the GI's confidence on the "
                      "surfaces met, grey from black 0 to white 1; dark blue: no voxel) or observed (voxels as "
                      "the probes see them: magenta where a ray crossed unobserved space and met nothing), as DIR/debug_NAME.png and .exr; may be repeated")
      ->check(CLI::IsMember(debugViewsByName()));
  command->add_option("--debug-camera", options->debugCamera,
                      "The debug views' camera, PX,PY,PZ,TX,TY,TZ,VFOV_DEG (default: the rendering camera): ssvgi's "
                      "voxels and probes seen from elsewhere, e.g. the surfaces the rendering camera never sees");
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  return [options] { return runRender(*options); };
}

}  // namespace ssvgi::cli
