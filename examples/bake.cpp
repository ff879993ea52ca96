// Bakes a glTF scene's light: loads a .gltf or .glb (its meshes, materials and KHR lights),
// solves its radiosity with the hierarchical method and writes the lit scene as a .glb whose
// vertex colours carry the light (io/gltf_export.h), ready for Blender, three.js or an engine.
//
//   bake room.glb room-baked.glb
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "lambert/lambert.h"

namespace {

std::string lowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s INPUT.gltf|INPUT.glb OUTPUT.glb\n", argv[0]);
    return 2;
  }
  const std::string input = argv[1], output = argv[2];
  // The input is read by its extension; anything but glTF is refused here, since this program
  // is about glTF in, glTF out (loadScene itself reads lambert's other formats too).
  if (lowercaseExtension(input) != ".gltf" && lowercaseExtension(input) != ".glb") {
    std::fprintf(stderr, "bake: %s: the input must be a .gltf or .glb file\n", input.c_str());
    return 2;
  }
  if (lowercaseExtension(output) != ".glb") {
    std::fprintf(stderr, "bake: %s: the output is binary glTF and must end in .glb\n", output.c_str());
    return 2;
  }

  lambert::Result<lambert::Scene> scene = lambert::loadScene(input);
  if (!scene) return std::fprintf(stderr, "bake: %s\n", scene.error().message.c_str()), 1;

  // Hierarchical radiosity: element trees under clusters, near-linear in the number of faces,
  // with a final gather at the vertices that the export's vertex colours take.
  lambert::RadiosityOptions options;
  options.meshing = lambert::MeshStrategy::Hierarchical;
  auto engine = lambert::Radiosity::create(std::move(*scene), options);
  if (!engine) return std::fprintf(stderr, "bake: %s: %s\n", input.c_str(), engine.error().message.c_str()), 1;
  if (auto solved = (*engine)->solve(); !solved)
    return std::fprintf(stderr, "bake: %s: %s\n", input.c_str(), solved.error().message.c_str()), 1;

  const lambert::SolutionView& solution = (*engine)->solution();
  if (lambert::Status written = lambert::writeGlb(output, solution); !written)
    return std::fprintf(stderr, "bake: %s\n", written.error().message.c_str()), 1;

  const std::vector<lambert::Rgb> radiance = solution.vertexRadiance();  // L = B/π, W/(m²·sr)
  lambert::Rgb mean;
  for (const lambert::Rgb& l : radiance) mean += l / static_cast<double>(radiance.size());
  std::printf("%s: %zu vertices, mean radiance %.4g %.4g %.4g W/(m2 sr), wrote %s\n", input.c_str(), radiance.size(), mean.r,
              mean.g, mean.b, output.c_str());
  return 0;
}
