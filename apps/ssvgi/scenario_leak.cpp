#include "scenario_command.h"

#include <memory>

namespace ssvgi::cli {

CommandRunner addLeakScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto leak = std::make_shared<bench::LeakOptions>();
  CLI::App* command = scenario.add_subcommand(
      "leak", "Leak ratio (SPEC §7) in two-rooms: mean indirect irradiance in the dark room, after the camera moved "
              "there from the lit room, over the mean in the lit room (bench/scenario_leak.cpp says why so)");
  // The scenario is made for two-rooms and its two cameras: the scene, its view and its lights are not options.
  addScenarioOptions(*command, *options, "two-rooms", {"--scene", "--camera", "--sun", "--sky"});
  command->add_option("--frames", leak->framesPerRoom, "Frames rendered in each room")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  return [options, leak] {
    return runScenario("leak", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                             const bench::ScenarioRendering& rendering) {
      nlohmann::json figures = bench::toJson(bench::measureLeak(device, rendering, resolved.scene, *leak));
      figures["framesPerRoom"] = leak->framesPerRoom;
      return figures;
    });
  };
}

}  // namespace ssvgi::cli
