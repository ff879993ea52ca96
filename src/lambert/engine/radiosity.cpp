#include "lambert/engine/radiosity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/core/cache_file.h"
#include "lambert/flat/adaptive_method.h"
#include "lambert/hierarchical/method.h"
#include "lambert/method/point_gather.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/flat/uniform_method.h"
#include "lambert/light/emission.h"
#include "lambert/light/injection.h"
#include "lambert/light/lights.h"
#include "lambert/core/photometric.h"
#include "lambert/light/many_lights.h"
#include "lambert/solve/energy.h"
#include "lambert/solve/problem.h"
#include "lambert/solve/progressive_shooter.h"
#include "lambert/solve/solver.h"

namespace lambert {

Result<std::unique_ptr<Method>> makeMethod(const Scene& scene, const RadiosityOptions& options) {
  switch (options.meshing) {
    case MeshStrategy::Uniform: {
      Result<std::unique_ptr<UniformMethod>> uniform = UniformMethod::create(scene, options);
      if (!uniform) return uniform.error();
      return std::unique_ptr<Method>(std::move(*uniform));
    }
    case MeshStrategy::Adaptive: {
      Result<std::unique_ptr<AdaptiveMethod>> adaptive = AdaptiveMethod::create(scene, options);
      if (!adaptive) return adaptive.error();
      return std::unique_ptr<Method>(std::move(*adaptive));
    }
    case MeshStrategy::Hierarchical: {
      if (options.solver == SolverKind::Direct || options.solver == SolverKind::Shooting)
        return Error{"the hierarchical method gathers over its links: use the gs or jacobi solver, not '" +
                     solverName(options.solver) + "'"};
      if (options.normalizeRows) return Error{"row normalisation is for the flat methods' form-factor matrix"};
      const LinkOptions& links = options.hierarchical.links;
      if (!(links.linkError > 0) || !(links.minElementArea >= 0) || links.visibilityRays < 1 || links.visibilityRays > 255 ||
          options.hierarchical.refinePasses < 1)
        return Error{"the hierarchical method needs a positive link error, a minimum element area of at least 0, "
                     "1 to 255 visibility rays per link and at least one refinement pass"};
      return std::unique_ptr<Method>(std::make_unique<HierarchicalMethod>(scene, options));
    }
  }
  return Error{"unknown mesh strategy"};
}

Result<PointGather> Method::pointGather(const ElementSolution&, std::span<const SurfacePoint>, PointGatherRequest) const {
  return Error{"light at points of the faces (lightmaps) is gathered over the hierarchical method's links: solve with "
               "--method hierarchical (the default) instead of the flat method"};
}

Result<PointGather> Method::vertexGather(const ElementSolution&, std::span<const std::uint32_t>, PointGatherRequest) const {
  return Error{"light at the vertices as weights is gathered over the hierarchical method's links: solve with --method hierarchical (the default)"};
}

Result<std::vector<Rgb>> Method::nodeMeanRadiosity(const ElementSolution&) const {
  return Error{"node mean radiosities are the hierarchical method's: solve with --method hierarchical (the default)"};
}

std::vector<Rgb> indirectRadiosity(const ElementSolution& solution) {
  std::vector<Rgb> indirect = solution.radiosity;
  for (std::size_t i = 0; i < indirect.size(); ++i)
    indirect[i] -= solution.skyInjected.empty() ? solution.injected[i] : solution.injected[i] - solution.skyInjected[i];
  return indirect;
}

std::vector<std::vector<Rgb>> Method::vertexSolution(const ElementSolution& solution, std::span<const VertexQuantity> quantities,
                                                      std::span<const std::uint8_t> /*neededVertices*/) const {
  // Interpolating every vertex costs as little as interpolating some.
  std::vector<std::vector<Rgb>> out;
  for (VertexQuantity quantity : quantities) {
    std::vector<Rgb> perElement = quantity == VertexQuantity::IndirectRadiosity ? indirectRadiosity(solution) : solution.radiosity;
    for (std::size_t i = 0; i < perElement.size(); ++i) {
      if (quantity != VertexQuantity::Irradiance) continue;
      for (int c = 0; c < 3; ++c) {
        const double rho = solution.albedo[i][c];
        perElement[i][c] = rho > 0 ? std::fmax(0.0, solution.radiosity[i][c] - solution.emitted[i][c]) / rho : 0;
      }
    }
    out.push_back(vertexValues(perElement));
  }
  return out;
}

// The engine's state, behind Radiosity's one pointer: the scene and options it was made with, the
// lights, the method, the system it solves and B, and the totals stats() reports. Radiosity's
// calls, its view and the internal readers (engine/solution_internals.h) read it here.
struct Radiosity::Impl {
  Impl(const Radiosity& engine, Scene scene, RadiosityOptions options);
  void rebuildProblem();
  Result<SolveReport> solve(const SolveBudget& budget);
  Status solvePass(const SolveBudget& budget, SolveReport& report);
  Stats stats() const;
  // The solution per element, as the method reads it.
  ElementSolution elementSolution() const {
    return {radiosity_, injected_, injection_->skyTotal(), surfaceEmitted_, problem_->albedo, lights_, scene_.metresPerUnit};
  }

  Scene scene_;
  RadiosityOptions options_;
  std::vector<Light> lights_;
  std::unique_ptr<Method> meshing_;
  std::unique_ptr<DirectLightInjection> injection_;
  std::unique_ptr<RadiosityProblem> problem_;  // E includes the injected direct light
  std::vector<Rgb> surfaceEmitted_;    // E of emissive surfaces alone, W/m²
  std::vector<Rgb> injected_;          // the lights' ρ·E_direct, W/m²
  std::vector<Rgb> vertexMeshAlbedo_;  // ρ per patch of the meshing's vertex mesh
  std::vector<Rgb> radiosity_;         // B, W/m², one per element
  bool solved_ = false;                // radiosity_ holds a solution (or a refinement's warm start)
  double largestEmittedPower_ = 0;     // Σ E A of any solve so far (findSolutionFault's scale)
  std::unique_ptr<ProgressiveShooter> shooter_;  // shoot: kept between solves, warm
  SolutionView view_;
  // Totals over every solve(), for stats().
  int solves_ = 0;
  // A distributed solve's residual and energy balance, made by every rank after each solve().
  struct DistributedFigures {
    double residual, emittedWatts, absorbedWatts, escapedWatts;
  };
  std::optional<DistributedFigures> distributedFigures_;
  SolveReport last_;
  double injectSeconds_ = 0, solveSeconds_ = 0, adaptSeconds_ = 0, formFactorSeconds_ = 0;
  std::uint64_t shadowRays_ = 0;
  int refined_ = 0, coarsened_ = 0;
};

// What a SolutionView reads: the engine's state behind it.
struct SolutionInternals {
  static const Radiosity::Impl& of(const SolutionView& view) { return *view.engine_->impl_; }
};

// Rank 0's lead over the other ranks' gathers (Method::leadRanks), let go of with its handle.
struct DistributedOutputs::Lead {
  explicit Lead(Method& leading) : method(leading) {}
  ~Lead() { method.leadRanks(false); }
  Method& method;
};

Result<std::unique_ptr<Radiosity>> Radiosity::create(Scene scene, RadiosityOptions options) {
  if (options.tolerance <= 0 || options.maxIterations < 1)
    return Error{"the solver needs a positive tolerance and at least one iteration"};
  if (options.communicator) {
    // Spread over ranks, a sweep reads the others' leaves as of the previous sweep: Jacobi. The
    // link cache is off: ranks that found different files (one written meanwhile) would solve
    // different hierarchies.
    if (options.meshing != MeshStrategy::Hierarchical)
      return Error{"a distributed solve spreads the hierarchical method's links over the ranks: use --method hierarchical (the default)"};
    options.solver = SolverKind::Jacobi;
    options.cacheDirectory.clear();
  }
  std::unique_ptr<Radiosity> engine(new Radiosity(std::move(scene), std::move(options)));
  Impl& e = *engine->impl_;
  // The strategy keeps a reference to the engine's scene, which never moves.
  Result<std::unique_ptr<Method>> meshing = makeMethod(e.scene_, e.options_);
  if (!meshing) return meshing.error();
  e.meshing_ = std::move(*meshing);
  e.rebuildProblem();
  return engine;
}

Result<Mesh> solutionVertexMesh(const Scene& scene, RadiosityOptions options) {
  if (options.meshing == MeshStrategy::Uniform) return uniformMesh(scene, options.uniform);
  Result<std::unique_ptr<Radiosity>> engine = Radiosity::create(scene, std::move(options));
  if (!engine) return engine.error();
  if (Result<SolveReport> solved = (*engine)->solve(); !solved) return solved.error();
  return (*engine)->solution().vertexMesh();
}

Radiosity::Radiosity(Scene scene, RadiosityOptions options)
    : impl_(std::make_unique<Impl>(*this, std::move(scene), std::move(options))) {}

Radiosity::Impl::Impl(const Radiosity& engine, Scene scene, RadiosityOptions options)
    : scene_(std::move(scene)),
      options_(std::move(options)),
      lights_(scene_.lights),
      injection_(std::make_unique<DirectLightInjection>(options_.directLight)),
      view_(engine) {}

Radiosity::~Radiosity() = default;

void Radiosity::setLights(std::vector<Light> lights) { impl_->lights_ = std::move(lights); }
const std::vector<Light>& Radiosity::lights() const { return impl_->lights_; }
Result<SolveReport> Radiosity::solve(const SolveBudget& budget) { return impl_->solve(budget); }
const SolutionView& Radiosity::solution() const { return impl_->view_; }
Stats Radiosity::stats() const { return impl_->stats(); }
const Scene& Radiosity::scene() const { return impl_->scene_; }
const RadiosityOptions& Radiosity::options() const { return impl_->options_; }
Status Radiosity::saveCache() { return impl_->meshing_->saveCache(); }
DistributedOutputs::DistributedOutputs(std::unique_ptr<Lead> lead) : lead_(std::move(lead)) {}
DistributedOutputs::DistributedOutputs(DistributedOutputs&& other) noexcept = default;
DistributedOutputs::~DistributedOutputs() = default;
DistributedOutputs Radiosity::leadDistributedOutputs() {
  const RadiosityOptions& options = impl_->options_;
  if (!options.communicator || options.communicator->size() < 2) return DistributedOutputs(nullptr);
  LAMBERT_CHECK(options.communicator->rank() == 0);
  impl_->meshing_->leadRanks(true);
  return DistributedOutputs(std::make_unique<DistributedOutputs::Lead>(*impl_->meshing_));
}
void Radiosity::serveDistributedOutputs() {
  const RadiosityOptions& options = impl_->options_;
  if (!options.communicator || options.communicator->size() < 2) return;
  impl_->meshing_->serveRanks(impl_->elementSolution());
}

// The elements changed (or were just made): the system, the lights' injection and the shooter's
// state all belong to the old ones.
void Radiosity::Impl::rebuildProblem() {
  const Mesh& elements = meshing_->elements();
  surfaceEmitted_ = emittedRadiosity(scene_, elements);
  problem_ = std::make_unique<RadiosityProblem>(makeRadiosityProblem(elements, surfaceEmitted_, patchAlbedo(scene_, elements), meshing_->transport()));
  injection_->reset();
  shooter_.reset();
  injected_.assign(elements.numPatches(), Rgb{});
  if (!solved_) radiosity_.assign(elements.numPatches(), Rgb{});
  vertexMeshAlbedo_ = patchAlbedo(scene_, meshing_->vertexMesh());
}

Status checkSolveBudget(SolverKind kind, const SolveBudget& budget) {
  if (budget.maxShots < 0 || budget.maxSweeps < 0 || !(budget.maxMilliseconds >= 0))
    return Error{"a solve budget cannot be negative"};
  const std::string solver = solverName(kind);
  switch (kind) {
    case SolverKind::Direct:
      if (!budget.unlimited())
        return Error{"the direct solver solves exactly, so it takes no budget of shots, sweeps or time: use gs, jacobi or shoot"};
      break;
    case SolverKind::GaussSeidel:
    case SolverKind::Jacobi:
      if (budget.maxShots > 0) return Error{"a budget of shots is for the shoot solver; " + solver + " takes sweeps or milliseconds"};
      break;
    case SolverKind::Shooting:
      if (budget.maxSweeps > 0) return Error{"a budget of sweeps is for gs and jacobi; shoot takes shots or milliseconds"};
      break;
  }
  return Ok{};
}

Result<SolveReport> Radiosity::Impl::solve(const SolveBudget& budget) {
  if (Status ok = checkSolveBudget(options_.solver, budget); !ok) return ok.error();
  // Each rank's clock would stop it at a sweep of its own, and the others would wait for it.
  if (options_.communicator && budget.maxMilliseconds > 0)
    return Error{"a distributed solve stops when it converges or after a number of sweeps, not after a time: "
                 "every rank must sweep alike"};
  SolveReport report;
  // Adaptive meshing refines every solve; the hierarchy refines until its passes are done (in
  // the first solve, or the first with any light: HierarchicalMethod::refine), then later solves
  // (lights moved) re-solve over the same links, refine() answering false.
  const int passes = options_.meshing == MeshStrategy::Adaptive       ? options_.adaptive.passesPerSolve
                     : options_.meshing == MeshStrategy::Hierarchical ? options_.hierarchical.refinePasses
                                                                      : 1;
  meshing_->startSolve(budget);
  for (int pass = 0; pass < passes; ++pass) {
    Result<bool> refined = meshing_->refine(lights_, radiosity_, report);
    if (!refined) return refined.error();
    // A hierarchy that loaded every pass's refinement from its link cache in the first pass
    // (hierarchical/link_cache.h) refines no more: its one solve is the computing run's last one.
    if (!*refined && pass > 0 && options_.meshing == MeshStrategy::Hierarchical) break;
    if (*refined) {
      solved_ = true;  // radiosity_ now holds the refinement's warm start
      rebuildProblem();
    }
    if (Status solved = solvePass(budget, report); !solved) return solved.error();
  }
  report.elements = meshing_->elements().numPatches();
  ++solves_;
  // A distributed solve's residual and energy balance each need a gather over every rank's links:
  // made here, where every rank is, for stats() on rank 0 alone.
  if (options_.communicator) {
    const EnergyBalance balance = energyBalance(*problem_, radiosity_, scene_.metresPerUnit);
    distributedFigures_ = DistributedFigures{relativeResidual(*problem_, radiosity_), balance.emittedWatts, balance.absorbedWatts, balance.escapedWatts};
  }
  last_ = report;
  injectSeconds_ += report.injectSeconds;
  solveSeconds_ += report.solveSeconds;
  adaptSeconds_ += report.adaptSeconds;
  formFactorSeconds_ += report.formFactorSeconds;
  refined_ += report.refined;
  coarsened_ += report.coarsened;
  return report;
}

Status Radiosity::Impl::solvePass(const SolveBudget& budget, SolveReport& report) {
  const Mesh& elements = meshing_->elements();
  const RayCaster& caster = meshing_->caster();

  Timer injectTimer;
  const std::uint64_t raysBefore = caster.raysCast();
  const DirectLightInjection::Update injection =
      injection_->update(elements, caster, problem_->albedo, lights_, scene_.metresPerUnit);
  report.lightsInjected += injection.lightsTraced;
  if (injection.changed) {
    // A moved spot changes the patches its cone reached or reaches: only those are refreshed.
    const std::vector<Rgb>& total = injection_->total();
    auto refresh = [&](std::size_t i) {
      injected_[i] = total[i];
      problem_->emitted[i] = surfaceEmitted_[i] + total[i];
    };
    if (injection.allPatches)
      for (std::size_t i = 0; i < elements.numPatches(); ++i) refresh(i);
    else
      for (std::uint32_t i : injection.changedPatches) refresh(i);
    if (shooter_) shooter_->setEmitted(problem_->emitted);
  }
  shadowRays_ += caster.raysCast() - raysBefore;
  report.injectSeconds += injectTimer.seconds();

  Timer solveTimer;
  const std::size_t n = problem_->size();
  if (options_.solver == SolverKind::Shooting) {
    // One shooter for the engine's life (until the elements change): a moved light's difference
    // is shot from where the last solve left off (Chen 1990), not from scratch.
    if (!shooter_) {
      shooter_ = std::make_unique<ProgressiveShooter>(*problem_);
      if (solved_) shooter_->warmStart(radiosity_);
    }
    const long long limit = static_cast<long long>(options_.maxIterations) * static_cast<long long>(n);
    const long long maxShots = budget.maxShots > 0 ? std::min(budget.maxShots, limit) : limit;
    ProgressiveShooter::Outcome outcome = shooter_->shoot(maxShots, options_.tolerance, budget.maxMilliseconds / 1e3);
    report.iterations += outcome.shots;
    report.converged = outcome.converged;
    report.unshotFraction = shooter_->unshotFraction();
    radiosity_ = shooter_->radiosity();
  } else {
    SolverOptions solve;
    solve.tolerance = options_.tolerance;
    solve.maxIterations = budget.maxSweeps > 0 ? std::min(budget.maxSweeps, options_.maxIterations) : options_.maxIterations;
    solve.maxSeconds = budget.maxMilliseconds / 1e3;
    solve.measureResidual = false;  // the engine reports its residual in stats(), when asked
    if (!solved_) radiosity_.clear();  // start from B = E
    SolverReport solved = makeSolver(options_.solver, solve)->solve(*problem_, radiosity_);
    report.iterations += solved.iterations;
    report.converged = solved.converged;
  }
  solved_ = true;
  report.solveSeconds += solveTimer.seconds();
  // A diverged or non-finite solution is an error naming where, never an image of garbage.
  largestEmittedPower_ = std::fmax(largestEmittedPower_, emittedPower(*problem_));
  if (std::optional<SolutionFault> fault = findSolutionFault(*problem_, radiosity_, largestEmittedPower_)) {
    const Patch& element = meshing_->elements().patches.at(fault->element);
    return Error{"the " + solverName(options_.solver) + " solve failed: the radiosity of element " + std::to_string(fault->element) +
                 " (surface '" + scene_.surfaces.at(element.surface).name + "') " + fault->what};
  }
  return Ok{};
}

Stats Radiosity::Impl::stats() const {
  Stats stats;
  stats.add("scene", "scene", scene_.name);
  meshing_->addStats(stats);
  if (options_.meshing == MeshStrategy::Adaptive) {
    stats.add("refined", "cells split", static_cast<std::int64_t>(refined_));
    stats.add("coarsened", "cells merged", static_cast<std::int64_t>(coarsened_));
    stats.add("adapt_seconds", "refinement time", adaptSeconds_, "s");
    stats.add("formfactor_seconds", "form-factor time", formFactorSeconds_, "s");
  }
  if (!lights_.empty()) {
    stats.add("lights", "lights", static_cast<std::int64_t>(lights_.size()));
    stats.add("shadow_rays", "direct-light shadow rays", static_cast<std::int64_t>(shadowRays_));
    stats.add("inject_seconds", "direct-light injection time", injectSeconds_, "s");
    stats.add("shadow_tolerance", "shadow tolerance τ (Ward; 0: every light a ray)", options_.directLight.shadowTolerance);
    if (const DirectLightingCounts& c = injection_->counts(); c.points > 0) {
      const double points = static_cast<double>(c.points);
      stats.add("lights_reaching_per_point", "lights reaching a point (mean, many-light injection)", static_cast<double>(c.lightsReaching) / points);
      stats.add("shadow_rays_per_point", "shadow rays per point (mean, many-light injection)", static_cast<double>(c.shadowRays) / points);
    }
  }
  stats.add("solver", "solver", solverName(options_.solver));
  stats.add("solves", "solves", static_cast<std::int64_t>(solves_));
  // Every pass of the last solve(): the hierarchy's refine-then-solve passes, the adaptive mesh's.
  stats.add("iterations", options_.solver == SolverKind::Shooting ? "shots (last solve, every pass)" : "iterations (last solve, every pass)",
            static_cast<std::int64_t>(last_.iterations));
  stats.add("residual", "relative residual",
            distributedFigures_ ? distributedFigures_->residual : solves_ > 0 ? relativeResidual(*problem_, radiosity_) : 1.0);
  stats.add("converged", "converged", std::string(solves_ > 0 && last_.converged ? "yes" : "no"));
  stats.add("solve_seconds", "solve time", solveSeconds_, "s");

  const EnergyBalance balance = distributedFigures_ ? EnergyBalance{distributedFigures_->emittedWatts, distributedFigures_->absorbedWatts,
                                                                    distributedFigures_->escapedWatts}
                                                  : energyBalance(*problem_, radiosity_, scene_.metresPerUnit);
  // The system's E holds the surfaces' emission and the lights' injected first reflection
  // ρ·E_direct: reported apart, beside what the lights themselves send out. Watts of luminance
  // (lm/683, solve/energy.h).
  double injectedWatts = 0;
  const double squareMetres = scene_.metresPerUnit * scene_.metresPerUnit;
  for (std::size_t i = 0; i < injected_.size(); ++i) injectedWatts += problem_->area[i] * squareMetres * injected_[i].luminance();
  stats.add("emitted_watts", "surfaces' emitted power", balance.emittedWatts - injectedWatts, "W");
  if (!lights_.empty()) {
    double lightLumensTotal = 0;
    for (const Light& light : lights_) lightLumensTotal += lightLumens(light);
    stats.add("light_watts", "lights' power (lm/683; suns and skies not counted)", lightLumensTotal / kLumensPerWatt, "W");
    stats.add("injected_watts", "lights' first reflection (ρ·E_direct) injected", injectedWatts, "W");
  }
  stats.add("absorbed_watts", lights_.empty() ? "absorbed power" : "absorbed power (after the first reflection)", balance.absorbedWatts, "W");
  stats.add("escaped_watts", "escaped power (openings)", balance.escapedWatts, "W");
  // XXH64 of every element's B to the bit: two runs (other thread counts, machines, versions)
  // solved alike exactly when these agree.
  cachefile::KeyHasher hash;
  for (const Rgb& b : radiosity_) hash.f64(b.r), hash.f64(b.g), hash.f64(b.b);
  stats.add("solution_hash", "solution hash (B, XXH64)", cachefile::hex(hash.digest()));
  return stats;
}

// The view reads the engine's current state.

const Scene& SolutionView::scene() const { return SolutionInternals::of(*this).scene_; }
const std::vector<Light>& SolutionView::lights() const { return SolutionInternals::of(*this).lights_; }
const Mesh& SolutionView::mesh() const { return SolutionInternals::of(*this).meshing_->elements(); }
const std::vector<Rgb>& SolutionView::radiosity() const { return SolutionInternals::of(*this).radiosity_; }
const std::vector<Rgb>& SolutionView::injected() const { return SolutionInternals::of(*this).injected_; }
const std::vector<Rgb>& SolutionView::emitted() const { return SolutionInternals::of(*this).surfaceEmitted_; }
const std::vector<Rgb>& SolutionView::albedo() const { return SolutionInternals::of(*this).problem_->albedo; }
const RayCaster& SolutionView::caster() const { return SolutionInternals::of(*this).meshing_->caster(); }
const Mesh& SolutionView::vertexMesh() const { return SolutionInternals::of(*this).meshing_->vertexMesh(); }
const std::vector<Rgb>& SolutionView::vertexMeshAlbedo() const { return SolutionInternals::of(*this).vertexMeshAlbedo_; }

std::vector<Rgb> SolutionView::indirectRadiosity() const { return lambert::indirectRadiosity(SolutionInternals::of(*this).elementSolution()); }

Rgb SolutionView::ambientRadiosity() const {
  const auto& e = SolutionInternals::of(*this);
  const ProgressiveShooter* shooter = e.shooter_.get();
  return shooter ? lambert::ambientRadiosity(*e.problem_, shooter->unshot()) : Rgb{};
}

std::vector<Rgb> SolutionView::vertexValues(const std::vector<Rgb>& perElement) const {
  return SolutionInternals::of(*this).meshing_->vertexValues(perElement);
}

std::vector<std::vector<Rgb>> SolutionView::vertexValues(std::span<const VertexQuantity> quantities,
                                                         std::span<const std::uint8_t> neededVertices) const {
  const auto& e = SolutionInternals::of(*this);
  LAMBERT_CHECK(neededVertices.empty() || neededVertices.size() == vertexMesh().numVertices());
  return e.meshing_->vertexSolution(e.elementSolution(), quantities, neededVertices);
}

std::vector<Rgb> SolutionView::vertexValues(VertexQuantity quantity, std::span<const std::uint8_t> neededVertices) const {
  return std::move(vertexValues(std::span<const VertexQuantity>(&quantity, 1), neededVertices).front());
}

Result<std::vector<Rgb>> SolutionView::pointIrradiance(std::span<const SurfacePoint> points) const {
  Result<PointGather> gathered = pointGather(*this, points, PointGatherRequest::Light);
  if (!gathered) return gathered.error();
  std::vector<Rgb> irradiance = std::move(gathered->fromSurfaces);
  const std::vector<Rgb> direct = directIrradiance(*this, gathered->sites, gathered->rayEpsilon);
  for (std::size_t i = 0; i < irradiance.size(); ++i) irradiance[i] += direct[i];
  return irradiance;
}

std::vector<Rgb> SolutionView::vertexRadiance() const {
  std::vector<Rgb> radiance = vertexValues(VertexQuantity::Radiosity);
  for (Rgb& l : radiance) l = l / kPi;
  return radiance;
}

// The internal readers (engine/solution_internals.h).

const RadiosityProblem& radiosityProblem(const SolutionView& view) { return *SolutionInternals::of(view).problem_; }

std::vector<Rgb> radiosityFromInjected(const SolutionView& view, std::vector<Rgb> injected) {
  const auto& e = SolutionInternals::of(view);
  LAMBERT_CHECK(injected.size() == e.problem_->size());
  const RadiosityProblem problem{e.problem_->transport, std::move(injected), e.problem_->albedo, e.problem_->area};
  SolverOptions options;
  options.tolerance = e.options_.tolerance;
  options.maxIterations = e.options_.maxIterations;
  options.measureResidual = false;
  // The engine's gathering solver; the dense-matrix ones are the flat method's, and gather as well.
  const SolverKind kind = e.options_.solver == SolverKind::Jacobi ? SolverKind::Jacobi : SolverKind::GaussSeidel;
  std::vector<Rgb> radiosity;
  makeSolver(kind, options)->solve(problem, radiosity);
  return radiosity;
}

Result<PointGather> pointGather(const SolutionView& view, std::span<const SurfacePoint> points, PointGatherRequest part) {
  const auto& e = SolutionInternals::of(view);
  return e.meshing_->pointGather(e.elementSolution(), points, part);
}

std::vector<Rgb> directIrradiance(const SolutionView& view, std::span<const VertexSite> sites, double rayEpsilon) {
  std::vector<Rgb> irradiance(sites.size());
  if (view.lights().empty()) return irradiance;
  // By Ward's adaptive shadow testing (light/many_lights.h): within the solve's shadow tolerance
  // of the unoccluded light at each point, exact when it is 0.
  const DirectLighting lighting(view.lights(), view.scene().metresPerUnit, SolutionInternals::of(view).options_.directLight.shadowTolerance);
  parallelFor(0, sites.size(), [&](std::size_t i) {
    irradiance[i] = lighting.irradiance(sites[i].point, sites[i].normal, view.caster(), rayEpsilon);
  }, 64);
  return irradiance;
}

Result<PointGather> vertexGather(const SolutionView& view, std::span<const std::uint32_t> vertices, PointGatherRequest part) {
  const auto& e = SolutionInternals::of(view);
  return e.meshing_->vertexGather(e.elementSolution(), vertices, part);
}

Result<std::vector<Rgb>> nodeMeanRadiosity(const SolutionView& view) {
  const auto& e = SolutionInternals::of(view);
  return e.meshing_->nodeMeanRadiosity(e.elementSolution());
}

}  // namespace lambert
