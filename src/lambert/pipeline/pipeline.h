#pragma once
// The whole radiosity computation for a scene, stage by stage (mesh → ray caster → form factors →
// emission → solve), with each stage's figures recorded in one Stats table.
#include <memory>

#include "lambert/core/stats.h"
#include "lambert/formfactor/form_factors.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
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
  DirectLightOptions directLight;  // how the scene's point, spot and directional lights are injected
  std::string cacheDirectory;      // form-factor cache (seed 003); empty: always compute, never save
  bool normalizeRows = false;      // seed 003's row normalisation (see formfactor/table.h)
};

struct RadiositySolution {
  Mesh mesh;
  std::unique_ptr<RayCaster> caster;  // over `mesh`, for shadow rays when drawing direct light
  RadiosityProblem problem;           // holds the form-factor matrix; emitted includes `injected`
  std::vector<Rgb> injected;          // ρ·E_direct of the scene's lights, per patch, W/m²
  std::vector<Rgb> radiosity;         // B_i, W/m²
  SolveReport report;
  Stats stats;

  // B less the lights' directly injected part: the indirect light to interpolate when the
  // lights' direct light is drawn per pixel.
  std::vector<Rgb> indirectRadiosity() const;
  // Outgoing radiance L = B/π at every mesh vertex, as Gouraud shading interpolates it.
  std::vector<Rgb> vertexRadiance() const;
};

RadiositySolution solveScene(const Scene& scene, const PipelineOptions& options);

}  // namespace lambert
