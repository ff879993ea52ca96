#include "lambert/pipeline/pipeline.h"

#include "lambert/core/timer.h"
#include "lambert/formfactor/cache.h"
#include "lambert/formfactor/table.h"
#include "lambert/geometry/coverage.h"
#include "lambert/render/vertex_radiosity.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/solve/energy.h"
#include "lambert/solve/problem.h"

namespace lambert {

RadiositySolution solveScene(const Scene& scene, const PipelineOptions& options) {
  RadiositySolution solution;
  Stats& stats = solution.stats;
  stats.add("scene", "scene", scene.name);

  Timer meshTimer;
  double maxEdge = options.maxEdgeLength > 0 ? options.maxEdgeLength : edgeLengthForPatchCount(scene, options.targetPatches);
  solution.mesh = subdivideScene(scene, maxEdge);
  const Mesh& mesh = solution.mesh;
  stats.add("patches", "patches", static_cast<std::int64_t>(mesh.numPatches()));
  stats.add("vertices", "vertices", static_cast<std::int64_t>(mesh.numVertices()));
  stats.add("max_edge_length", "max edge length", maxEdge, "scene units");
  stats.add("mesh_seconds", "mesh time", meshTimer.seconds(), "s");

  Timer bvhTimer;
  solution.caster = makeEmbreeRayCaster(mesh);
  const RayCaster& caster = *solution.caster;
  stats.add("bvh_seconds", "BVH build time", bvhTimer.seconds(), "s");
  measureOpenFractions(solution.mesh, caster);

  FormFactorStats ffStats;
  CachedFormFactors cached = cachedFormFactors(mesh, caster, options.formFactors, options.cacheDirectory, &ffStats);
  auto F = std::make_shared<FormFactorMatrix>(std::move(cached.matrix));
  if (options.normalizeRows) normalizeRows(*F);
  stats.add("formfactor_method", "form-factor method", formFactorMethodName(options.formFactors.method));
  stats.add("formfactor_cache", "form-factor cache",
            options.cacheDirectory.empty() ? std::string("off") : (cached.fromCache ? "loaded " : "saved ") + cached.path);
  if (options.formFactors.method == FormFactorMethod::AreaMonteCarlo)
    stats.add("sample_pairs", "sample pairs per patch pair", static_cast<std::int64_t>(options.formFactors.samplePairs));
  if (options.formFactors.method == FormFactorMethod::Hemicube)
    stats.add("hemicube_resolution", "hemi-cube resolution", static_cast<std::int64_t>(options.formFactors.hemicubeResolution), "px");
  if (options.formFactors.method == FormFactorMethod::HemisphereRays)
    stats.add("hemisphere_rays", "rays per patch", static_cast<std::int64_t>(options.formFactors.hemisphereRays));
  stats.add("pairs_evaluated", "patch pairs evaluated", static_cast<std::int64_t>(ffStats.pairsEvaluated));
  stats.add("pairs_culled", "patch pairs culled", static_cast<std::int64_t>(ffStats.pairsCulled));
  stats.add("visibility_rays", "visibility rays", static_cast<std::int64_t>(ffStats.visibilityRays));
  stats.add("formfactor_seconds", "form-factor time", ffStats.seconds, "s");
  stats.add("rays_per_second", "visibility rays per second",
            ffStats.seconds > 0 ? static_cast<double>(ffStats.visibilityRays) / ffStats.seconds : 0.0, "rays/s");

  solution.problem = makeRadiosityProblem(scene, mesh, F);
  solution.injected.assign(mesh.numPatches(), Rgb{});
  if (!scene.lights.empty()) {
    Timer lightTimer;
    const std::uint64_t raysBefore = caster.raysCast();
    for (const Light& light : scene.lights) {
      std::vector<Rgb> e = patchIrradiance(mesh, caster, light, scene.metresPerUnit, options.directLight);
      std::vector<Rgb> injected = injectedRadiosity(mesh, solution.problem.albedo, e);
      for (std::size_t i = 0; i < mesh.numPatches(); ++i) solution.injected[i] += injected[i];
    }
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) solution.problem.emitted[i] += solution.injected[i];
    stats.add("lights", "lights", static_cast<std::int64_t>(scene.lights.size()));
    stats.add("shadow_rays", "direct-light shadow rays", static_cast<std::int64_t>(caster.raysCast() - raysBefore));
    stats.add("inject_seconds", "direct-light injection time", lightTimer.seconds(), "s");
  }
  auto solver = makeSolver(options.solver, options.solve);
  solution.report = solver->solve(solution.problem, solution.radiosity);
  stats.add("solver", "solver", solution.report.solver);
  stats.add("iterations", "iterations", static_cast<std::int64_t>(solution.report.iterations));
  stats.add("residual", "relative residual", solution.report.residual);
  stats.add("converged", "converged", std::string(solution.report.converged ? "yes" : "no"));
  stats.add("solve_seconds", "solve time", solution.report.seconds, "s");

  EnergyBalance balance = energyBalance(solution.problem, solution.radiosity, scene.metresPerUnit);
  // With lights, E includes their injected first reflection ρ·E_direct, so "emitted" counts it.
  stats.add("emitted_watts", scene.lights.empty() ? "emitted power" : "emitted + injected power", balance.emittedWatts, "W");
  stats.add("absorbed_watts", "absorbed power", balance.absorbedWatts, "W");
  stats.add("escaped_watts", "escaped power (openings)", balance.escapedWatts, "W");
  return solution;
}

std::vector<Rgb> RadiositySolution::vertexRadiance() const {
  std::vector<Rgb> radiance = vertexRadiosity(mesh, radiosity);
  for (Rgb& l : radiance) l = l / kPi;
  return radiance;
}

std::vector<Rgb> RadiositySolution::indirectRadiosity() const {
  std::vector<Rgb> indirect = radiosity;
  for (std::size_t i = 0; i < indirect.size(); ++i) indirect[i] -= injected[i];
  return indirect;
}

}  // namespace lambert
