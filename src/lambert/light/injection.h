#pragma once
// The lights' direct light as the radiosity system sees it (Keller 1997, seed 003): each patch's
// injected radiosity ρ_i·E_direct,i in W/m², summed over the lights. It is kept per light, so that
// when lights move only the ones that changed are traced again (Chen 1990's incremental update);
// the solver then shoots or gathers the difference.
#include <optional>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

class DirectLightInjection {
 public:
  explicit DirectLightInjection(DirectLightOptions options = {}) : options_(options) {}

  // Brings the injection up to date for `lights` on `mesh` (albedo ρ per patch): a light equal to
  // the one last injected at its index is kept, every other one is traced again. After reset(),
  // or when the number of lights changes, every light is.
  struct Update {
    int lightsTraced = 0;
    bool changed = false;  // total() differs from before (traced, or lights removed)
  };
  Update update(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo, const std::vector<Light>& lights,
                double metresPerUnit);
  // The mesh changed: the next update traces every light afresh.
  void reset();

  // Σ_l ρ_i E_l,i per patch of the mesh last updated for, W/m² (zeros without lights).
  const std::vector<Rgb>& total() const { return total_; }
  const DirectLightOptions& options() const { return options_; }

 private:
  DirectLightOptions options_;
  std::vector<std::optional<Light>> lights_;  // as last injected
  std::vector<std::vector<Rgb>> perLight_;    // ρ·E_direct per patch, per light
  std::vector<Rgb> total_;
};

}  // namespace lambert
