#include "lambert/solve/solver.h"

#include <cmath>

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

std::unique_ptr<Solver> makeSolver(SolverKind kind, SolveOptions options) {
  switch (kind) {
    case SolverKind::Direct: return std::make_unique<DirectSolver>();
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
