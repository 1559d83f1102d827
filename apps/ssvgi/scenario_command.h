#pragma once
// `ssvgi scenario <name>`: the scenario measurements of SPEC §7, one subcommand each, each printing one JSON object.
// A scenario lives in its own file (scenario_<name>.cpp): it adds its subcommand to `scenario` and returns its runner,
// as the top-level commands do (commands.h). Adding one is its file, its declaration below and its line in the list
// of scenario_command.cpp.
#include "commands.h"
#include "scene_options.h"

#include "gpu_host/owned_device.h"
#include "scenarios.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <initializer_list>
#include <string>

namespace ssvgi::cli {

CommandRunner addLeakScenario(CLI::App& scenario);
CommandRunner addFlickerScenario(CLI::App& scenario);
CommandRunner addLagScenario(CLI::App& scenario);
CommandRunner addCameraCutScenario(CLI::App& scenario);
CommandRunner addLookAwayScenario(CLI::App& scenario);
CommandRunner addErrorScenario(CLI::App& scenario);
CommandRunner addProbesScenario(CLI::App& scenario);

// The options every scenario has: the scene options of render (scene_options.h) at 640×360, the GI options (--tier,
// --gi-set) and --out.
struct ScenarioOptions {
  SceneOptions scene;
  GiOptions gi;
  std::string out;  // JSON file; standard output when empty
};

// Adds the options of `options` to a scenario's subcommand, `defaultScene` as --scene's default. A scenario's view
// stands still, so the animation options (--moving-object, --sun-cycle, --camera-path) are left out, and so is every
// scene option named in `without` (a scenario made for one scene, with its own views, leaves out --scene, --camera, …).
void addScenarioOptions(CLI::App& command, ScenarioOptions& options, const std::string& defaultScene,
                        std::initializer_list<const char*> without = {});

// What a scenario measures: on the device, in the resolved scene, rendered as `rendering` says; returns its figures.
using ScenarioMeasurement = std::function<nlohmann::json(gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                                         const bench::ScenarioRendering& rendering)>;

// Resolves the scene, opens the device, measures, and prints the report — the scenario's name, the device, scene,
// size, GI settings and wall time, then the figures — on standard output or into --out. Returns the exit code: 1 when
// validation was on and reported errors, else 0; a bad option or file throws std::runtime_error (one line).
int runScenario(const std::string& name, const ScenarioOptions& options, const ScenarioMeasurement& measure);

}  // namespace ssvgi::cli
