#include "lambert/solve/problem.h"

#include "lambert/core/error.h"

namespace lambert {

RadiosityProblem makeRadiosityProblem(const Mesh& mesh, std::vector<Rgb> emitted, std::vector<Rgb> albedo,
                                      std::shared_ptr<const Transport> transport) {
  LAMBERT_CHECK(emitted.size() == mesh.numPatches() && albedo.size() == mesh.numPatches());
  LAMBERT_CHECK(!transport || transport->size() == mesh.numPatches());
  RadiosityProblem problem;
  problem.transport = std::move(transport);
  problem.emitted = std::move(emitted);
  problem.albedo = std::move(albedo);
  problem.area.resize(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) problem.area[i] = mesh.patches[i].area;
  return problem;
}

}  // namespace lambert
