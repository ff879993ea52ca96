#pragma once
// The Perez all-weather sky for an hour of weather, as Radiance's gendaymtx and gendaylit make it.
//
//  - Sky clearness ε and brightness Δ (Perez, Ineichen, Seals, Michalsky and Stewart, "Modeling
//    daylight availability and irradiance components from direct and global irradiance", Solar
//    Energy 44(5), 1990, pp. 271–289, eqs. 1 and 2): ε = ((Dh + In)/Dh + κZ³)/(1 + κZ³), κ = 1.041
//    (Z in radians), Δ = Dh·m/I0, with Dh the diffuse horizontal and In the direct normal irradiance,
//    m the relative air mass (Kasten 1966, as gendaymtx: 1/(cos Z + 0.15 (93.885 − Z°)^−1.253)) and I0
//    the extraterrestrial normal irradiance, 1367 W/m² × the orbit's eccentricity correction for
//    the day (Spencer 1971's series, as gendaymtx). ε falls into one of 8 bins (1990, table 1).
//  - The five coefficients a–e of the 1993 luminance distribution (Perez, Seals and Michalsky,
//    Solar Energy 50(3), 1993, pp. 235–245, table 1 and eqs. 6–8): x = x1 + x2·Z + Δ(x3 + x4·Z),
//    but in bin 1 c = exp((Δ(c1 + c2·Z))^c3) − c4 and d = −exp(Δ(d1 + d2·Z)) + d3 + Δ·d4.
//  - Luminous efficacies (1990, table 4, eqs. 7 and 8): diffuse a + b·W + c·cos Z + d·ln Δ, direct
//    max(0, a + b·W + c·exp(5.73 Z − 5) + d·Δ), lm/W, W the precipitable water in cm from the dew
//    point Td (1990, eq. 3, after Wright, Perez and Michalsky 1989): W = exp(0.07 Td − 0.075).
//
// Limits, as gendaymtx: the sun's zenith angle Z is taken within [3°, 90°] (a sun below the horizon,
// twilight, as on it; one within 3° of the zenith 3° from it, keeping the circumsolar peak off the
// zenith), ε ≤ 11.9 and Δ ≥ 0.01; for a–e, Δ ≥ 0.2 in 1.065 < ε < 2.8 (the paper's bins 2–4,
// where smaller Δ fall outside the data it was fitted to). Cost: a few exps per hour.
#include <optional>

#include "lambert/core/error.h"
#include "lambert/core/vec3.h"
#include "lambert/light/sky.h"
#include "lambert/light/weather.h"

namespace lambert {

// The sun's angular diameter (degrees) and so the elevation −0.2665° above which its disc shows
// (gendaymtx's test for a sun in the sky).
inline constexpr double kSunDiameterDegrees = 0.533;

// Relative optical air mass at a zenith angle (radians, ≤ 90°): Kasten 1966.
double perezAirMass(double sunZenithRadians);
// Extraterrestrial normal irradiance in W/m² on a day of the year (1–365): 1367 × eccentricity.
double extraterrestrialIrradiance(int dayOfYear);
// The sun's zenith angle the model uses: the true one limited to [3°, 90°].
double perezModelZenithRadians(double sunElevationDegrees);
// ε from diffuse horizontal and direct normal irradiance (W/m², diffuse > 0), unlimited.
double perezSkyClearness(double diffuseHorizontalIrradiance, double directNormalIrradiance, double sunZenithRadians);
// Δ, unlimited.
double perezSkyBrightness(double diffuseHorizontalIrradiance, double sunZenithRadians, int dayOfYear);
// The bin 1–8 of a clearness: [1, 1.065), [1.065, 1.23), [1.23, 1.5), [1.5, 1.95), [1.95, 2.8),
// [2.8, 4.5), [4.5, 6.2), [6.2, ∞) (below 1: bin 1).
int perezClearnessBin(double clearness);
// a–e for a clearness and brightness (limited as above) at a model zenith angle.
PerezCoefficients perezCoefficients(double clearness, double brightness, double sunZenithRadians);
// All of it from an hour's irradiances (W/m², diffuse > 0) and its sun.
PerezCoefficients perezSkyCondition(double diffuseHorizontalIrradiance, double directNormalIrradiance, double sunElevationDegrees,
                                    int dayOfYear);

// Atmospheric precipitable water in cm from the dew point in °C.
double precipitableWaterCentimetres(double dewPointCelsius);
// Luminous efficacies in lm/W of diffuse (horizontal) and direct (normal) light, for a sky
// condition (its bin, Δ and model zenith angle) and precipitable water.
double perezDiffuseEfficacy(const PerezCoefficients& sky, double precipitableWaterCm);
double perezDirectEfficacy(const PerezCoefficients& sky, double precipitableWaterCm);

// One hour's daylight: the Perez sky scaled to the hour's diffuse horizontal illuminance, and the
// sun.
struct PerezHourSky {
  // Empty when the hour has no diffuse light: diffuse horizontal illuminance or irradiance ≤ 0 (a
  // night hour; the irradiance is what ε and Δ divide by). Otherwise its horizontalIlluminance() is
  // the hour's diffuse horizontal illuminance. Twilight (diffuse light, the sun below the horizon)
  // has a sky, as in gendaymtx: the model's sun sits on the horizon at the sun's azimuth.
  std::optional<SkyModel> sky;
  PerezCoefficients coefficients;  // the hour's ε, Δ, bin, a–e (default when the sky is empty)
  SunPosition sun;                 // the true sun at the hour's middle (weatherSunPosition)
  bool sunInSky = false;           // its disc above the horizon: elevation > −kSunDiameterDegrees/2
  // The sun's illuminance on a plane facing it (the hour's direct normal illuminance, lux): 0 when
  // the sun is not in the sky (the direct light of such an hour, a file's error, is dropped).
  double sunIlluminanceLux = 0;
};

// The hour's sky and sun at the file's place. An error only for values SkyModel::perez refuses (not
// finite: the reader never gives them).
Result<PerezHourSky> perezSkyForHour(const WeatherData& weather, const WeatherHour& hour, const Vec3& north = {0, 0, -1});

}  // namespace lambert
