// `lambert scenes`: the built-in scenes' names, and (--export DIR) each as a scene file to start
// one's own from.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "lambert/scene/builtin.h"
#include "lambert/load/scene_file.h"

namespace lambert::cli {

std::function<int()> addScenesCommand(CLI::App& app) {
  auto directory = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("scenes", "List the built-in scenes (and write them as scene files)");
  cmd->add_option("--export", *directory, "Write every built-in scene as DIR/<name>.json (docs/scene-format.md)");
  return [directory] {
    for (const std::string& name : builtinSceneNames()) {
      if (directory->empty()) {
        std::printf("%s\n", name.c_str());
        continue;
      }
      const std::string path = (std::filesystem::path(*directory) / (name + ".json")).string();
      if (Status written = writeSceneFile(path, *builtinScene(name)); !written) {
        std::fprintf(stderr, "lambert scenes: %s\n", written.error().message.c_str());
        return 1;
      }
      std::printf("wrote %s\n", path.c_str());
    }
    return 0;
  };
}

}  // namespace lambert::cli
