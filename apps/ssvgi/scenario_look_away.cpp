#include "scenario_command.h"

#include <memory>

namespace ssvgi::cli {

CommandRunner addLookAwayScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto lookAway = std::make_shared<bench::LookAwayOptions>();
  CLI::App* command = scenario.add_subcommand(
      "look-away", "Look away (SPEC §6.1): a local light is switched off while the camera looks the other way; frames "
                   "after it turns back until the indirect irradiance is within the tolerance of a run in which the "
                   "light was never on");
  addScenarioOptions(*command, *options, "cornell");
  command->add_option("--light", lookAway->light, "Index of the scene's local light to switch off")->capture_default_str();
  command->add_option("--frames", lookAway->framesBefore, "Frames rendered at the view with the light on")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--frames-away", lookAway->framesAway, "Frames rendered looking the other way, the light off")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--frames-after", lookAway->framesAfter, "Frames rendered back at the view")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--tolerance", lookAway->tolerance,
                      "Relative mean absolute difference of E_indirect from the run without the light that counts as "
                      "matched")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  return [options, lookAway] {
    return runScenario("look-away", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                                  const bench::ScenarioRendering& rendering) {
      nlohmann::json figures =
          bench::toJson(bench::measureLookAway(device, rendering, {resolved.scene, resolved.camera}, *lookAway));
      figures["light"] = lookAway->light;
      figures["frames"] = lookAway->framesBefore;
      figures["framesAway"] = lookAway->framesAway;
      figures["framesAfter"] = lookAway->framesAfter;
      figures["tolerance"] = lookAway->tolerance;
      return figures;
    });
  };
}

}  // namespace ssvgi::cli
