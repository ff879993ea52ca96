#include "lambert/light/injection.h"

namespace lambert {

DirectLightInjection::Update DirectLightInjection::update(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo,
                                 const std::vector<Light>& lights, double metresPerUnit) {
  const bool startAfresh = lights.size() != lights_.size() || total_.size() != mesh.numPatches();
  if (startAfresh) {
    lights_.assign(lights.size(), std::nullopt);
    perLight_.assign(lights.size(), {});
  }
  Update update;
  for (std::size_t l = 0; l < lights.size(); ++l) {
    if (lights_[l] && *lights_[l] == lights[l]) continue;
    perLight_[l] = injectedRadiosity(mesh, albedo, patchIrradiance(mesh, caster, lights[l], metresPerUnit, options_));
    lights_[l] = lights[l];
    ++update.lightsTraced;
  }
  update.changed = update.lightsTraced > 0 || startAfresh;
  if (update.changed) {
    total_.assign(mesh.numPatches(), Rgb{});
    for (const std::vector<Rgb>& injected : perLight_)
      for (std::size_t i = 0; i < injected.size(); ++i) total_[i] += injected[i];
  }
  return update;
}

void DirectLightInjection::reset() {
  lights_.clear();
  perLight_.clear();
  total_.clear();
}

}  // namespace lambert
