// lambert: radiosity for diffuse scenes. A thin front end: each subcommand lives in its own file.
#include <cstdio>
#include <functional>
#include <vector>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"lambert — physically based radiosity for diffuse scenes"};
  app.require_subcommand(1);
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands;
  auto render = lambert::cli::addRenderCommand(app);
  commands.emplace_back(app.get_subcommand("render"), render);
  auto solve = lambert::cli::addSolveCommand(app);
  commands.emplace_back(app.get_subcommand("solve"), solve);
  auto animate = lambert::cli::addAnimateCommand(app);
  commands.emplace_back(app.get_subcommand("animate"), animate);
  auto scenes = lambert::cli::addScenesCommand(app);
  commands.emplace_back(app.get_subcommand("scenes"), scenes);
  CLI11_PARSE(app, argc, argv);
  for (auto& [command, run] : commands)
    if (command->parsed()) return run();
  return 2;
}
