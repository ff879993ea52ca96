#pragma once
// Daylight coefficients (Tregenza and Waters 1983, "Daylight coefficients", Lighting Research &
// Technology 15(2) 65–71): light transport is linear in the sky, so the illuminance at a sensor
// under any sky is Σ_p C_p L_p over the sky's patches p (light/sky_patches.h), L_p the patch's mean
// luminance, C_p what the patch alone gives at 1 cd/m², direct and interreflected. Computed once,
// the coefficients give every hour of a year by one product (design/annual_daylight.h). The sun is
// split as Radiance's five-phase method splits it (McNeil 2013, "The Five-Phase Method for
// Simulating Complex Fenestration with Radiance"): its direct light at each sensor is traced exactly
// for each hour's sun (a shadow ray: a sharp sun patch where it falls), and so is its first
// reflection (each sensor's fixed hemisphere rays, a shadow ray from each sunward hit toward that
// hour's sun: a sun patch on a wall beside a desk is sharp too); only its further reflections go
// through coefficients, of "basis suns" at the centres of the finer patches (MF:sunSubdivisions),
// each hour interpolated between the four centres around its sun.
//
// How, in one radiosity engine (engine/radiosity.h) meshed and linked once under a uniform sky:
//  1. each element's and each sensor's sky coefficients in one pass over the hemisphere's
//     directions, each visible sample binned to its patch (skyPatchIlluminance: the sampling the
//     sky light uses, the elements' at their centroids, the sensors' following edges as the
//     illuminance meter's do);
//  2. per patch and per basis sun, the element radiosity B = ρE_direct + ρFB it brings, solved
//     over the engine's transport (the links the engine refined), each a fresh Gauss–Seidel solve
//     to the engine's tolerance, the engine's own solution untouched;
//  3. at each sensor, the interreflected light as the illuminance meter (design/illuminance.h)
//     takes it, the same cosine-weighted directions through the vertex mesh, each hit reading the
//     basis's B interpolated at the hit (the meter's ρE); fixed per sensor, so each basis costs an
//     interpolation, not rays.
// Cost: one sky's injection (the element pass) and a meter's rays per sensor, then per basis a
// solve and an interpolation (the 145 patches and 750 basis suns of a 3,600-element office in about
// three seconds), and per sun a shadow ray per sensor and per sunward hit of its sunReflectionRays.
// Failure modes: the patches' luminance is taken as uniform over each (the sky's gradation within
// a 12° patch; finer subdivisions for sharper skies); the sun's further reflections are
// interpolated between basis suns; its first reflection is a quadrature of a sharp patch by fixed
// directions (±20–30% where the patch fills 1% of a sensor's view); what the engine's mesh cannot
// resolve (it is refined for a uniform sky, not for each sun's patch) is averaged over its elements.
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/design/illuminance.h"
#include "lambert/light/sky_patches.h"
#include "lambert/method/options.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct DaylightCoefficientOptions {
  Vec3 north{0, 0, -1};      // the scene's north (a horizontal direction), where the patches are counted from
  int skySubdivisions = 1;   // Reinhart's MF of the sky patches the interreflected light is solved for: 1 (Tregenza's 145), 2 (577), 4 (2305)
  int directSkySubdivisions = 4;  // MF of the finer patches the sensors' direct sky light (the sky component) is counted in
  int sunSubdivisions = 4;   // MF of the patches whose centres are the basis suns
  int skyDirections = kDefaultSkyDirections;  // directions per sky estimate, at elements and sensors
  int indirectRays = 256;    // hemisphere directions per sensor (the meter's indirectRays)
  int sunReflectionRays = 2048;  // hemisphere directions per sensor for each sun's first reflection (a shadow ray per sunward hit, per hour)
  std::uint64_t seed = 1;
  bool showProgress = false;
};

struct DaylightCoefficients {
  SkyPatches sky;         // the patches of the interreflected sky light
  SkyPatches directSky;   // the finer patches of the sky component
  SkyPatches sunPatches;  // the patches whose centres the basis suns stand at
  std::size_t sensors = 0;
  // Lux at the sensor per cd/m² over a patch, sensor-major: the sky component (sensors × directSky
  // patches: the direct light of a circumsolar sky through a window varies within a 12° patch) and
  // the interreflected light (sensors × sky patches).
  std::vector<float> skyDirect;
  std::vector<float> skyIndirect;
  // The basis suns: their patch of sunPatches, and sensors × basis suns (sensor-major): the lux at
  // the sensor per lux of direct normal illuminance from the patch's centre, reflected twice or
  // more (the first reflection is traced for each sun, below).
  std::vector<int> basisSunPatch;
  std::vector<float> sunIndirect;
  // Per sun asked for (the hours' suns, in order), four slots each: the basis suns that interpolate
  // it (SkyPatches::interpolation over sunPatches' centres; −1 unused, all −1 below the horizon) and
  // their weights. The light through a window changes fast with a high sun's altitude (as its
  // cosine to the glass: 8.6% a degree and a half at 72°), which the nearest centre alone misses.
  std::vector<int> basisSunOf;
  std::vector<float> basisSunWeight;
  // Per sun, suns × sensors (sun-major), per lux of direct normal illuminance: the direct lux at the
  // sensor, max(0, n·s) × visible, and the lux reflected to it once, (1/N) Σ over its hemisphere
  // rays' hits of ρ max(0, n_hit·s) × the hit visible from the sun.
  std::vector<float> sunDirect;
  std::vector<float> sunReflected;

  bool sunInSky(std::size_t sun) const { return basisSunOf[4 * sun] >= 0; }
  // The sun's light at a sensor beyond its direct light, per lux of direct normal illuminance:
  // its first reflection and its further ones, interpolated between the basis suns.
  double sunInterreflected(std::size_t sun, std::size_t sensor) const {
    double lux = sunReflected[sun * sensors + sensor];
    const std::size_t basis = basisSunPatch.size();
    for (std::size_t k = 4 * sun; k < 4 * sun + 4; ++k)
      if (basisSunOf[k] >= 0) lux += basisSunWeight[k] * sunIndirect[sensor * basis + static_cast<std::size_t>(basisSunOf[k])];
    return lux;
  }
  double seconds = 0;  // the whole computation
  std::uint64_t raysCast = 0;
};

// The coefficients of `sensors` in `scene` lit by daylight alone (its lights and emitting surfaces
// left out), for the suns toward `sunDirections` (unit, scene frame; below the horizon they give
// nothing), the engine made with engineOptions (its method, tolerance, link cache). An Error for
// options out of range or an engine that cannot be made.
Result<DaylightCoefficients> computeDaylightCoefficients(const Scene& scene, std::span<const CalculationPoint> sensors,
                                                         std::span<const Vec3> sunDirections, const DaylightCoefficientOptions& options,
                                                         const RadiosityOptions& engineOptions);

}  // namespace lambert
