// Direct solution of (I − diag(ρ_c) F) B_c = E_c by LU with partial pivoting, one factorisation
// per channel: O(n³), exact up to rounding, the reference the iterative solvers are checked with.
// Needs the dense matrix: a transport without one (hierarchical) is a failed check.
#include <cmath>

#include <Eigen/LU>

#include "lambert/core/error.h"
#include "lambert/core/timer.h"
#include "lambert/solve/concrete_solvers.h"

namespace lambert {

SolverReport DirectSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  const auto n = static_cast<Eigen::Index>(problem.size());
  LAMBERT_CHECK(problem.transport && problem.transport->matrix());
  const Eigen::MatrixXd F = problem.transport->matrix()->cast<double>();
  radiosity.assign(problem.size(), Rgb{});
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd albedo(n), emitted(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      albedo[i] = problem.albedo[i][c];
      emitted[i] = problem.emitted[i][c];
    }
    Eigen::MatrixXd system = -(albedo.asDiagonal() * F);
    system.diagonal().array() += 1.0;
    Eigen::VectorXd solution = system.partialPivLu().solve(emitted);
    for (Eigen::Index i = 0; i < n; ++i) radiosity[i][c] = solution[i];
  }
  SolverReport report{"direct", 1, measureResidual_ ? relativeResidual(problem, radiosity) : std::nan(""), 0, true};
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
