#include "scenario_command.h"

#include <memory>

namespace ssvgi::cli {

CommandRunner addFlickerScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto flicker = std::make_shared<bench::FlickerOptions>();
  CLI::App* command = scenario.add_subcommand(
      "flicker", "Flicker (SPEC §7): mean over the pixels of the frame-to-frame relative change of the final image of "
                 "a still view, after it converged");
  addScenarioOptions(*command, *options, "dark-room");
  command->add_option("--frames", flicker->convergenceFrames, "Frames rendered before measuring")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--measured-frames", flicker->measuredFrames,
                      "Frame-to-frame changes averaged (16: the gather's whole jitter cycle)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  return [options, flicker] {
    return runScenario("flicker", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                                const bench::ScenarioRendering& rendering) {
      nlohmann::json figures =
          bench::toJson(bench::measureFlicker(device, rendering, {resolved.scene, resolved.camera}, *flicker));
      figures["frames"] = flicker->convergenceFrames;
      figures["measuredFrames"] = flicker->measuredFrames;
      return figures;
    });
  };
}

}  // namespace ssvgi::cli
