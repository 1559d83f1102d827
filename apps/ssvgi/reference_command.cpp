#include "commands.h"
#include "output_files.h"
#include "scene_options.h"

#include "gpu_host/owned_device.h"
#include "path_tracer.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <memory>

namespace ssvgi::cli {

namespace {

struct ReferenceOptions {
  SceneOptions scene;
  uint32_t samplesPerPixel = 256;
  uint32_t bounces = reference::kDefaultMaxBounces;
  uint32_t seed = 0;
  std::string emitterSampling = "on";
  float animationSeconds = 0.0f;  // the time of the scene's animation shown
  float exposure = 1.0f;
  std::string out = "out-reference";
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int runReference(const ReferenceOptions& options) {
  const ResolvedScene resolved = resolveScene(options.scene);
  prepareOutputDirectory(options.out);
  gpu::OwnedDevice device = openDevice(gpu::DeviceDesc{options.scene.device, options.scene.validation});

  // The scene as `render` shows it at that time, so that the two can be compared pixel by pixel.
  const auto setupStart = std::chrono::steady_clock::now();
  reference::PathTracerSettings settings;
  settings.width = resolved.width;
  settings.height = resolved.height;
  settings.maxBounces = options.bounces;
  settings.seed = options.seed;
  settings.sampleEmitters = options.emitterSampling == "on";
  settings.exposure = options.exposure;
  const renderer::AnimatedState state =
      renderer::evaluateAnimation(resolved.scene, resolved.camera, options.animationSeconds);
  reference::PathTracer tracer(device, resolved.scene, state, settings);
  const double setupSeconds = secondsSince(setupStart);

  const std::string label = "path tracing " + resolved.scene.name;
  const auto traceStart = std::chrono::steady_clock::now();
  drawProgress(label, 0, options.samplesPerPixel);
  tracer.trace(options.samplesPerPixel, [&](uint32_t done) { drawProgress(label, done, options.samplesPerPixel); });
  const double traceSeconds = secondsSince(traceStart);

  nlohmann::json stats = sceneStats(device, options.scene, resolved);
  stats["samplesPerPixel"] = tracer.samplesPerPixel();
  stats["bounces"] = options.bounces;
  stats["seed"] = options.seed;
  stats["emitterSampling"] = settings.sampleEmitters;
  stats["emissiveTriangles"] = tracer.emissiveTriangleCount();
  stats["time"] = options.animationSeconds;
  stats["bvh"] = {{"triangles", tracer.triangleCount()}, {"nodes", tracer.bvhNodeCount()}, {"depth", tracer.bvhDepth()}};
  stats["setupSeconds"] = setupSeconds;  // BVH build, uploads, primary hits
  stats["seconds"] = traceSeconds;       // path tracing
  const double paths = double(resolved.width) * resolved.height * tracer.samplesPerPixel();
  stats["samplesPerSecond"] = paths / traceSeconds;  // paths (one per pixel and sample) per second
  nlohmann::json passes = nlohmann::json::object();
  for (const auto& timing : tracer.passTimings()) passes[timing.name] = timing.milliseconds;
  stats["gpuMilliseconds"] = {{"passes", passes}};

  writeRenderedImages(options.out,
                      RenderedImages{tracer.finalRadiance(), tracer.directIrradiance(), tracer.indirectIrradiance(),
                                     tracer.albedo(), tracer.normal(), tracer.viewDistance(), tracer.tonemapped()},
                      stats);

  if (reportValidationErrors(options.scene, device)) return 1;
  std::printf("wrote %s (%s): %u samples per pixel in %.1f s (%.3g paths/s) on %s\n", options.out.c_str(),
              kRenderedFileList, tracer.samplesPerPixel(), traceSeconds, paths / traceSeconds,
              device.description().c_str());
  return 0;
}

}  // namespace

CommandRunner addReferenceCommand(CLI::App& app) {
  auto options = std::make_shared<ReferenceOptions>();
  CLI::App* command = app.add_subcommand(
      "reference", "Path-trace the ground truth of a scene (the view `render` shows) and write the same files");
  addSceneOptions(*command, options->scene);
  command->add_option("--spp", options->samplesPerPixel, "Path samples per pixel for the indirect irradiance")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 20));
  command->add_option("--bounces", options->bounces,
                      "Most reflections light may take from its source to the visible surface (0: sky and emitters "
                      "only); Russian roulette ends most paths sooner without bias")
      ->capture_default_str()
      ->check(CLI::Range(0u, 1024u));
  command->add_option("--emitter-sampling", options->emitterSampling,
                      "Next-event estimation of emissive triangles, weighted against the paths' own hits by multiple "
                      "importance sampling: on, or off (paths find emitters only by hitting them: the same mean, more "
                      "noise)")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}));
  command->add_option("--seed", options->seed, "Random seed: the same seed gives bit-identical images")
      ->capture_default_str();
  command->add_option("--time", options->animationSeconds,
                      "Animation time in seconds (moving object, sun cycle, camera path); render's last frame of "
                      "--frames N is at (N - 1)/30")
      ->capture_default_str()
      ->check(kFiniteNumber & CLI::Range(0.0f, 1.0e6f));
  command->add_option("--exposure", options->exposure, "Multiplier on radiance before tonemapping")
      ->capture_default_str()
      ->check(kNonNegativeNumber);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  return [options] { return runReference(*options); };
}

}  // namespace ssvgi::cli
