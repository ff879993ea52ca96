#pragma once
// One function per subcommand; each registers its options on the CLI11 app and runs when chosen.
#include <functional>

#include <CLI/CLI.hpp>

#include "lambert/reference/reference.h"

namespace lambert::cli {

// Registers `lambert render`; the returned callback runs it and gives the exit code.
std::function<int()> addRenderCommand(CLI::App& app);
std::function<int()> addAnimateCommand(CLI::App& app);
std::function<int()> addSolveCommand(CLI::App& app);
std::function<int()> addReferenceCommand(CLI::App& app);
std::function<int()> addCompareCommand(CLI::App& app);
std::function<int()> addScenesCommand(CLI::App& app);
std::function<int()> addInfoCommand(CLI::App& app);
std::function<int()> addGenerateCommand(CLI::App& app);
std::function<int()> addViewCommand(CLI::App& app);
std::function<int()> addReportCommand(CLI::App& app);
std::function<int()> addDaylightCommand(CLI::App& app);

// Path-tracer options shared by `reference` and `compare`.
void addReferenceOptions(CLI::App& command, ReferenceOptions& options);

}  // namespace lambert::cli
