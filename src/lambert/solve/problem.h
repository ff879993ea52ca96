#pragma once
#include "lambert/scene/scene.h"
#include "lambert/mesh/mesh.h"
#include "lambert/solve/solver.h"

namespace lambert {

// The radiosity system for a meshed scene: emission and albedo from its surfaces and materials.
RadiosityProblem makeRadiosityProblem(const Scene& scene, const Mesh& mesh,
                                      std::shared_ptr<const FormFactorMatrix> formFactors);

}  // namespace lambert
