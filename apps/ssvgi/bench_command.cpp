#include "commands.h"
#include "output_files.h"
#include "scene_options.h"

#include "gpu_host/owned_device.h"
#include "renderer.h"
#include "sky.h"
#include "trace_benchmark.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>
#include <string>

namespace ssvgi::cli {

namespace {

struct BenchOptions {
  SceneOptions scene;
  uint32_t frames = 16;
  uint32_t measuredFrames = 8;  // the last frames whose pass times are reported (median per pass)
  GiOptions giOptions;
  uint32_t rays = 1'000'000;
  uint32_t repetitions = 5;
  std::vector<uint32_t> pixelRays{4, 16, 64};
  uint32_t pixelStride = 8;
  std::string out;  // JSON file; stdout when empty
};

nlohmann::json traceMethodJson(const bench::TraceMethodResult& result) {
  return {{"milliseconds", result.milliseconds},
          {"raysPerSecond", result.raysPerSecond},
          {"readsPerRay", result.readsPerRay},
          {"hitFraction", result.hitFraction}};
}

// Rays a pass traced through the voxels, their reads and the reads per ray, as `pass`'s fields "rays", "reads",
// "readsPerRay", or with a prefix ("seed": "seedRays", …).
void addVoxelRays(nlohmann::json& pass, const ssvgi::VoxelRays& traced, const std::string& prefix = "") {
  const auto key = [&](const std::string& name) {
    return prefix.empty() ? name : prefix + char(std::toupper(name[0])) + name.substr(1);
  };
  pass[key("rays")] = traced.rays;
  pass[key("reads")] = traced.reads;
  pass[key("readsPerRay")] = traced.rays ? double(traced.reads) / traced.rays : 0.0;
}

// The work of ssvgi's passes in the counted frame (ssvgi::Stats::work), by pass name as in "gpuMilliseconds".
nlohmann::json workJson(const ssvgi::Stats& gi, uint32_t frame, size_t extraViews) {
  const ssvgi::WorkCounts& work = gi.work;
  nlohmann::json report = {{"frame", frame},
                           {"probeLevel", gi.probeLevelUpdatedLastFrame},
                           {"extraViews", extraViews},
                           {"HiZBuild", {{"texels", work.hizBuild.texels}}},
                           {"ObservedSpace", {{"rays", work.observedSpace.rays}, {"cells", work.observedSpace.cells}}},
                           {"SceneVoxelization", {{"voxels", work.sceneVoxelization.voxels},
                                                  {"voxelsInView", work.sceneVoxelization.voxelsInView}}},
                           {"ExtraViews", {{"voxels", work.extraViewVoxelization.voxels},
                                           {"voxelsInView", work.extraViewVoxelization.voxelsInView}}},
                           {"VoxelRelight", {{"voxels", work.voxelRelight.voxels}}},
                           {"ProbePlacement", {{"probes", work.probePlacement.probes},
                                               {"reads", work.probePlacement.reads}}},
                           {"ProbeTrace", {{"probes", work.probeTrace.probes}}},
                           {"ProbeRelocate", nlohmann::json::object()},
                           {"FinalGather", {{"tiles", work.finalGather.tiles}}},
                           {"TemporalUpsample", {{"pixels", work.temporalUpsample.pixels}}}};
  addVoxelRays(report["VoxelRelight"], work.voxelRelight.visibility);
  addVoxelRays(report["ProbeTrace"], work.probeTrace.rays);
  addVoxelRays(report["ProbeTrace"], work.probeTrace.seedVisibility, "seed");
  addVoxelRays(report["ProbeRelocate"], work.probeRelocate);
  addVoxelRays(report["FinalGather"], work.finalGather.visibility);
  return report;
}

int runBench(const BenchOptions& options) {
  bench::checkPixelTraceRayCounts(options.pixelRays);  // before minutes of rendering
  const ResolvedScene resolved = resolveScene(options.scene);
  gpu::OwnedDevice device = openDevice(gpu::DeviceDesc{options.scene.device, options.scene.validation});
  renderer::RendererSettings settings;
  settings.width = resolved.width;
  settings.height = resolved.height;
  settings.gi = giSettings(options.giOptions, resolved.scene);
  settings.extraViews = options.giOptions.extraViews;
  settings.litFrameDirectOnly = options.giOptions.litFrame == "direct";
  settings.giMemoryBudgetBytes = memoryBudgetBytes(options.giOptions);
  renderer::Renderer renderer(device, resolved.scene, settings);
  const std::string label = "bench " + resolved.scene.name;
  const renderer::AnimatedState state = renderer::evaluateAnimation(resolved.scene, resolved.camera, 0.0f);
  // Each pass's time in each measured frame (0 in a frame without it: the extra views take turns).
  std::map<std::string, std::vector<double>> passFrames;
  const uint32_t firstMeasured = options.frames - std::min(options.measuredFrames, options.frames);
  for (uint32_t frame = 0; frame < options.frames; ++frame) {
    renderer.render(state);
    if (frame >= firstMeasured) {
      for (const auto& timing : renderer.passTimings()) {
        std::vector<double>& times = passFrames[timing.name];
        times.resize(frame - firstMeasured, 0.0);
        times.push_back(timing.milliseconds);
      }
    }
    drawProgress(label, frame + 1, options.frames);
  }
  const auto measured = options.frames - firstMeasured;

  nlohmann::json report = sceneStats(device, options.scene, resolved);
  report["frames"] = options.frames;
  report["tier"] = options.giOptions.tier;
  report["giSettings"] = giSettingsJson(*settings.gi);
  report["giMemoryBudgetBytes"] = settings.giMemoryBudgetBytes;
  report["giSettingsUsed"] = giSettingsJson(renderer.giContext()->settings());  // within the budget
  // SPEC §5: the median of each pass over the measured frames. And its mean: work that comes in turns (the extra
  // views, a third of the bricks relit a frame) is done on some frames only, and the median leaves it out where those
  // are fewer than half.
  nlohmann::json passes = nlohmann::json::object(), passMeans = nlohmann::json::object();
  double ssvgiMilliseconds = 0.0, rendererMilliseconds = 0.0;
  for (auto& [name, times] : passFrames) {
    times.resize(measured, 0.0);
    passMeans[name] = std::accumulate(times.begin(), times.end(), 0.0) / double(measured);
    std::sort(times.begin(), times.end());
    const double median = measured % 2 ? times[measured / 2] : 0.5 * (times[measured / 2 - 1] + times[measured / 2]);
    passes[name] = median;
    (name.rfind("ssvgi: ", 0) == 0 ? ssvgiMilliseconds : rendererMilliseconds) += median;
  }
  report["measuredFrames"] = measured;
  report["gpuMilliseconds"] = {{"passes", passes},
                               {"passMeans", passMeans},
                               {"ssvgiTotal", ssvgiMilliseconds},
                               {"rendererTotal", rendererMilliseconds}};
  // The views beyond the camera (SPEC §6.3, §5): the host's rendering of them and ssvgi's injection of them, each
  // also a line of "passes", and the host's share of the renderer's own frame (its passes other than ssvgi's).
  const double hostViews = passes.value("renderer: ExtraViews", 0.0), ssvgiViews = passes.value("ssvgi: ExtraViews", 0.0);
  report["extraViews"] = {{"hostMilliseconds", hostViews},
                          {"ssvgiMilliseconds", ssvgiViews},
                          {"rendererMilliseconds", rendererMilliseconds},
                          {"hostShareOfRendererFrame", rendererMilliseconds > 0.0 ? hostViews / rendererMilliseconds : 0.0},
                          {"settings", {{"sunViewSize", settings.extraViews.sunViewSize},
                                        {"surroundViewSize", settings.extraViews.surroundViewSize},
                                        {"overheadViewSize", settings.extraViews.overheadViewSize},
                                        {"lightViewSize", settings.extraViews.lightViewSize},
                                        {"viewsPerFrame", settings.extraViews.viewsPerFrame}}}};
  const ssvgi::Stats gi = *renderer.giStats();
  report["ssvgiMemoryBytes"] = gi.totalBytes;
  report["bricksLive"] = gi.bricksLive;
  report["voxelsValid"] = gi.voxelsValid;
  report["probesUpdatedLastFrame"] = gi.probesUpdatedLastFrame;
  report["probeLevelUpdatedLastFrame"] = gi.probeLevelUpdatedLastFrame;

  const renderer::FloatImage viewDistance = renderer.viewDistance(), normal = renderer.normal();
  const auto trace = bench::benchmarkVoxelTrace(device, *renderer.giContext(), resolved.camera, viewDistance, normal,
                                                options.rays, options.repetitions);
  report["voxelTrace"] = {{"rays", trace.rays},
                          {"hierarchical", traceMethodJson(trace.hierarchical)},
                          {"flat", traceMethodJson(trace.flat)},
                          {"hierarchicalSpeedup", trace.hierarchical.raysPerSecond / trace.flat.raysPerSecond},
                          {"identicalHits", trace.identicalHits}};

  const auto pixelTrace = bench::benchmarkPixelTrace(
      device, *renderer.giContext(), resolved.camera, viewDistance, normal, renderer.indirectIrradiance(),
      renderer::projectSkyToSh2(renderer::makeSkyParameters(resolved.scene.sky, state.sun)), options.pixelStride,
      options.pixelRays, options.repetitions);
  nlohmann::json perPixel = nlohmann::json::array();
  for (const auto& result : pixelTrace.results)
    perPixel.push_back({{"raysPerPixel", result.raysPerPixel},
                        {"milliseconds", result.milliseconds},
                        {"fullFrameMilliseconds", result.fullFrameMilliseconds},
                        {"differenceFromSsvgi", result.differenceFromSsvgi},
                        {"noise", result.noise}});
  report["pixelTrace"] = {{"tracedPixels", pixelTrace.tracedPixels},
                          {"surfacePixels", pixelTrace.surfacePixels},
                          {"pixelStride", options.pixelStride},
                          {"results", perPixel}};

  // One more frame, counting the work of ssvgi's passes (FrameDesc::countWork): after everything above, which it
  // would otherwise change.
  renderer.setCountGiWork(true);
  renderer.render(state);
  report["work"] = workJson(*renderer.giStats(), options.frames, renderer.extraViews().size());

  writeJsonReport(report, options.out, device);
  return reportValidationErrors(options.scene, device) ? 1 : 0;
}

}  // namespace

CommandRunner addBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench", "Render a scene with ssvgi and report, as JSON, the GPU time of every pass, GI memory and counters, "
               "rays/s of the hierarchical against the flat voxel trace on the same rays, a per-pixel voxel "
               "trace's time and quality against ssvgi's (SPEC §7 baselines), and the work of ssvgi's passes "
               "(rays, reads, items) in one more frame");
  addSceneOptions(*command, options->scene);
  command->add_option("--frames", options->frames, "Frames to render")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--measured-frames", options->measuredFrames,
                      "The last frames whose GPU times are reported: the median of each pass over them")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  addGiOptions(*command, options->giOptions);
  command->add_option("--rays", options->rays, "Rays for the voxel trace comparison")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64'000'000u));
  command->add_option("--repetitions", options->repetitions, "Timed runs of each trace; the median is reported")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100u));
  command->add_option("--pixel-rays", options->pixelRays,
                      "Rays per pixel of the per-pixel voxel trace baseline (SPEC §7), even squares; may be repeated")
      ->capture_default_str()
      ->check(CLI::Range(4u, 1024u));
  command->add_option("--pixel-stride", options->pixelStride,
                      "The per-pixel baseline traces every Nth surface pixel in X and Y; its time is scaled to all")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  command->add_option("--out", options->out, "Write the JSON report to this file instead of standard output");
  return [options] { return runBench(*options); };
}

}  // namespace ssvgi::cli
