#include "scenario_command.h"

#include <memory>

namespace ssvgi::cli {

CommandRunner addLagScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto lag = std::make_shared<bench::LagOptions>();
  CLI::App* command = scenario.add_subcommand(
      "lag", "Lag (SPEC §7): frames after a local light is switched on (or off, --off) until the mean indirect "
             "irradiance has made 90 % of its way to the new steady state; SPEC §6.2's target is reported alongside");
  addScenarioOptions(*command, *options, "cornell");
  command->add_option("--light", lag->light, "Index of the scene's local light to switch")->capture_default_str();
  command->add_flag("--off", lag->switchOff, "Switch the light off (on before the switch) instead of on");
  command->add_option("--frames", lag->convergenceFrames, "Frames rendered before the switch")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--frames-after", lag->framesAfterSwitch, "Frames rendered after the switch")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--steady-frames", lag->steadyFrames,
                      "The last frames before the switch, averaged as the old steady state")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--settled-mean-frames", lag->settledMeanFrames,
                      "The last frames of the run with the light as the switch leaves it all along, averaged as the "
                      "new steady state")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--settled-frames", lag->settledRunFrames,
                      "Frames the run with the light as the switch leaves it all along renders in all (at least as "
                      "many as the switched run): its last steady frames are the new steady state")
      ->capture_default_str()
      ->check(CLI::Range(0u, 1000000u));
  return [options, lag] {
    return runScenario("lag", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                            const bench::ScenarioRendering& rendering) {
      nlohmann::json figures = bench::toJson(bench::measureLag(device, rendering, {resolved.scene, resolved.camera}, *lag));
      figures["light"] = lag->light;
      figures["switch"] = lag->switchOff ? "off" : "on";
      figures["frames"] = lag->convergenceFrames;
      figures["framesAfterSwitch"] = lag->framesAfterSwitch;
      figures["steadyFrames"] = lag->steadyFrames;
      figures["settledFrames"] = lag->settledRunFrames;
      figures["settledMeanFrames"] = lag->settledMeanFrames;
      return figures;
    });
  };
}

}  // namespace ssvgi::cli
