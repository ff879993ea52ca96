#include <cstdio>

#include "commands.h"
#include "lambert/scene/builtin.h"

namespace lambert::cli {

std::function<int()> addScenesCommand(CLI::App& app) {
  app.add_subcommand("scenes", "List the built-in scenes");
  return [] {
    for (const std::string& name : builtinSceneNames()) std::printf("%s\n", name.c_str());
    return 0;
  };
}

}  // namespace lambert::cli
