#include "lambert/design/daylight_coefficients.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

#include "lambert/core/parallel.h"
#include "lambert/core/photometric.h"
#include "lambert/core/progress.h"
#include "lambert/core/timer.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {
namespace {

// A hemisphere ray of a sensor that met the front of a vertex-mesh patch: where, so that any
// basis's radiosity can be read there.
struct SensorHit {
  std::uint32_t patch = 0;
  Vec3 point;
  Vec3 normal;            // the patch's front
  double albedoLuminance;  // its ρ's luminance (Rec. 709 weights)
};

// Visibility of the sky along directions from `origin`, as light/lights.h's sky estimate traces it.
auto skyVisibleFrom(const RayCaster& caster, const Vec3& origin) {
  return [&caster, origin](std::span<const Vec3> directions, std::span<bool> seen) {
    thread_local std::vector<Ray> rays;
    rays.clear();
    for (const Vec3& w : directions) rays.push_back(Ray{origin, w, 0, INFINITY});
    caster.occluded(rays, seen);
    for (bool& s : seen) s = !s;
  };
}

}  // namespace

Result<DaylightCoefficients> computeDaylightCoefficients(const Scene& scene, std::span<const CalculationPoint> sensors,
                                                         std::span<const Vec3> sunDirections, const DaylightCoefficientOptions& options,
                                                         const RadiosityOptions& engineOptions) {
  const Timer timer;
  if (options.skySubdivisions < 1 || options.skySubdivisions > 8) return Error{"the sky's subdivision (MF) must be 1 to 8"};
  if (options.sunSubdivisions < 1 || options.sunSubdivisions > 16) return Error{"the basis suns' subdivision (MF) must be 1 to 16"};
  if (options.skyDirections < 1 || options.indirectRays < 1 || options.sunReflectionRays < 1)
    return Error{"the sky directions, indirect rays and sun reflection rays must be at least 1"};
  for (std::size_t s = 0; s < sensors.size(); ++s)
    if (!(length(sensors[s].normal) > 0) || !std::isfinite(sensors[s].position.x + sensors[s].position.y + sensors[s].position.z))
      return Error{"sensor " + std::to_string(s) + ": its position is not finite or its normal is zero"};
  Result<SkyPatches> sky = SkyPatches::reinhart(options.skySubdivisions, options.north);
  if (!sky) return sky.error();
  if (options.directSkySubdivisions < options.skySubdivisions || options.directSkySubdivisions > 16)
    return Error{"the sky component's subdivision (MF) must be at least the sky's and at most 16"};
  Result<SkyPatches> directSky = SkyPatches::reinhart(options.directSkySubdivisions, options.north);
  if (!directSky) return directSky.error();
  Result<SkyPatches> sunPatches = SkyPatches::reinhart(options.sunSubdivisions, options.north);
  if (!sunPatches) return sunPatches.error();

  // The scene lit by daylight alone, meshed and linked under a uniform sky (every direction above
  // the horizon alike: the mesh follows the openings, not one sky's bright side).
  Scene daylit = scene;
  daylit.lights.clear();
  for (Surface& surface : daylit.surfaces) surface.emittedRadiance = {};
  Light uniform;
  uniform.name = "uniform sky (the daylight coefficients' meshing)";
  uniform.kind = LightKind::Sky;
  uniform.sky = std::make_shared<SkyModel>(SkyModel::cieStandard(5, 0, 90, 1.0, options.north).value().withHorizontalIlluminance(10000));
  uniform.skyDirections = options.skyDirections;
  daylit.lights.push_back(uniform);
  Result<std::unique_ptr<Radiosity>> engine = Radiosity::create(std::move(daylit), engineOptions);
  if (!engine) return engine.error();
  if (Result<SolveReport> solved = (*engine)->solve(); !solved) return solved.error();
  const SolutionView& view = (*engine)->solution();
  const Mesh& mesh = view.mesh();
  const RayCaster& caster = view.caster();
  const std::uint64_t raysBefore = caster.raysCast();
  const double epsilon = rayEpsilon(mesh);
  const std::size_t patches = static_cast<std::size_t>(sky->count()), elements = mesh.numPatches(), n = sensors.size();

  DaylightCoefficients out;
  out.sky = *sky;
  out.directSky = *directSky;
  const std::size_t directPatches = static_cast<std::size_t>(directSky->count());
  out.sunPatches = *sunPatches;
  out.sensors = n;

  // 1. The elements' sky coefficients (at their centroids, as the sky light injects) and the
  // sensors' (following edges, as the meter measures).
  std::vector<float> elementSky(elements * patches);
  {
    Progress progress("sky coefficients", elements + n, options.showProgress);
    parallelFor(0, elements, [&](std::size_t i) {
      thread_local std::vector<double> bins;
      bins.resize(patches);
      const Patch& element = mesh.patches[i];
      skyPatchIlluminance(*sky, element.normal, options.skyDirections, skyVisibleFrom(caster, element.centroid + element.normal * epsilon),
                          SkyEdges::Cells, bins);
      std::copy(bins.begin(), bins.end(), elementSky.begin() + static_cast<std::ptrdiff_t>(i * patches));
      progress.advance();
    }, 16);
    out.skyDirect.resize(n * directPatches);
    parallelFor(0, n, [&](std::size_t s) {
      thread_local std::vector<double> bins;
      bins.resize(directPatches);
      const Vec3 normal = normalize(sensors[s].normal);
      skyPatchIlluminance(*directSky, normal, options.skyDirections, skyVisibleFrom(caster, sensors[s].position + normal * epsilon),
                          SkyEdges::Traced, bins);
      std::copy(bins.begin(), bins.end(), out.skyDirect.begin() + static_cast<std::ptrdiff_t>(s * directPatches));
      progress.advance();
    });
    progress.finish();
  }

  // The sensors' hemisphere rays through the vertex mesh, once: the meter's directions, and more
  // of them for the sun's first reflection (a small bright sun patch: 256 rays left sensors beside
  // one off by a factor of three against the path tracer).
  const Mesh& vertexMesh = view.vertexMesh();
  const std::unique_ptr<RayCaster> vertexCaster = makeEmbreeRayCaster(vertexMesh);
  const double vertexEpsilon = rayEpsilon(vertexMesh);
  auto hemisphereHits = [&](int rays) {
    const std::vector<Vec3> directions = cosineDirections(rays, options.seed);
    std::vector<std::vector<SensorHit>> hitsOf(n);
    parallelFor(0, n, [&](std::size_t s) {
      const Vec3 normal = normalize(sensors[s].normal);
      const Vec3 origin = sensors[s].position + normal * vertexEpsilon;
      Vec3 tangent, bitangent;
      orthonormalBasis(normal, tangent, bitangent);
      std::vector<Ray> ray(directions.size());
      std::vector<std::optional<RayHit>> hits(directions.size());
      for (std::size_t k = 0; k < directions.size(); ++k)
        ray[k] = Ray{origin, tangent * directions[k].x + bitangent * directions[k].y + normal * directions[k].z, 0, INFINITY};
      vertexCaster->intersect(ray, hits);
      for (std::size_t k = 0; k < directions.size(); ++k)
        if (hits[k] && hits[k]->frontFace) {
          const std::uint32_t patch = hits[k]->patch;
          hitsOf[s].push_back({patch, origin + ray[k].direction * hits[k]->t, vertexMesh.patches[patch].normal,
                               view.vertexMeshAlbedo()[patch].luminance()});
        }
    });
    return std::make_pair(std::move(hitsOf), static_cast<double>(directions.size()));
  };
  // (Named variables, not structured bindings: the lambdas below capture them, which clang 14 refuses.)
  const auto hemisphere = hemisphereHits(options.indirectRays);
  const auto sunHemisphere = hemisphereHits(options.sunReflectionRays);
  const std::vector<std::vector<SensorHit>>& hitsOf = hemisphere.first;
  const std::vector<std::vector<SensorHit>>& sunHitsOf = sunHemisphere.first;
  const double rayCount = hemisphere.second, sunRayCount = sunHemisphere.second;

  // 2–3. Per basis: B from its injected light, then the sensors' interreflected lux.
  const std::vector<Rgb>& albedo = view.albedo();
  std::vector<double> indirectLux(n);
  // The interreflected lux at every sensor when the elements receive `irradiance` (W/m²); without
  // its first reflection (the light the sensor sees reflected straight from where it lands) where
  // that is traced apart.
  auto interreflected = [&](const std::vector<Rgb>& irradiance, bool withFirstReflection) {
    std::vector<Rgb> injected(elements);
    for (std::size_t i = 0; i < elements; ++i) injected[i] = albedo[i] * irradiance[i];
    std::vector<Rgb> radiosity = radiosityFromInjected(view, injected);
    if (!withFirstReflection)
      for (std::size_t i = 0; i < elements; ++i) radiosity[i] -= injected[i];
    const PatchInterpolation reflected(vertexMesh, view.vertexValues(radiosity));
    parallelFor(0, n, [&](std::size_t s) {
      Rgb sum;
      for (const SensorHit& hit : hitsOf[s]) sum += reflected.at(hit.patch, hit.point);
      indirectLux[s] = illuminanceLux(sum / rayCount);
    });
  };

  // The basis suns: the centres of the sun patches that interpolate one of the suns asked for.
  std::map<int, int> basisOfPatch;
  out.basisSunOf.assign(4 * sunDirections.size(), -1);
  out.basisSunWeight.assign(4 * sunDirections.size(), 0.0f);
  for (std::size_t h = 0; h < sunDirections.size(); ++h) {
    const SkyPatches::Interpolation stencil = sunPatches->interpolation(sunDirections[h]);
    for (int k = 0; k < 4; ++k) {
      const int p = stencil.patch[k];
      if (p < 0) continue;
      auto [at, inserted] = basisOfPatch.try_emplace(p, static_cast<int>(out.basisSunPatch.size()));
      if (inserted) out.basisSunPatch.push_back(p);
      out.basisSunOf[4 * h + k] = at->second;
      out.basisSunWeight[4 * h + k] = static_cast<float>(stencil.weight[k]);
    }
  }
  const std::size_t suns = out.basisSunPatch.size();

  out.skyIndirect.assign(n * patches, 0.0f);
  out.sunIndirect.assign(n * suns, 0.0f);
  std::vector<Rgb> irradiance(elements);
  Progress progress("daylight coefficients", patches + suns, options.showProgress);
  for (std::size_t p = 0; p < patches; ++p) {
    for (std::size_t i = 0; i < elements; ++i) irradiance[i] = Rgb{1, 1, 1} * (elementSky[i * patches + p] / kLumensPerWatt);
    interreflected(irradiance, true);
    for (std::size_t s = 0; s < n; ++s) out.skyIndirect[s * patches + p] = static_cast<float>(indirectLux[s]);
    progress.advance();
  }
  for (std::size_t k = 0; k < suns; ++k) {
    Light sun;
    sun.kind = LightKind::Directional;
    sun.direction = -sunPatches->centre(out.basisSunPatch[k]);
    sun.irradiance = Rgb{1, 1, 1} / kLumensPerWatt;  // 1 lux, normal to the sun
    irradiance = patchIrradiance(mesh, caster, sun, scene.metresPerUnit, engineOptions.directLight);
    interreflected(irradiance, false);
    for (std::size_t s = 0; s < n; ++s) out.sunIndirect[s * suns + k] = static_cast<float>(indirectLux[s]);
    progress.advance();
  }
  progress.finish();

  // Each sun's direct light at the sensors, exactly (a shadow ray toward it), and its first
  // reflection, the sunlit surfaces the sensors' hemisphere rays meet (a shadow ray from each hit):
  // a sun patch is sharp, and the elements, meshed for the sky, would blur it.
  out.sunDirect.assign(sunDirections.size() * n, 0.0f);
  out.sunReflected.assign(sunDirections.size() * n, 0.0f);
  {
    Progress progress("sun", sunDirections.size(), options.showProgress);
    parallelFor(0, sunDirections.size(), [&](std::size_t h) {
      progress.advance();
      if (!out.sunInSky(h)) return;
      const Vec3 toSun = normalize(sunDirections[h]);
      thread_local std::vector<Ray> rays;
      thread_local std::vector<double> weights;
      thread_local std::unique_ptr<bool[]> occluded;
      thread_local std::size_t capacity = 0;
      for (std::size_t s = 0; s < n; ++s) {
        const Vec3 normal = normalize(sensors[s].normal);
        const double cosine = dot(normal, toSun);
        if (cosine > 0 && !caster.occluded(Ray{sensors[s].position + normal * epsilon, toSun, 0, INFINITY}))
          out.sunDirect[h * n + s] = static_cast<float>(cosine);
        rays.clear();
        weights.clear();
        for (const SensorHit& hit : sunHitsOf[s]) {
          const double c = dot(hit.normal, toSun);
          if (c <= 0 || hit.albedoLuminance <= 0) continue;
          rays.push_back(Ray{hit.point + hit.normal * epsilon, toSun, 0, INFINITY});
          weights.push_back(c * hit.albedoLuminance);
        }
        if (rays.empty()) continue;
        if (capacity < rays.size()) capacity = rays.size(), occluded = std::make_unique<bool[]>(capacity);
        caster.occluded(rays, std::span<bool>(occluded.get(), rays.size()));
        double sum = 0;
        for (std::size_t k = 0; k < rays.size(); ++k)
          if (!occluded[k]) sum += weights[k];
        out.sunReflected[h * n + s] = static_cast<float>(sum / sunRayCount);
      }
    }, 16);
    progress.finish();
  }
  out.raysCast = caster.raysCast() - raysBefore + vertexCaster->raysCast();
  out.seconds = timer.seconds();
  return out;
}

}  // namespace lambert
