#include "lambert/light/injection.h"

#include <algorithm>

#include "lambert/light/many_lights.h"

namespace lambert {

DirectLightInjection::DirectLightInjection(DirectLightOptions options) : options_(options) {}
DirectLightInjection::~DirectLightInjection() = default;

DirectLightInjection::Update DirectLightInjection::update(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo,
                                 const std::vector<Light>& lights, double metresPerUnit) {
  const std::size_t n = mesh.numPatches();
  const bool startAfresh = lights.size() != lights_.size() || total_.size() != n;
  if (startAfresh) {
    lights_.assign(lights.size(), std::nullopt);
    perLight_.assign(lights.size(), {});
    traced_.assign(lights.size(), {});
  }
  if (total_.size() != n) {  // another mesh
    tree_.reset();
    epsilon_.reset();
  }
  // Made with the mesh's first update that has lights (with its first solve), so that the first
  // frame a light moves in does not pay for it; a scene lit by its surfaces alone never needs them
  // (3% of a second run from the link cache on a 10⁵-face building).
  if (!lights.empty() && !epsilon_) epsilon_ = rayEpsilon(mesh);
  if (!lights.empty() && !tree_) tree_ = std::make_unique<PatchSphereTree>(mesh);
  Update update;
  update.allPatches = startAfresh;
  if (options_.shadowTolerance > 0 && lights.size() > kPerLightInjectionLights) return updateTogether(mesh, caster, albedo, lights, metresPerUnit, startAfresh);
  together_ = false;
  for (std::size_t l = 0; l < lights.size(); ++l) {
    if (lights_[l] && *lights_[l] == lights[l]) continue;
    std::vector<Rgb>& injected = perLight_[l];
    if (injected.size() != n) injected.assign(n, Rgb{});
    for (std::uint32_t i : traced_[l]) injected[i] = Rgb{};
    const std::vector<std::uint32_t> candidates = tree_->candidates(lights[l]);
    patchIrradiance(mesh, caster, lights[l], metresPerUnit, options_, *epsilon_, candidates, injected);
    std::vector<std::uint32_t> lit;
    for (std::uint32_t i : candidates) {
      injected[i] = albedo[i] * injected[i];  // as injectedRadiosity
      if (!(injected[i] == Rgb{})) lit.push_back(i);
    }
    if (!update.allPatches) {
      update.changedPatches.insert(update.changedPatches.end(), traced_[l].begin(), traced_[l].end());
      update.changedPatches.insert(update.changedPatches.end(), lit.begin(), lit.end());
    }
    traced_[l] = std::move(lit);
    lights_[l] = lights[l];
    ++update.lightsTraced;
  }
  update.changed = update.lightsTraced > 0 || startAfresh;
  if (!update.changed) return update;
  std::sort(update.changedPatches.begin(), update.changedPatches.end());
  update.changedPatches.erase(std::unique(update.changedPatches.begin(), update.changedPatches.end()), update.changedPatches.end());
  update.allPatches |= update.changedPatches.size() == n;
  if (update.allPatches) update.changedPatches.clear();
  // Each patch summed in the lights' order from zero, wherever it is summed.
  auto sum = [&](std::size_t i) {
    Rgb t, sky;
    for (std::size_t l = 0; l < perLight_.size(); ++l) {
      t += perLight_[l][i];
      if (lights_[l]->kind == LightKind::Sky) sky += perLight_[l][i];
    }
    total_[i] = t;
    skyTotal_[i] = sky;
  };
  if (update.allPatches) {
    total_.assign(n, Rgb{});
    skyTotal_.assign(n, Rgb{});
    for (std::size_t i = 0; i < n; ++i) sum(i);
  } else {
    for (std::uint32_t i : update.changedPatches) sum(i);
  }
  return update;
}

// Many lights: every patch's light from all of them at once, each point's shadow rays chosen by
// Ward's adaptive testing (many_lights.h), so that the cost follows the lights that matter at a
// point rather than leaves × lights. The estimate at a point is not a sum of per-light parts
// (the untested lights are weighted by the tested ones' visibility), so nothing is kept per light:
// any change traces every light again. Only the patches some light may reach are traced (the
// union of PatchSphereTree's candidates; every patch when one light is not a spot). Skies are
// traced apart (below).
DirectLightInjection::Update DirectLightInjection::updateTogether(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo,
                                                                  const std::vector<Light>& lights, double metresPerUnit, bool startAfresh) {
  const std::size_t n = mesh.numPatches();
  Update update;
  bool same = !startAfresh && together_;
  for (std::size_t l = 0; same && l < lights.size(); ++l) same = lights_[l] && *lights_[l] == lights[l];
  if (same) return update;
  perLight_.assign(lights.size(), {});  // the per-light path's memory, released
  traced_.assign(lights.size(), {});
  for (std::size_t l = 0; l < lights.size(); ++l) lights_[l] = lights[l];
  together_ = true;
  // A sky is traced on its own: its estimate is many rays over the whole hemisphere, which Ward's
  // testing of point-like lights cannot thin, and kept apart, its part stays known (skyTotal).
  std::vector<Light> others;
  std::vector<Rgb> skyIrradiance(n);
  std::vector<std::uint32_t> allPatches(n);
  for (std::uint32_t i = 0; i < n; ++i) allPatches[i] = i;
  for (const Light& light : lights) {
    if (light.kind != LightKind::Sky) {
      others.push_back(light);
      continue;
    }
    std::vector<Rgb> e(n);
    patchIrradiance(mesh, caster, light, metresPerUnit, options_, *epsilon_, allPatches, e);
    for (std::size_t i = 0; i < n; ++i) skyIrradiance[i] += e[i];
  }
  std::vector<char> reached(n, 0);
  for (const Light& light : others) {
    if (light.kind != LightKind::Spot) {
      std::fill(reached.begin(), reached.end(), 1);
      break;
    }
    for (std::uint32_t i : tree_->candidates(light)) reached[i] = 1;
  }
  std::vector<std::uint32_t> patches;
  for (std::uint32_t i = 0; i < n; ++i)
    if (reached[i]) patches.push_back(i);
  std::vector<Rgb> irradiance(n);
  if (!others.empty()) {
    const DirectLighting lighting(others, metresPerUnit, options_.shadowTolerance);
    DirectLightingCounts counts;
    patchIrradiance(mesh, caster, lighting, options_, *epsilon_, patches, irradiance, &counts);
    counts_.add(counts);
  }
  total_.assign(n, Rgb{});
  skyTotal_.assign(n, Rgb{});
  for (std::size_t i = 0; i < n; ++i) {
    skyTotal_[i] = albedo[i] * skyIrradiance[i];
    total_[i] = albedo[i] * (irradiance[i] + skyIrradiance[i]);
  }
  update.lightsTraced = static_cast<int>(lights.size());
  update.changed = true;
  update.allPatches = true;
  return update;
}

void DirectLightInjection::reset() {
  together_ = false;
  lights_.clear();
  perLight_.clear();
  traced_.clear();
  total_.clear();
  tree_.reset();
  epsilon_.reset();
}

}  // namespace lambert
