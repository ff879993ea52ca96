// The Solver face of progressive refinement: a ProgressiveShooter run to convergence, with the
// ambient-corrected estimate handed to onProgress along the way.
#include "lambert/core/timer.h"
#include "lambert/solve/shooter.h"
#include "lambert/solve/solvers.h"

namespace lambert {

SolveReport ShootingSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  ProgressiveShooter shooter(problem);
  if (radiosity.size() == problem.size()) shooter.warmStart(radiosity);

  SolveReport report;
  report.solver = "shoot";
  const long long maxShots = static_cast<long long>(options_.maxIterations) * static_cast<long long>(problem.size());
  const bool reporting = options_.onProgress && options_.progressEvery > 0;
  const long long chunk = reporting ? options_.progressEvery : maxShots;
  long long shots = 0;
  while (shots < maxShots) {
    long long done = shooter.shoot(std::min(chunk, maxShots - shots), options_.tolerance);
    shots += done;
    if (done < std::min(chunk, maxShots - shots + done)) {
      report.converged = true;
      break;
    }
    if (reporting) options_.onProgress(static_cast<int>(shots), options_.displayAmbient ? shooter.displayRadiosity() : shooter.radiosity());
  }
  if (!report.converged) report.converged = shooter.unshotFraction() <= options_.tolerance;
  report.iterations = static_cast<int>(shots);
  radiosity = shooter.radiosity();
  report.residual = relativeResidual(problem, radiosity);
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
