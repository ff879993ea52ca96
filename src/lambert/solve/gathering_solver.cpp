// Gathering iterations B_i ← E_i + ρ_i Σ_j F_ij B_j, each sweep one Transport::sweep, so any
// transport will do. Gauss–Seidel uses each new value as soon as it exists; Jacobi
// sweeps from the previous iterate so rows run in parallel. Both converge because ρ < 1 and the
// rows of F sum to at most 1. Each sweep is one more bounce.
//
// Gauss–Seidel's sweeps shrink the error by the largest loop gain each, which nears 1 in a pocket
// of near-white faces (RenderPark's hospital repairs rd = 1 to 0.999: 423 sweeps, 0.9875 a sweep
// at the end, for what its first 10 had nearly done). Where kSlowSweeps sweeps in a row each
// leave more than kSlowRatio of the change before them, the rest is solved by BiCGSTAB over the
// transport's gather (solve/krylov.h), to the same bound on the change a sweep would make.
#include <cmath>

#include "lambert/core/cancel.h"
#include "lambert/core/error.h"
#include "lambert/core/timer.h"
#include "lambert/solve/concrete_solvers.h"
#include "lambert/solve/krylov.h"

namespace lambert {
namespace {

constexpr int kSlowSweeps = 3;
constexpr double kSlowRatio = 0.7;

// B = E + ρ G(B) from B's current value, G the transport's gather; returns the Krylov
// iterations, or −1 where BiCGSTAB did not converge (B is then left as it was).
int finishByKrylov(const RadiosityProblem& problem, std::vector<Rgb>& radiosity, double tolerance, int maxIterations) {
  const std::size_t n = radiosity.size();
  const Transport& transport = *problem.transport;
  std::vector<Rgb> in(n), irradiance;
  const auto applyM = [&](const double* x, double* y) {
    for (std::size_t i = 0; i < n; ++i) in[i] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    transport.gather(in, irradiance);
    for (std::size_t i = 0; i < n; ++i) {
      const Rgb h = problem.albedo[i] * irradiance[i];
      y[3 * i] = h.r;
      y[3 * i + 1] = h.g;
      y[3 * i + 2] = h.b;
    }
  };
  Eigen::VectorXd b(3 * n), x(3 * n);
  double magnitude = 0;
  for (std::size_t i = 0; i < n; ++i) {
    b.segment<3>(3 * i) << problem.emitted[i].r, problem.emitted[i].g, problem.emitted[i].b;
    x.segment<3>(3 * i) << radiosity[i].r, radiosity[i].g, radiosity[i].b;
    magnitude = std::fmax(magnitude, radiosity[i].maxComponent());
  }
  // ‖r‖₂ bounds every element's |r_i|, the change a Jacobi sweep would make there.
  const KrylovReport report = solveIdentityMinus(applyM, b, x, tolerance * magnitude, maxIterations);
  if (!report.converged) return -1;
  // The exact solution is not negative; the iterate may be, by a share of the tolerance.
  for (std::size_t i = 0; i < n; ++i) radiosity[i] = nonNegative(Rgb{x[3 * i], x[3 * i + 1], x[3 * i + 2]});
  return report.iterations;
}

}  // namespace

SolverReport GatheringSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  const std::size_t n = problem.size();
  LAMBERT_CHECK(problem.transport && problem.transport->size() == n);
  const Transport& transport = *problem.transport;
  if (radiosity.size() != n) radiosity = problem.emitted;

  SolverReport report;
  report.solver = inPlace_ ? "gs" : "jacobi";
  double previousChange = INFINITY;
  int slowSweeps = 0;
  for (int sweep = 1; sweep <= options_.maxIterations; ++sweep) {
    throwIfCancelled();
    const SweepChange step = transport.sweep(problem.emitted, problem.albedo, radiosity, inPlace_);
    report.iterations = sweep;
    if (options_.onProgress && options_.progressEvery > 0 && sweep % options_.progressEvery == 0)
      options_.onProgress(sweep, radiosity);
    if (step.change <= options_.tolerance * step.magnitude) {
      report.converged = true;
      break;
    }
    slowSweeps = inPlace_ && step.change > kSlowRatio * previousChange ? slowSweeps + 1 : 0;
    previousChange = step.change;
    // Not under a time budget (a live view's frame): BiCGSTAB runs to its end without looking at
    // the clock, where each sweep does.
    if (slowSweeps >= kSlowSweeps && sweep < options_.maxIterations && !(options_.maxSeconds > 0)) {
      // Each Krylov iteration applies the transport twice: counted as two sweeps.
      const int krylov = finishByKrylov(problem, radiosity, options_.tolerance, (options_.maxIterations - sweep) / 2);
      if (krylov >= 0) {
        report.iterations = sweep + 2 * krylov;
        report.converged = true;
        break;
      }
      slowSweeps = 0;  // not converged: back to sweeping from where they were
    }
    if (options_.maxSeconds > 0 && timer.seconds() >= options_.maxSeconds) break;
  }
  transport.completeSweeps(radiosity);
  report.residual = options_.measureResidual ? relativeResidual(problem, radiosity) : std::nan("");
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
