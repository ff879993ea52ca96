#pragma once
// The lights' direct light as the radiosity system sees it (Keller 1997): each patch's
// injected radiosity ρ_i·E_direct,i in W/m², summed over the lights. It is kept per light, so that
// when lights move only the ones that changed are traced again (Chen 1990's incremental update);
// the solver then shoots or gathers the difference.
//
// A spot that moves is traced again on the patches its cone may reach only (PatchSphereTree),
// and only the patches it lit before or lights now are cleared and summed again: an update
// costs the spot's patches and O(log n) each, not the mesh, and gives every patch the same bits
// a trace of every light on every patch would.
//
// More than kPerLightInjectionLights lights under a shadow tolerance (DirectLightOptions) are
// traced together instead, each point's shadow rays chosen by Ward's adaptive testing
// (many_lights.h): no per-light arrays (200 lights × 10⁵ patches would be 0.5 GB of them), and
// any change traces them all again. Skies are traced on their own in either case.
#include <memory>
#include <optional>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/light/many_lights.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

class DirectLightInjection {
 public:
  explicit DirectLightInjection(DirectLightOptions options = {});
  ~DirectLightInjection();

  // Brings the injection up to date for `lights` on `mesh` (albedo ρ per patch): a light equal to
  // the one last injected at its index is kept, every other one is traced again. After reset(),
  // or when the number of lights changes, every light is.
  struct Update {
    int lightsTraced = 0;
    bool changed = false;  // total() may differ from before (traced, or lights removed)
    // Where it may differ: every patch, or (allPatches false) only changedPatches, in
    // increasing order; outside them total() keeps its bits.
    bool allPatches = false;
    std::vector<std::uint32_t> changedPatches;
  };
  Update update(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo, const std::vector<Light>& lights,
                double metresPerUnit);
  // The mesh changed: the next update traces every light afresh.
  void reset();

  // Σ_l ρ_i E_l,i per patch of the mesh last updated for, W/m² (zeros without lights).
  const std::vector<Rgb>& total() const { return total_; }
  // The part of total() the skies bring (LightKind::Sky), which a hybrid image keeps in the
  // solution while it draws every other light per pixel. Skies are traced apart from the other
  // lights even where those are traced together, so it is always known.
  const std::vector<Rgb>& skyTotal() const { return skyTotal_; }
  const DirectLightOptions& options() const { return options_; }
  // Points, lights reaching them and shadow rays of the many-light traces (more than
  // kPerLightInjectionLights lights under a shadow tolerance), summed over every update.
  const DirectLightingCounts& counts() const { return counts_; }

 private:
  DirectLightOptions options_;
  std::vector<std::optional<Light>> lights_;  // as last injected
  std::vector<std::vector<Rgb>> perLight_;    // ρ·E_direct per patch, per light
  // Per light, the patches it lights (a non-zero injection), in increasing order; it is zero on
  // every other.
  std::vector<std::vector<std::uint32_t>> traced_;
  std::vector<Rgb> total_, skyTotal_;
  // Of the mesh last updated for, made at its first update.
  std::unique_ptr<PatchSphereTree> tree_;
  std::optional<double> epsilon_;
  // Whether total_ holds the lights traced together (updateTogether), not per light.
  bool together_ = false;
  DirectLightingCounts counts_;
  Update updateTogether(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo, const std::vector<Light>& lights,
                        double metresPerUnit, bool startAfresh);
};

}  // namespace lambert
