// Progressive refinement radiosity (Cohen, Chen, Wallace & Greenberg, "A Progressive Refinement
// Approach to Fast Radiosity Image Generation", SIGGRAPH 1988), as in seed 001: repeatedly pick
// the patch with the most unshot power ΔB_i A_i and shoot it to every patch j,
//   ΔB_j += ρ_j ΔB_i F_ji,  F_ji = F_ij A_i / A_j (reciprocity, so row i is all we read),
// until the unshot power is a small fraction of the total. Starting from a guess B₀, the residual
// r₀ = E + ρFB₀ − B₀ (which may be negative) is added to B₀ and becomes the unshot radiosity.
#include <cmath>

#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/solve/gather.h"
#include "lambert/solve/solvers.h"

namespace lambert {

SolveReport ShootingSolver::solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const {
  Timer timer;
  const std::size_t n = problem.size();
  const FormFactorMatrix& F = *problem.formFactors;
  std::vector<Rgb> unshot(n);
  if (radiosity.size() != n) {
    radiosity = problem.emitted;
    unshot = problem.emitted;
  } else {
    // B = B₀ + X with X = r₀ + ρFX: the residual r₀ is both added and left to shoot.
    parallelFor(0, n, [&](std::size_t i) {
      unshot[i] = problem.emitted[i] + problem.albedo[i] * gatherRow(F, i, radiosity) - radiosity[i];
    }, 16);
    for (std::size_t i = 0; i < n; ++i) radiosity[i] += unshot[i];
  }

  auto power = [&](std::size_t i) {
    return (std::fabs(unshot[i].r) + std::fabs(unshot[i].g) + std::fabs(unshot[i].b)) * problem.area[i];
  };

  SolveReport report;
  report.solver = "shoot";
  const long long maxShots = static_cast<long long>(options_.maxIterations) * static_cast<long long>(n);
  std::vector<Rgb> display;
  for (long long shot = 1; shot <= maxShots; ++shot) {
    // The brightest shooter, and the totals the stopping test compares.
    std::size_t shooter = 0;
    double best = -1, unshotPower = 0, totalPower = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double p = power(i);
      unshotPower += p;
      totalPower += radiosity[i].sum() * problem.area[i];
      if (p > best) {
        best = p;
        shooter = i;
      }
    }
    if (unshotPower <= options_.tolerance * totalPower) {
      report.converged = true;
      break;
    }
    const Rgb shooting = unshot[shooter];
    unshot[shooter] = Rgb{};
    const float* row = F.data() + shooter * static_cast<std::size_t>(F.cols());
    const double shooterArea = problem.area[shooter];
    for (std::size_t j = 0; j < n; ++j) {
      if (row[j] == 0) continue;
      double fji = row[j] * shooterArea / problem.area[j];
      Rgb received = problem.albedo[j] * shooting * fji;
      unshot[j] += received;
      radiosity[j] += received;
    }
    report.iterations = static_cast<int>(shot);
    if (options_.onProgress && options_.progressEvery > 0 && shot % options_.progressEvery == 0) {
      Rgb ambient = options_.displayAmbient ? ambientRadiosity(problem, unshot) : Rgb{};
      display.resize(n);
      for (std::size_t i = 0; i < n; ++i) display[i] = radiosity[i] + problem.albedo[i] * ambient;
      options_.onProgress(static_cast<int>(shot), display);
    }
  }
  report.residual = relativeResidual(problem, radiosity);
  report.seconds = timer.seconds();
  return report;
}

}  // namespace lambert
