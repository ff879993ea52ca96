#include "lambert/solve/problem.h"

#include "lambert/light/emission.h"

namespace lambert {

RadiosityProblem makeRadiosityProblem(const Scene& scene, const Mesh& mesh,
                                      std::shared_ptr<const FormFactorMatrix> formFactors) {
  RadiosityProblem problem;
  problem.formFactors = std::move(formFactors);
  problem.emitted = emittedRadiosity(scene, mesh);
  problem.albedo = patchAlbedo(scene, mesh);
  problem.area.resize(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) problem.area[i] = mesh.patches[i].area;
  return problem;
}

}  // namespace lambert
