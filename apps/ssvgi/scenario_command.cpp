#include "scenario_command.h"

#include "output_files.h"

#include <array>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>

namespace ssvgi::cli {

namespace {

// Every scenario, in the order `ssvgi scenario --help` lists them.
constexpr std::array kScenarios = {
    addLeakScenario,
    addFlickerScenario,
    addLagScenario,
    addCameraCutScenario,
    addLookAwayScenario,
    addErrorScenario,
    addProbesScenario,
};

}  // namespace

void addScenarioOptions(CLI::App& command, ScenarioOptions& options, const std::string& defaultScene,
                        std::initializer_list<const char*> without) {
  options.scene.scene = defaultScene;
  options.scene.size = "640x360";
  addSceneOptions(command, options.scene);
  for (const char* name : {"--moving-object", "--sun-cycle", "--camera-path"}) command.remove_option(command.get_option(name));
  for (const char* name : without) command.remove_option(command.get_option(name));
  addGiOptions(command, options.gi);
  command.add_option("--out", options.out, "Write the JSON report to this file instead of standard output");
}

int runScenario(const std::string& name, const ScenarioOptions& options, const ScenarioMeasurement& measure) {
  const ResolvedScene resolved = resolveScene(options.scene);
  gpu::OwnedDevice device = openDevice(gpu::DeviceDesc{options.scene.device, options.scene.validation});
  const bench::ScenarioRendering rendering{resolved.width, resolved.height, giSettings(options.gi, resolved.scene),
                                           options.gi.extraViews, options.gi.litFrame == "direct",
                                           memoryBudgetBytes(options.gi)};

  const auto start = std::chrono::steady_clock::now();
  const nlohmann::json figures = measure(device, resolved, rendering);
  const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;

  nlohmann::json report = {{"scenario", name},
                           {"device", device.description()},
                           {"scene", options.scene.scene},
                           {"width", resolved.width},
                           {"height", resolved.height},
                           {"tier", options.gi.tier},
                           {"giSettings", giSettingsJson(rendering.gi)},
                           {"memoryBudgetBytes", rendering.giMemoryBudgetBytes},
                           {"seconds", seconds.count()}};
  report.update(figures);
  writeJsonReport(report, options.out, device);
  return reportValidationErrors(options.scene, device) ? 1 : 0;
}

CommandRunner addScenarioCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "scenario", "Measure one of SPEC §7's scenarios (leak ratio, flicker, lag, recovery after a camera cut, error vs "
                  "the path-traced reference, probe irradiance vs the reference) with ssvgi on, and report its "
                  "figures as JSON");
  command->require_subcommand(1);
  auto runners = std::make_shared<std::map<CLI::App*, CommandRunner>>();
  for (const auto addScenario : kScenarios) {
    const CommandRunner runner = addScenario(*command);
    (*runners)[command->get_subcommands({}).back()] = runner;
  }
  return [runners] {
    for (auto& [scenario, runner] : *runners)
      if (scenario->parsed()) return runner();
    return 1;
  };
}

}  // namespace ssvgi::cli
