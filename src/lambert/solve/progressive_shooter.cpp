#include "lambert/solve/progressive_shooter.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/cancel.h"
#include "lambert/core/error.h"
#include "lambert/core/timer.h"

namespace lambert {
namespace {

double absoluteSum(const Rgb& c) { return std::fabs(c.r) + std::fabs(c.g) + std::fabs(c.b); }

}  // namespace

ProgressiveShooter::ProgressiveShooter(const RadiosityProblem& problem)
    : problem_(problem), radiosity_(problem.emitted), unshot_(problem.emitted) {
  LAMBERT_CHECK(problem_.transport && problem_.transport->matrix());
}

void ProgressiveShooter::warmStart(const std::vector<Rgb>& radiosity) {
  LAMBERT_CHECK(radiosity.size() == problem_.size());
  radiosity_ = radiosity;
  std::vector<Rgb> irradiance;
  problem_.transport->gather(radiosity_, irradiance);
  for (std::size_t i = 0; i < problem_.size(); ++i) {
    unshot_[i] = problem_.emitted[i] + problem_.albedo[i] * irradiance[i] - radiosity_[i];
    radiosity_[i] += unshot_[i];
  }
}

void ProgressiveShooter::setEmitted(const std::vector<Rgb>& emitted) {
  LAMBERT_CHECK(emitted.size() == problem_.size());
  for (std::size_t i = 0; i < emitted.size(); ++i) {
    Rgb change = emitted[i] - problem_.emitted[i];
    radiosity_[i] += change;
    unshot_[i] += change;
  }
  problem_.emitted = emitted;
}

long long ProgressiveShooter::shoot(long long maxShots, double tolerance) {
  const std::size_t n = problem_.size();
  const FormFactorMatrix& F = *problem_.transport->matrix();
  long long shots = 0;
  while (shots < maxShots) {
    throwIfCancelled();
    // The brightest shooter, and the totals the stopping test compares.
    std::size_t shooter = 0;
    double best = -1, unshotPower = 0, totalPower = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double p = absoluteSum(unshot_[i]) * problem_.area[i];
      unshotPower += p;
      totalPower += absoluteSum(radiosity_[i]) * problem_.area[i];
      if (p > best) {
        best = p;
        shooter = i;
      }
    }
    if (unshotPower <= tolerance * totalPower) break;
    const Rgb shooting = unshot_[shooter];
    unshot_[shooter] = Rgb{};
    const float* row = F.data() + shooter * static_cast<std::size_t>(F.cols());
    const double shooterArea = problem_.area[shooter];
    for (std::size_t j = 0; j < n; ++j) {
      if (row[j] == 0) continue;
      Rgb received = problem_.albedo[j] * shooting * (row[j] * shooterArea / problem_.area[j]);
      unshot_[j] += received;
      radiosity_[j] += received;
    }
    ++shots;
  }
  return shots;
}

ProgressiveShooter::Outcome ProgressiveShooter::shoot(long long maxShots, double tolerance, double maxSeconds) {
  Timer timer;
  const long long chunk = maxSeconds > 0 ? 32 : maxShots;
  Outcome outcome;
  while (outcome.shots < maxShots) {
    const long long want = std::min(chunk, maxShots - outcome.shots);
    const long long done = shoot(want, tolerance);
    outcome.shots += done;
    if (done < want) {
      outcome.converged = true;
      return outcome;
    }
    if (maxSeconds > 0 && timer.seconds() >= maxSeconds) break;
  }
  outcome.converged = unshotFraction() <= tolerance;
  return outcome;
}

double ProgressiveShooter::unshotFraction() const {
  double unshotPower = 0, totalPower = 0;
  for (std::size_t i = 0; i < problem_.size(); ++i) {
    unshotPower += absoluteSum(unshot_[i]) * problem_.area[i];
    totalPower += absoluteSum(radiosity_[i]) * problem_.area[i];
  }
  return totalPower > 0 ? unshotPower / totalPower : 0;
}

std::vector<Rgb> ProgressiveShooter::displayRadiosity() const {
  Rgb ambient = ambientRadiosity(problem_, unshot_);
  std::vector<Rgb> display(radiosity_);
  for (std::size_t i = 0; i < display.size(); ++i) display[i] += problem_.albedo[i] * ambient;
  return display;
}

}  // namespace lambert
