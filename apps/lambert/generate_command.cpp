// `lambert generate building`: procedural office buildings (scene/building.h) for scaling runs,
// written as OBJ + MTL with a scene file beside them that places the OBJ and sets the camera.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "lambert/core/atomic_file.h"
#include "lambert/core/text.h"
#include "lambert/scene/building.h"
#include "lambert/load/obj.h"

namespace lambert::cli {

namespace {

struct GenerateOptions {
  BuildingOptions building;
  std::string output;
};

int runGenerate(const GenerateOptions& o) {
  if (lowercaseExtension(o.output) != ".json") {
    std::fprintf(stderr, "lambert generate: %s: give a .json path (the OBJ and MTL are written beside it)\n", o.output.c_str());
    return 2;
  }
  Result<Scene> scene = generateBuilding(o.building);
  if (!scene) {
    std::fprintf(stderr, "lambert generate: %s\n", scene.error().message.c_str());
    return 2;
  }
  const std::filesystem::path json(o.output);
  const std::filesystem::path obj = std::filesystem::path(o.output).replace_extension(".obj");
  if (Status written = writeObj(obj.string(), *scene); !written) {
    std::fprintf(stderr, "lambert generate: %s\n", written.error().message.c_str());
    return 1;
  }
  const Camera& c = scene->camera;
  char camera[400];
  std::snprintf(camera, sizeof camera,
                "  \"camera\": {\"eye\": [%.17g, %.17g, %.17g], \"target\": [%.17g, %.17g, %.17g], \"verticalFovDegrees\": %.17g}\n",
                c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.verticalFovDegrees);
  const std::string text = "{\n  \"version\": 1,\n  \"name\": \"" + scene->name + "\",\n  \"unit\": \"m\",\n  \"meshes\": [{\"path\": \"" +
                           obj.filename().string() + "\"}],\n" + camera + "}\n";
  if (Status written = writeFileAtomically(json.string(), std::span<const std::uint8_t>(
                                                               reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
      !written) {
    std::fprintf(stderr, "lambert generate: %s\n", written.error().message.c_str());
    return 1;
  }
  std::size_t faces = 0;
  for (const Surface& s : scene->surfaces) faces += surfaceFaces(s).size();
  std::printf("wrote %s (%zu rooms, %zu faces, %zu rectangles) with %s\n", json.string().c_str(), static_cast<std::size_t>(o.building.rooms),
              faces, scene->surfaces.size(), obj.filename().string().c_str());
  return 0;
}

}  // namespace

std::function<int()> addGenerateCommand(CLI::App& app) {
  auto o = std::make_shared<GenerateOptions>();
  CLI::App* generate = app.add_subcommand("generate", "Write a procedural scene (for scaling runs)");
  generate->require_subcommand(1);
  CLI::App* building = generate->add_subcommand(
      "building", "Storeys of offices on both sides of a corridor: doors, windows, ceiling lights, furniture blocks (metres)");
  building->add_option("--rooms", o->building.rooms, "Offices in all (16 per storey)")->check(CLI::Range(1, 100000))->capture_default_str();
  building->add_option("--face-size", o->building.faceSize, "Split every rectangle into faces no longer than this (m; 0: whole)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  building->add_option("--seed", o->building.seed, "Furniture placement")->capture_default_str();
  building->add_option("-o,--output", o->output, "The scene file to write (.json; NAME.obj and NAME.mtl go beside it)")->required();
  return [o] { return runGenerate(*o); };
}

}  // namespace lambert::cli
