#pragma once
// The ssvgi command-line tool: one file per command, each adding itself to the CLI11 app and running when chosen.
#include <CLI/CLI.hpp>

#include <functional>

namespace ssvgi::cli {

// Adds the command's options to `app` and returns what runs it; the runner returns the process exit code.
using CommandRunner = std::function<int()>;
CommandRunner addRenderCommand(CLI::App& app);
CommandRunner addReferenceCommand(CLI::App& app);
CommandRunner addCompareCommand(CLI::App& app);
CommandRunner addInfoCommand(CLI::App& app);
CommandRunner addViewCommand(CLI::App& app);  // view_command.cpp: the window, view_*.cpp
CommandRunner addBenchCommand(CLI::App& app);
CommandRunner addScenarioCommand(CLI::App& app);  // scenario_command.h: its subcommands

}  // namespace ssvgi::cli
