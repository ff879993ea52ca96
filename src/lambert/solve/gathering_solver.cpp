// Gathering iterations B_i ← E_i + ρ_i Σ_j F_ij B_j. Gauss–Seidel (seed 000) uses each new value
// as soon as it exists; Jacobi sweeps from the previous iterate so rows run in parallel. Both
// converge because ρ < 1 and the rows of F sum to at most 1. Each sweep is one more bounce.
#include <cmath>

#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/solve/gather_row.h"
#include "lambert/solve/concrete_solvers.h"

namespace lambert {

SolveReport GatheringSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  const std::size_t n = problem.size();
  const FormFactorMatrix& F = *problem.formFactors;
  if (radiosity.size() != n) radiosity = problem.emitted;

  SolveReport report;
  report.solver = inPlace_ ? "gs" : "jacobi";
  std::vector<Rgb> next(n);
  std::vector<double> rowChange(n), rowMagnitude(n);
  for (int sweep = 1; sweep <= options_.maxIterations; ++sweep) {
    double change = 0, magnitude = 0;
    if (inPlace_) {
      for (std::size_t i = 0; i < n; ++i) {
        Rgb updated = problem.emitted[i] + problem.albedo[i] * gatherRow(F, i, radiosity);
        Rgb delta = updated - radiosity[i];
        change = std::fmax(change, std::fmax(std::fabs(delta.r), std::fmax(std::fabs(delta.g), std::fabs(delta.b))));
        magnitude = std::fmax(magnitude, updated.maxComponent());
        radiosity[i] = updated;
      }
    } else {
      parallelFor(0, n, [&](std::size_t i) {
        next[i] = problem.emitted[i] + problem.albedo[i] * gatherRow(F, i, radiosity);
        Rgb delta = next[i] - radiosity[i];
        rowChange[i] = std::fmax(std::fabs(delta.r), std::fmax(std::fabs(delta.g), std::fabs(delta.b)));
        rowMagnitude[i] = next[i].maxComponent();
      }, 16);
      radiosity.swap(next);
      for (std::size_t i = 0; i < n; ++i) {
        change = std::fmax(change, rowChange[i]);
        magnitude = std::fmax(magnitude, rowMagnitude[i]);
      }
    }
    report.iterations = sweep;
    if (options_.onProgress && options_.progressEvery > 0 && sweep % options_.progressEvery == 0)
      options_.onProgress(sweep, radiosity);
    if (change <= options_.tolerance * magnitude) {
      report.converged = true;
      break;
    }
    if (options_.maxSeconds > 0 && timer.seconds() >= options_.maxSeconds) break;
  }
  report.residual = relativeResidual(problem, radiosity);
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
