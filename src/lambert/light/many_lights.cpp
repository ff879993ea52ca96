#include "lambert/light/many_lights.h"

#include <algorithm>
#include <cmath>

#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lambert/core/error.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/light/lights.h"
#include "lambert/light/photometry.h"
#include "lambert/core/photometric.h"  // kLumensPerWatt
#include "lambert/scene/scene.h"

namespace lambert {
namespace {

constexpr double kDegrees = kPi / 180;


// The shadow ray lights.cpp's irradiance() traces.
bool occluded(const Light& light, const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon) {
  const Vec3 origin = x + n * epsilon;
  const Ray shadow = light.kind == LightKind::Directional ? Ray{origin, -normalize(light.direction), 0, INFINITY}
                                                          : Ray{origin, light.position - origin, 0, 1 - 1e-7};
  return caster.occluded(shadow);
}

struct Candidate {
  double key;  // Σ channels of E_l: the order the rays are traced in
  std::uint32_t light;
  Rgb e;
  bool operator<(const Candidate& o) const { return key < o.key || (key == o.key && light > o.light); }
};

}  // namespace

DirectLighting::DirectLighting(std::span<const Light> lights, double metresPerUnit, double tolerance)
    : lights_(lights.begin(), lights.end()), metresPerUnit_(metresPerUnit), tolerance_(tolerance) {
  LAMBERT_CHECK(tolerance >= 0 && tolerance < 1);
  prepared_.resize(lights_.size());
  for (std::size_t l = 0; l < lights_.size(); ++l) {
    const Light& light = lights_[l];
    Prepared& p = prepared_[l];
    if (light.kind == LightKind::Luminaire && light.luminaireModel == LuminaireModel::FarField && light.photometry &&
        light.photometry->verticalDegrees.size() >= 2 && !light.photometry->horizontalDegrees.empty()) {
      // E = I(C, γ)·cosθ/r² from its photometric centre (lights.cpp's luminaireSourceIrradiance,
      // the frame and the tilt factor computed once).
      const Photometry& photometry = *light.photometry;
      p.fast = p.luminaire = true;
      p.position = light.position;
      p.frame = luminaireFrame(light);
      double tilt = 1;
      if (!photometry.tilt.degrees.empty()) {
        // As lights.cpp's tiltFactor: the lamps tilt by the angle between the aim and straight down.
        const double cosTilt = std::fmin(std::fmax(-normalize(light.direction).y, -1.0), 1.0);
        tilt = photometry.tilt.factor(std::acos(cosTilt) / kDegrees);
      }
      // intensity is colour × multiplier: W/sr = candela × intensity / 683 lm/W (scene.h).
      p.intensityPerSquareMetre = light.intensity * (tilt / (kLumensPerWatt * metresPerUnit * metresPerUnit));
      const std::size_t nV = photometry.verticalDegrees.size();
      p.candelaBeyond.assign(nV, 0);
      for (std::size_t v = nV; v-- > 0;) {
        double largest = v + 1 < nV ? p.candelaBeyond[v + 1] : 0;
        for (std::size_t c = 0; c < photometry.horizontalDegrees.size(); ++c) largest = std::fmax(largest, photometry.candelaGrid[c * nV + v]);
        p.candelaBeyond[v] = largest;
      }
      continue;
    }
    if (light.kind != LightKind::Point && light.kind != LightKind::Spot) continue;
    p.fast = true;
    p.position = light.position;
    p.intensityPerSquareMetre = light.intensity / (metresPerUnit * metresPerUnit);
    if (light.kind == LightKind::Spot) {
      p.spot = true;
      p.axis = normalize(light.direction);
      const double outer = light.coneAngleDegrees * kDegrees;
      const double inner = std::fmax(outer - light.falloffDegrees * kDegrees, 0.0);
      p.cosOuter = std::cos(outer);
      p.sinOuter = std::sin(outer);
      p.cosInner = std::cos(inner);
    }
  }
}

Rgb DirectLighting::contribution(std::size_t l, const Vec3& x, const Vec3& n) const {
  const Prepared& p = prepared_[l];
  if (!p.fast) return unshadowedIrradiance(lights_[l], x, n, metresPerUnit_);
  // E = I cosθ / r² (unshadowedIrradiance's formula, the cone's cosines precomputed).
  const Vec3 toLight = p.position - x;
  const double distanceSquared = lengthSquared(toLight);
  if (distanceSquared <= 0) return {};
  const double cosine = dot(n, toLight);
  if (cosine <= 0) return {};
  if (p.luminaire) {
    const double distance = std::sqrt(distanceSquared);
    double c = 0, gamma = 0;
    photometricAngles(p.frame, toLight / -distance, c, gamma);
    const double candela = lights_[l].photometry->candela(c, gamma);
    return p.intensityPerSquareMetre * (candela * (cosine / distance) / distanceSquared);
  }
  const double inverseDistance = 1 / std::sqrt(distanceSquared);
  double falloff = 1;
  if (p.spot) {
    falloff = smoothstep(p.cosOuter, p.cosInner, -dot(p.axis, toLight) * inverseDistance);
    if (falloff <= 0) return {};
  }
  return p.intensityPerSquareMetre * (falloff * cosine * inverseDistance / distanceSquared);
}

Rgb DirectLighting::unoccluded(const Vec3& x, const Vec3& n) const {
  Rgb sum;
  for (std::size_t l = 0; l < lights_.size(); ++l) sum += contribution(l, x, n);
  return sum;
}

Rgb DirectLighting::upperBound(std::size_t l, const Vec3& centre, double radius, const Vec3& n) const {
  const Prepared& p = prepared_[l];
  constexpr Rgb kUnknown{INFINITY, INFINITY, INFINITY};
  if (!p.fast) return kUnknown;
  const Vec3 toCentre = centre - p.position;
  const double distance = length(toCentre);
  if (!(distance > radius)) return kUnknown;
  // Every x of the region has n·(light − x) ≤ n·(light − centre) + radius and |light − x| ≥
  // distance − radius: cosθ/r² is at most their quotient over (distance − radius)².
  const double nearest = distance - radius;
  const double facing = -dot(n, toCentre) + radius;
  if (facing <= 0) return {};
  const double cosine = std::fmin(1.0, facing / nearest);
  if (p.luminaire) {
    // The least γ of a direction from the light into the region: the centre's, less the region's
    // angular radius asin(radius / distance); no candela beyond it exceeds candelaBeyond there.
    const std::vector<double>& v = lights_[l].photometry->verticalDegrees;
    const double alpha = std::acos(std::fmin(std::fmax(dot(p.frame.nadir, toCentre) / distance, -1.0), 1.0)) / kDegrees;
    const double gamma = std::fmax(0.0, alpha - std::asin(std::fmin(1.0, radius / distance)) / kDegrees);
    if (gamma > v.back() + 1e-9) return {};  // beyond the measured range it emits nothing
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), gamma) - v.begin());
    const double candela = p.candelaBeyond[k > 0 ? k - 1 : 0];
    return p.intensityPerSquareMetre * (candela * (1 + 1e-9) * cosine / (nearest * nearest));
  }
  if (p.spot) {
    // Seen from the light the region spans β = asin(radius / distance) about its centre: it
    // reaches into the cone when the angle to the axis is below the cone's + β (lights.cpp's
    // sphereReachesCone, by cosines).
    const double sinBeta = radius / distance, cosBeta = std::sqrt(1 - sinBeta * sinBeta);
    const bool always = p.cosOuter < 0 && sinBeta >= p.sinOuter;
    const double cosAxis = std::fmin(std::fmax(dot(p.axis, toCentre) / distance, -1.0), 1.0);
    if (!always && !(cosAxis > p.cosOuter * cosBeta - p.sinOuter * sinBeta)) return {};
  }
  return p.intensityPerSquareMetre * (cosine / (nearest * nearest));
}

void DirectLighting::select(const Vec3& centre, double radius, const Vec3& n, LightSelection& out) const {
  out.kept.clear();
  out.dropped.clear();
  out.droppedBound = {};
  if (exact()) {
    for (std::uint32_t l = 0; l < lights_.size(); ++l) out.kept.push_back(l);
    return;
  }
  // The bounds, the lights that cannot reach dropped outright (bound 0: behind the region, the
  // region outside the cone), then the weakest dropped while their bounds sum to at most τ/2 of a
  // quarter of all the bounds (a guess at the kept lights' unoccluded sum; a point where it is
  // wrong evaluates the dropped lights itself, so the guess costs time, never accuracy).
  thread_local std::vector<std::pair<double, std::uint32_t>> bounded;
  bounded.clear();
  Rgb all;
  for (std::uint32_t l = 0; l < lights_.size(); ++l) {
    const Rgb b = upperBound(l, centre, radius, n);
    if (!(b.maxComponent() > 0)) continue;
    if (!std::isfinite(b.maxComponent())) {
      out.kept.push_back(l);
      continue;
    }
    all += b;
    bounded.push_back({b[0] + b[1] + b[2], l});
  }
  std::sort(bounded.begin(), bounded.end());
  const Rgb budget = all * (0.25 * 0.5 * tolerance_);
  std::size_t k = 0;
  for (; k < bounded.size(); ++k) {
    const Rgb next = out.droppedBound + upperBound(bounded[k].second, centre, radius, n);
    if (next[0] > budget[0] || next[1] > budget[1] || next[2] > budget[2]) break;
    out.droppedBound = next;
    out.dropped.push_back(bounded[k].second);
  }
  for (; k < bounded.size(); ++k) out.kept.push_back(bounded[k].second);
  std::sort(out.kept.begin(), out.kept.end());
}

Rgb DirectLighting::irradiance(const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon, DirectLightingCounts* counts) const {
  if (exact()) {
    // Every light its ray, in order: lights.h's irradiance() summed.
    Rgb e;
    for (const Light& light : lights_) {
      const Rgb el = unshadowedIrradiance(light, x, n, metresPerUnit_);
      if (el.maxComponent() <= 0) continue;
      if (counts) ++counts->lightsReaching, ++counts->shadowRays;
      e += light.kind == LightKind::Point || light.kind == LightKind::Spot || light.kind == LightKind::Directional
               ? (occluded(light, x, n, caster, epsilon) ? Rgb{} : el)
               : lambert::irradiance(light, x, n, caster, epsilon, metresPerUnit_);
    }
    if (counts) ++counts->points;
    return e;
  }
  // A single point: every light evaluated (its bound would cost as much as its value).
  thread_local std::vector<std::uint32_t> all;
  if (all.size() != lights_.size()) {
    all.resize(lights_.size());
    for (std::uint32_t l = 0; l < all.size(); ++l) all[l] = l;
  }
  return ward(x, n, caster, epsilon, all, {}, {}, counts);
}

Rgb DirectLighting::irradiance(const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon, const LightSelection& selection,
                               DirectLightingCounts* counts) const {
  if (exact()) return irradiance(x, n, caster, epsilon, counts);
  return ward(x, n, caster, epsilon, selection.kept, selection.dropped, selection.droppedBound, counts);
}

Rgb DirectLighting::ward(const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon, std::span<const std::uint32_t> lights,
                         std::span<const std::uint32_t> dropped, const Rgb& droppedBound, DirectLightingCounts* counts) const {
  thread_local std::vector<Candidate> heap;
  heap.clear();
  Rgb total;
  auto evaluate = [&](std::span<const std::uint32_t> which) {
    for (std::uint32_t l : which) {
      const Rgb el = contribution(l, x, n);
      if (!(el.maxComponent() > 0)) continue;
      total += el;
      heap.push_back({el[0] + el[1] + el[2], l, el});
    }
  };
  evaluate(lights);
  // The dropped lights stay dropped where their bound is within τ/2 of what the kept ones give
  // here (so within τ/2 of U); then Ward's testing gets the other half. Else they are evaluated,
  // and Ward's testing gets all of τ.
  double tolerance = tolerance_;
  if (!dropped.empty()) {
    const Rgb allowed = total * (0.5 * tolerance_);
    if (droppedBound[0] <= allowed[0] && droppedBound[1] <= allowed[1] && droppedBound[2] <= allowed[2])
      tolerance = 0.5 * tolerance_;
    else
      evaluate(dropped);
  }
  if (counts) ++counts->points, counts->lightsReaching += heap.size();
  if (heap.empty()) return {};
  // The untested remainder, in each channel; the rays go out in decreasing order of E_l (a heap:
  // only the lights tested are ordered, the remainder never is).
  std::make_heap(heap.begin(), heap.end());
  Rgb remainder = total, tested, visible;
  const Rgb allowed = total * tolerance;
  auto within = [&] { return remainder[0] <= allowed[0] && remainder[1] <= allowed[1] && remainder[2] <= allowed[2]; };
  std::size_t untested = heap.size();
  while (untested > 0 && !within()) {
    std::pop_heap(heap.begin(), heap.begin() + static_cast<std::ptrdiff_t>(untested));
    const Candidate& c = heap[--untested];
    tested += c.e;
    remainder -= c.e;
    if (counts) ++counts->shadowRays;
    if (!prepared_[c.light].fast && lights_[c.light].kind != LightKind::Directional) {
      // Another kind (a luminaire, whose opening may be several sources) traces its own rays:
      // its shadowed irradiance, between 0 and c.e, is what the bound needs.
      visible += lambert::irradiance(lights_[c.light], x, n, caster, epsilon, metresPerUnit_);
    } else if (!occluded(lights_[c.light], x, n, caster, epsilon)) {
      visible += c.e;
    }
  }
  if (untested == 0) return visible;
  // The remainder, summed afresh from the untested lights (subtraction leaves rounding behind),
  // weighted by the tested lights' visible fraction per channel.
  Rgb rest;
  for (std::size_t k = 0; k < untested; ++k) rest += heap[k].e;
  Rgb e = visible;
  for (int ch = 0; ch < 3; ++ch)
    if (tested[ch] > 0) e[ch] += rest[ch] * (visible[ch] / tested[ch]);
  return e;
}

void patchIrradiance(const Mesh& mesh, const RayCaster& caster, const DirectLighting& lighting, const DirectLightOptions& options,
                     double epsilon, std::span<const std::uint32_t> patches, std::vector<Rgb>& irradiance, DirectLightingCounts* counts) {
  LAMBERT_CHECK(irradiance.size() == mesh.numPatches());
  const int samples = std::max(options.samplesPerPatch, 1);
  std::mutex countsMutex;
  if (patches.empty()) return;
  // As core/parallel.h's parallelFor, by ranges, so that each adds its counts once.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, patches.size(), 16), [&](const tbb::blocked_range<std::size_t>& range) {
    DirectLightingCounts local;
    LightSelection selection;
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const std::uint32_t i = patches[k];
      const Patch& patch = mesh.patches[i];
      const PatchCorners corners = mesh.corners(i);
      // The points of lights.cpp's meanPatchIrradiance: the same generator, stream and scramble.
      Pcg32 rng(options.seed, i);
      const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
      // The lights this patch needs, chosen once for its bounding sphere (DirectLighting::select).
      double radius = 0;
      for (const Vec3& c : corners) radius = std::fmax(radius, length(c - patch.centroid));
      lighting.select(patch.centroid, radius * (1 + 1e-9), patch.normal, selection);
      Rgb sum;
      for (int s = 0; s < samples; ++s) {
        auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(s), su, sv);
        sum += lighting.irradiance(sampleConvexPolygon(corners, u, v), patch.normal, caster, epsilon, selection, counts ? &local : nullptr);
      }
      irradiance[i] = sum / samples;
    }
    if (counts) {
      const std::lock_guard<std::mutex> lock(countsMutex);
      counts->add(local);
    }
  });
}

}  // namespace lambert
