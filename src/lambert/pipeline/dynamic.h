#pragma once
// Radiosity for lights that move while the geometry stays (seed 003's user story). The form
// factors are computed once; each frame re-injects the direct light of the lights that changed and
// shoots only the difference from the previous frame's state, optionally within a fixed budget of
// shots per frame (the seeds' "iterations over several frames").
#include <memory>
#include <optional>
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/solve/shooter.h"

namespace lambert {

struct DynamicOptions {
  DirectLightOptions direct;
  long long shotsPerFrame = 0;  // 0: shoot until converged every frame
  double tolerance = 1e-4;      // unshot power fraction counted as converged
};

struct FrameReport {
  int lightsUpdated = 0;
  long long shots = 0;
  double injectSeconds = 0;
  double solveSeconds = 0;
  double unshotFraction = 0;  // left for later frames when the budget ran out
};

class DynamicRadiosity {
 public:
  // problem: the scene's surfaces (emission, albedo, areas, form factors) without its lights.
  DynamicRadiosity(const Mesh& mesh, const RayCaster& caster, RadiosityProblem problem, double metresPerUnit,
                   DynamicOptions options = {});

  // Sets this frame's lights (same count and order every frame), re-injects those that differ
  // from the last frame's, and shoots within the frame's budget.
  FrameReport update(const std::vector<Light>& lights);

  // B in W/m²: emission, injected direct light and every bounce.
  const std::vector<Rgb>& radiosity() const { return shooter_.radiosity(); }
  // B less what the lights inject directly: what to interpolate when direct light is drawn per
  // pixel (seed 000's hybrid).
  std::vector<Rgb> indirectRadiosity() const;
  const std::vector<Rgb>& albedo() const { return albedo_; }

 private:
  const Mesh& mesh_;
  const RayCaster& caster_;
  double metresPerUnit_;
  DynamicOptions options_;
  std::vector<Rgb> surfaceEmitted_;
  std::vector<Rgb> albedo_;
  std::vector<std::optional<Light>> lights_;  // as last injected; empty before the first frame
  std::vector<std::vector<Rgb>> injected_;  // per light: ρ·E_direct per patch
  ProgressiveShooter shooter_;
};

}  // namespace lambert
