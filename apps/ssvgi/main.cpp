#include "commands.h"

#include <cstdio>
#include <exception>
#include <map>

int main(int argc, char** argv) {
  CLI::App app{"ssvgi: dynamic diffuse global illumination from screen-space voxels (Vulkan).\n"
               "Runs on any Vulkan 1.3 device; on a machine without a GPU, on Mesa's lavapipe."};
  app.require_subcommand(1);
  std::map<CLI::App*, ssvgi::cli::CommandRunner> runners;
  auto add = [&](auto addCommand) {
    const auto runner = addCommand(app);
    runners[app.get_subcommands({}).back()] = runner;
  };
  add(ssvgi::cli::addRenderCommand);
  add(ssvgi::cli::addViewCommand);
  add(ssvgi::cli::addReferenceCommand);
  add(ssvgi::cli::addCompareCommand);
  add(ssvgi::cli::addBenchCommand);
  add(ssvgi::cli::addScenarioCommand);
  add(ssvgi::cli::addInfoCommand);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& help) {  // --help
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    // One line naming the problem, like every other error of the tool.
    std::fprintf(stderr, "ssvgi: %s (see ssvgi --help)\n", error.what());
    return 2;
  }
  try {
    for (auto& [command, runner] : runners)
      if (command->parsed()) return runner();
  } catch (const std::exception& error) {
    std::fprintf(stderr, "ssvgi: %s\n", error.what());
    return 1;
  }
  return 1;
}
