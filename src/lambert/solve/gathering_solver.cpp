// Gathering iterations B_i ← E_i + ρ_i Σ_j F_ij B_j, each sweep one Transport::sweep, so any
// transport will do. Gauss–Seidel uses each new value as soon as it exists; Jacobi
// sweeps from the previous iterate so rows run in parallel. Both converge because ρ < 1 and the
// rows of F sum to at most 1. Each sweep is one more bounce.
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/timer.h"
#include "lambert/solve/concrete_solvers.h"

namespace lambert {

SolverReport GatheringSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  const std::size_t n = problem.size();
  LAMBERT_CHECK(problem.transport && problem.transport->size() == n);
  const Transport& transport = *problem.transport;
  if (radiosity.size() != n) radiosity = problem.emitted;

  SolverReport report;
  report.solver = inPlace_ ? "gs" : "jacobi";
  for (int sweep = 1; sweep <= options_.maxIterations; ++sweep) {
    const SweepChange step = transport.sweep(problem.emitted, problem.albedo, radiosity, inPlace_);
    report.iterations = sweep;
    if (options_.onProgress && options_.progressEvery > 0 && sweep % options_.progressEvery == 0)
      options_.onProgress(sweep, radiosity);
    if (step.change <= options_.tolerance * step.magnitude) {
      report.converged = true;
      break;
    }
    if (options_.maxSeconds > 0 && timer.seconds() >= options_.maxSeconds) break;
  }
  transport.completeSweeps(radiosity);
  report.residual = options_.measureResidual ? relativeResidual(problem, radiosity) : std::nan("");
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
