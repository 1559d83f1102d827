// The scenarios that hold the GI to the path-traced reference (bench/reference_scenarios.h): `ssvgi scenario error`
// (SPEC §7's error vs reference) and `ssvgi scenario probes` (the probes' irradiance against the reference's at the
// same points).
#include "scenario_command.h"

#include "reference_scenarios.h"

#include <memory>

namespace ssvgi::cli {

namespace {

void addConvergenceOptions(CLI::App& command, bench::ConvergenceOptions& convergence) {
  command.add_option("--window", convergence.windowFrames,
                     "Frames per convergence window: converged when the mean indirect irradiance changes by less "
                     "than --tolerance from one window to the next")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  command.add_option("--tolerance", convergence.tolerance, "Relative change that counts as converged")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  command.add_option("--max-frames", convergence.maxFrames, "Stop rendering here, converged or not")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000000u));
}

}  // namespace

CommandRunner addErrorScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto error = std::make_shared<bench::IndirectErrorOptions>();
  CLI::App* command = scenario.add_subcommand(
      "error", "Error vs reference (SPEC §7): relative mean absolute error of the converged GI's indirect irradiance "
               "against the path-traced reference's, over the surface pixels, both box-filtered in K×K blocks");
  addScenarioOptions(*command, *options, "cornell");
  addConvergenceOptions(*command, error->convergence);
  command->add_option("--spp", error->referenceSamples,
                      "Reference samples per pixel, traced as two halves of independent seeds (their difference gives "
                      "the reference's noise floor)")
      ->capture_default_str()
      ->check(CLI::Range(2u, 1u << 20));
  command->add_option("--downsample", error->downsample, "K: both images averaged over K×K blocks first")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1024u));
  command->add_option("--seed", error->seed, "Seed of the reference's first half (the second uses seed + 1)")
      ->capture_default_str();
  return [options, error] {
    return runScenario("error", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                              const bench::ScenarioRendering& rendering) {
      return bench::toJson(bench::measureIndirectError(device, rendering, {resolved.scene, resolved.camera}, *error));
    });
  };
}

CommandRunner addProbesScenario(CLI::App& scenario) {
  auto options = std::make_shared<ScenarioOptions>();
  auto probes = std::make_shared<bench::ProbeIrradianceOptions>();
  CLI::App* command = scenario.add_subcommand(
      "probes", "Probe irradiance vs reference (SPEC §4.5): E(n) for the six axis normals of the converged level-0 "
                "probes the camera sees into, against the path-traced radiance at their positions");
  addScenarioOptions(*command, *options, "cornell");
  addConvergenceOptions(*command, probes->convergence);
  command->add_option("--directions", probes->referenceDirections,
                      "Reference directions per probe, traced as two halves of independent seeds")
      ->capture_default_str()
      ->check(CLI::Range(256u, 1u << 26));
  command->add_option("--seed", probes->seed, "Seed of the reference's first half (the second uses seed + 1)")
      ->capture_default_str();
  return [options, probes] {
    return runScenario("probes", *options, [&](gpu::OwnedDevice& device, const ResolvedScene& resolved,
                                               const bench::ScenarioRendering& rendering) {
      return bench::toJson(
          bench::measureProbeIrradiance(device, rendering, {resolved.scene, resolved.camera}, *probes));
    });
  };
}

}  // namespace ssvgi::cli
