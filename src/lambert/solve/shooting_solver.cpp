// The Solver face of progressive refinement: a ProgressiveShooter run to convergence, with the
// ambient-corrected estimate handed to onProgress along the way.
#include <algorithm>
#include <cmath>

#include "lambert/core/timer.h"
#include "lambert/solve/progressive_shooter.h"
#include "lambert/solve/concrete_solvers.h"

namespace lambert {

SolverReport ShootingSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  ProgressiveShooter shooter(problem);
  if (radiosity.size() == problem.size()) shooter.warmStart(radiosity);

  SolverReport report;
  report.solver = "shoot";
  const long long maxShots = static_cast<long long>(options_.maxIterations) * static_cast<long long>(problem.size());
  const bool reporting = options_.onProgress && options_.progressEvery > 0;
  const long long chunk = reporting ? options_.progressEvery : maxShots;
  long long shots = 0;
  while (shots < maxShots) {
    const double secondsLeft = options_.maxSeconds > 0 ? std::max(1e-9, options_.maxSeconds - timer.seconds()) : 0;
    ProgressiveShooter::Outcome outcome = shooter.shoot(std::min(chunk, maxShots - shots), options_.tolerance, secondsLeft);
    shots += outcome.shots;
    report.converged = outcome.converged;
    if (outcome.converged || (options_.maxSeconds > 0 && timer.seconds() >= options_.maxSeconds)) break;
    if (reporting) options_.onProgress(static_cast<int>(shots), options_.displayAmbient ? shooter.displayRadiosity() : shooter.radiosity());
  }
  report.iterations = static_cast<int>(shots);
  radiosity = shooter.radiosity();
  report.residual = options_.measureResidual ? relativeResidual(problem, radiosity) : std::nan("");
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
