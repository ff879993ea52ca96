#pragma once
// The whole radiosity computation for a scene, stage by stage (mesh → ray caster → form factors →
// emission → solve), with each stage's figures recorded in one Stats table.
#include <memory>

#include "lambert/core/stats.h"
#include "lambert/formfactor/form_factors.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"
#include "lambert/solve/solver.h"

namespace lambert {

struct PipelineOptions {
  std::size_t targetPatches = 784;  // used when maxEdgeLength is 0
  double maxEdgeLength = 0;         // scene units; 0 picks it from targetPatches
  FormFactorOptions formFactors;
  SolverKind solver = SolverKind::GaussSeidel;
  SolveOptions solve;
};

struct RadiositySolution {
  Mesh mesh;
  RadiosityProblem problem;    // holds the form-factor matrix
  std::vector<Rgb> radiosity;  // B_i, W/m²
  SolveReport report;
  Stats stats;
};

RadiositySolution solveScene(const Scene& scene, const PipelineOptions& options);

}  // namespace lambert
