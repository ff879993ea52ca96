#include "lambert/pipeline/dynamic.h"

#include <limits>

#include "lambert/core/error.h"
#include "lambert/core/timer.h"

namespace lambert {

DynamicRadiosity::DynamicRadiosity(const Mesh& mesh, const RayCaster& caster, RadiosityProblem problem,
                                   double metresPerUnit, DynamicOptions options)
    : mesh_(mesh),
      caster_(caster),
      metresPerUnit_(metresPerUnit),
      options_(options),
      surfaceEmitted_(problem.emitted),
      albedo_(problem.albedo),
      shooter_(problem) {}

FrameReport DynamicRadiosity::update(const std::vector<Light>& lights) {
  FrameReport report;
  Timer injectTimer;
  if (lights_.empty()) {
    lights_.resize(lights.size());
    injected_.resize(lights.size());
  }
  LAMBERT_CHECK(lights.size() == lights_.size());
  bool changed = false;
  for (std::size_t l = 0; l < lights.size(); ++l) {
    if (lights_[l] && *lights_[l] == lights[l]) continue;
    lights_[l] = lights[l];
    injected_[l] = injectedRadiosity(mesh_, albedo_, patchIrradiance(mesh_, caster_, lights[l], metresPerUnit_, options_.direct));
    ++report.lightsUpdated;
    changed = true;
  }
  if (changed) {
    std::vector<Rgb> emitted = surfaceEmitted_;
    for (const auto& injected : injected_)
      for (std::size_t i = 0; i < injected.size(); ++i) emitted[i] += injected[i];
    shooter_.setEmitted(emitted);
  }
  report.injectSeconds = injectTimer.seconds();

  Timer solveTimer;
  long long budget = options_.shotsPerFrame > 0 ? options_.shotsPerFrame : std::numeric_limits<long long>::max();
  report.shots = shooter_.shoot(budget, options_.tolerance);
  report.unshotFraction = shooter_.unshotFraction();
  report.solveSeconds = solveTimer.seconds();
  return report;
}

std::vector<Rgb> DynamicRadiosity::indirectRadiosity() const {
  std::vector<Rgb> indirect = shooter_.radiosity();
  for (const auto& injected : injected_)
    for (std::size_t i = 0; i < injected.size(); ++i) indirect[i] -= injected[i];
  return indirect;
}

}  // namespace lambert
