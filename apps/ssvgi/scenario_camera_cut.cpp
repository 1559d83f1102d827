#include "scenario_command.h"

#include <memory>

namespace ssvgi::cli {

namespace {

struct CameraCutCommandOptions {
  std::string to;  // the view after the cut, as --camera writes it
  bench::CameraCutOptions cut;
};

}  // namespace

CommandRunner addCameraCutScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto cut = std::make_shared<CameraCutCommandOptions>();
  CLI::App* command = scenario.add_subcommand(
      "cut", "Camera cut: the camera jumps from --camera to --to in one frame (a teleport, a turn); reports whether "
             "the images stay finite and, per frame after the cut, how far E_indirect is from a run that sat at the "
             "new view, and with --spp how far each is from the path-traced reference there");
  addScenarioOptions(*command, *options, "courtyard");
  command->add_option("--to", cut->to, "The view after the cut, PX,PY,PZ,TX,TY,TZ,VFOV_DEG as --camera")->required();
  command->add_option("--frames", cut->cut.framesBefore, "Frames rendered at the first view")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--frames-after", cut->cut.framesAfter, "Frames rendered at the new view after the cut")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--spp", cut->cut.referenceSamples,
                      "Also compare both runs' E_indirect over their last 8 frames with the reference path-traced at "
                      "the new view with this many samples per pixel (0: no reference)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 1048576u));
  command->add_option("--tolerance", cut->cut.recoveryTolerance,
                      "Recovered once the relative mean absolute difference stays below this")
      ->capture_default_str()
      ->check(kPositiveNumber);
  return [options, cut] {
    return runScenario("cut", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                            const bench::ScenarioRendering& rendering) {
      SceneOptions newView = options->scene;
      newView.camera = cut->to;
      bench::CameraCutOptions cutOptions = cut->cut;
      cutOptions.to = resolveScene(newView).camera;
      nlohmann::json figures =
          bench::toJson(bench::measureCameraCut(device, rendering, {resolved.scene, resolved.camera}, cutOptions));
      figures["frames"] = cutOptions.framesBefore;
      figures["framesAfter"] = cutOptions.framesAfter;
      figures["tolerance"] = cutOptions.recoveryTolerance;
      return figures;
    });
  };
}

}  // namespace ssvgi::cli
