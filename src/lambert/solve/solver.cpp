#include "lambert/solve/solver.h"

#include <cmath>
#include <cstdio>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/solve/concrete_solvers.h"

namespace lambert {

std::string solverName(SolverKind kind) {
  switch (kind) {
    case SolverKind::Direct: return "direct";
    case SolverKind::GaussSeidel: return "gs";
    case SolverKind::Jacobi: return "jacobi";
    case SolverKind::Shooting: return "shoot";
  }
  return "?";
}

std::unique_ptr<Solver> makeSolver(SolverKind kind, SolverOptions options) {
  switch (kind) {
    case SolverKind::Direct: return std::make_unique<DirectSolver>(options.measureResidual);
    case SolverKind::GaussSeidel: return std::make_unique<GatheringSolver>(options, /*inPlace=*/true);
    case SolverKind::Jacobi: return std::make_unique<GatheringSolver>(options, /*inPlace=*/false);
    case SolverKind::Shooting: return std::make_unique<ShootingSolver>(options);
  }
  return nullptr;
}

double relativeResidual(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity) {
  const std::size_t n = problem.size();
  LAMBERT_CHECK(problem.transport && radiosity.size() == n);
  std::vector<Rgb> irradiance;
  problem.transport->gather(radiosity, irradiance);
  std::vector<double> rowResidual(n), rowMagnitude(n);
  parallelFor(0, n, [&](std::size_t i) {
    Rgb r = problem.emitted[i] + problem.albedo[i] * irradiance[i] - radiosity[i];
    rowResidual[i] = std::fmax(std::fabs(r.r), std::fmax(std::fabs(r.g), std::fabs(r.b)));
    const Rgb& b = radiosity[i];
    rowMagnitude[i] = std::fmax(std::fabs(b.r), std::fmax(std::fabs(b.g), std::fabs(b.b)));
  }, 64);
  double residual = 0, magnitude = 0;
  for (std::size_t i = 0; i < n; ++i) {
    residual = std::fmax(residual, rowResidual[i]);
    magnitude = std::fmax(magnitude, rowMagnitude[i]);
  }
  return magnitude > 0 ? residual / magnitude : residual;
}

double emittedPower(const RadiosityProblem& problem) {
  double power = 0;
  for (std::size_t i = 0; i < problem.size(); ++i) power += (problem.emitted[i].r + problem.emitted[i].g + problem.emitted[i].b) * problem.area[i];
  return power;
}

std::optional<SolutionFault> findSolutionFault(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity,
                                               double earlierEmittedPower) {
  double power = 0, maxAlbedo = 0, largest = -1;
  std::size_t brightest = 0;
  for (std::size_t i = 0; i < radiosity.size(); ++i) {
    const Rgb& b = radiosity[i];
    if (!std::isfinite(b.r) || !std::isfinite(b.g) || !std::isfinite(b.b)) return SolutionFault{i, "is not finite"};
    const double p = (b.r + b.g + b.b) * problem.area[i];
    power += p;
    if (p > largest) largest = p, brightest = i;
    maxAlbedo = std::fmax(maxAlbedo, problem.albedo[i].maxComponent());
  }
  const double bound = 1.5 * std::fmax(emittedPower(problem), 1e-6 * earlierEmittedPower) / std::fmax(1 - maxAlbedo, 1e-6);
  if (power > bound && power > 0) {
    char what[200];
    std::snprintf(what, sizeof what, "holds the most of %.3g W·units² of power where the emission can give at most %.3g: the solve diverged",
                  power, bound);
    return SolutionFault{brightest, what};
  }
  return std::nullopt;
}

Rgb ambientRadiosity(const RadiosityProblem& problem, const std::vector<Rgb>& unshot) {
  double totalArea = 0;
  Rgb unshotPower, reflectedArea;
  for (std::size_t i = 0; i < problem.size(); ++i) {
    totalArea += problem.area[i];
    unshotPower += unshot[i] * problem.area[i];
    reflectedArea += problem.albedo[i] * problem.area[i];
  }
  Rgb ambient;
  for (int c = 0; c < 3; ++c) {
    double averageAlbedo = reflectedArea[c] / totalArea;
    ambient[c] = unshotPower[c] / totalArea / (1 - averageAlbedo);
  }
  return ambient;
}

}  // namespace lambert
