#pragma once
// A year of daylight at sensor points, hour by hour, from a weather file (load/epw.h): each hour's
// Perez all-weather sky and sun (light/perez_sky.h, as Radiance's gendaymtx makes them) through
// daylight coefficients computed once (design/daylight_coefficients.h):
//   E(s, h) = Σ_q D_sq L̄_q(h) + Σ_p I_sp L̄_p(h) + E_sun(h) · (direct_s(h) + reflected_s(h) + I☉_s,k(h))
// D the sky component over the finer patches q, I the interreflected sky over the coarse patches p,
// L̄ each patch's mean luminance that hour, E_sun the direct normal illuminance, and the sun's
// direct light and first reflection traced for its own position, its further reflections those of
// the basis sun k of its patch. Two products of matrices (sensors × patches by patches × hours,
// Eigen's), the sun's terms added per hour.
//
// The coefficients are kept on disk (cacheDirectory, file "daylight-<key>.ldc"): the key hashes the
// scene's geometry and materials, the sensors, the year's suns, every option they depend on and the
// sources that compute them (lambert's version and the digest of CMakeLists.txt's link sources),
// so another weather file at the same place reuses them only where its suns are the same.
// Cost: the coefficients (once), then about (patches + fine patches) × sensors × hours
// multiply-adds: 49 sensors × 8,760 h × 2,450 patches in a fraction of a second.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/design/daylight_coefficients.h"
#include "lambert/design/daylight_metrics.h"
#include "lambert/light/weather.h"

namespace lambert {

struct AnnualDaylightOptions {
  DaylightCoefficientOptions coefficients;
  std::string cacheDirectory;  // where the coefficients are kept; empty: computed every time
};

struct AnnualDaylight {
  AnnualIlluminance illuminance;  // per weather hour, per sensor (design/daylight_metrics.h)
  std::vector<float> skyLux;      // hours × sensors: the sky's part of totalLux (direct and interreflected)
  int daylightHours = 0;          // hours with a sky or a sun
  int sunHours = 0;               // hours with the sun in the sky and a direct normal illuminance
  bool coefficientsFromCache = false;
  double coefficientSeconds = 0;  // computing or reading the coefficients
  double hourlySeconds = 0;       // the skies, the products and the sun's terms
  std::size_t skyPatches = 0, directSkyPatches = 0, basisSuns = 0;
  std::uint64_t raysCast = 0;
};

// Every hour of `weather` at `sensors` of `scene` (its north: options.coefficients.north), daylight
// alone. Errors: the coefficients' (design/daylight_coefficients.h); a cache that cannot be read
// is a warning and recomputed, one that cannot be written a warning.
Result<AnnualDaylight> annualDaylight(const Scene& scene, std::span<const CalculationPoint> sensors, const WeatherData& weather,
                                      const AnnualDaylightOptions& options, const RadiosityOptions& engineOptions);

}  // namespace lambert
