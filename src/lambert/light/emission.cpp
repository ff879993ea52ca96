#include "lambert/light/emission.h"

namespace lambert {

std::vector<Rgb> emittedRadiosity(const Scene& scene, const Mesh& mesh) {
  std::vector<Rgb> emitted(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i)
    emitted[i] = scene.surfaces[mesh.patches[i].surface].emittedRadiance * kPi;
  return emitted;
}

std::vector<Rgb> patchAlbedo(const Scene& scene, const Mesh& mesh) {
  std::vector<Rgb> albedo(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i)
    albedo[i] = scene.materials[scene.surfaces[mesh.patches[i].surface].material].albedo;
  return albedo;
}

}  // namespace lambert
