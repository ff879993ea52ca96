#include "lambert/light/perez_sky.h"

#include <algorithm>
#include <cmath>

namespace lambert {
namespace {

constexpr double kRadians = kPi / 180;
constexpr double kSolarConstant = 1367;  // W/m², as gendaymtx and gendaylit

// Perez, Seals and Michalsky 1993, table 1: for each ε bin, the four x1..x4 of a, b, c, d and e.
constexpr double kCoefficients[8][5][4] = {
    {{1.3525, -0.2576, -0.2690, -1.4366}, {-0.7670, 0.0007, 1.2734, -0.1233}, {2.8000, 0.6004, 1.2375, 1.0000},
     {1.8734, 0.6297, 0.9738, 0.2809}, {0.0356, -0.1246, -0.5718, 0.9938}},
    {{-1.2219, -0.7730, 1.4148, 1.1016}, {-0.2054, 0.0367, -3.9128, 0.9156}, {6.9750, 0.1774, 6.4477, -0.1239},
     {-1.5798, -0.5081, -1.7812, 0.1080}, {0.2624, 0.0672, -0.2190, -0.4285}},
    {{-1.1000, -0.2515, 0.8952, 0.0156}, {0.2782, -0.1812, -4.5000, 1.1766}, {24.7219, -13.0812, -37.7000, 34.8438},
     {-5.0000, 1.5218, 3.9229, -2.6204}, {-0.0156, 0.1597, 0.4199, -0.5562}},
    {{-0.5484, -0.6654, -0.2672, 0.7117}, {0.7234, -0.6219, -5.6812, 2.6297}, {33.3389, -18.3000, -62.2500, 52.0781},
     {-3.5000, 0.0016, 1.1477, 0.1062}, {0.4659, -0.3296, -0.0876, -0.0329}},
    {{-0.6000, -0.3566, -2.5000, 2.3250}, {0.2937, 0.0496, -5.6812, 1.8415}, {21.0000, -4.7656, -21.5906, 7.2492},
     {-3.5000, -0.1554, 1.4062, 0.3988}, {0.0032, 0.0766, -0.0656, -0.1294}},
    {{-1.0156, -0.3670, 1.0078, 1.4051}, {0.2875, -0.5328, -3.8500, 3.3750}, {14.0000, -0.9999, -7.1406, 7.5469},
     {-3.4000, -0.1078, -1.0750, 1.5702}, {-0.0672, 0.4016, 0.3017, -0.4844}},
    {{-1.0000, 0.0211, 0.5025, -0.5119}, {-0.3000, 0.1922, 0.7023, -1.6317}, {19.0000, -5.0000, 1.2438, -1.9094},
     {-4.0000, 0.0250, 0.3844, 0.2656}, {1.0468, -0.3788, -2.4517, 1.4656}},
    {{-1.0500, 0.0289, 0.4260, 0.3590}, {-0.3250, 0.1156, 0.7781, 0.0025}, {31.0625, -14.5000, -46.1148, 55.3750},
     {-7.2312, 0.4050, 13.3500, 0.6234}, {1.5000, -0.6426, 1.8564, 0.5636}},
};

// The upper ends of bins 1–7 (Perez et al. 1990, table 1).
constexpr double kBinUpper[7] = {1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200};

// Perez et al. 1990, table 4: (a, b, c, d) of the diffuse (eq. 7) and direct (eq. 8) efficacies.
constexpr double kDiffuseEfficacy[8][4] = {{97.24, -0.46, 12.00, -8.91},   {107.22, 1.15, 0.59, -3.95},  {104.97, 2.96, -5.53, -8.77},
                                           {102.39, 5.59, -13.95, -13.90}, {100.71, 5.94, -22.75, -23.74}, {106.42, 3.83, -36.15, -28.83},
                                           {141.88, 1.90, -53.24, -14.03}, {152.23, 0.35, -45.27, -7.98}};
constexpr double kDirectEfficacy[8][4] = {{57.20, -4.55, -2.98, 117.12}, {98.99, -3.46, -1.21, 12.38},  {109.83, -4.90, -1.71, -8.81},
                                          {110.34, -5.84, -1.99, -4.56}, {106.36, -3.97, -1.75, -6.16}, {107.19, -1.25, -1.51, -26.73},
                                          {105.75, 0.77, -1.26, -34.44}, {101.18, 1.58, -1.10, -8.29}};

}  // namespace

double perezAirMass(double sunZenithRadians) {
  const double degrees = std::min(sunZenithRadians / kRadians, 90.0);
  return 1 / (std::cos(degrees * kRadians) + 0.15 * std::pow(93.885 - degrees, -1.253));
}

double extraterrestrialIrradiance(int dayOfYear) {
  const double g = 2 * kPi * (dayOfYear - 1) / 365;
  return kSolarConstant *
         (1.00011 + 0.034221 * std::cos(g) + 0.00128 * std::sin(g) + 0.000719 * std::cos(2 * g) + 0.000077 * std::sin(2 * g));
}

double perezModelZenithRadians(double sunElevationDegrees) { return std::clamp(90 - sunElevationDegrees, 3.0, 90.0) * kRadians; }

double perezSkyClearness(double diffuseHorizontalIrradiance, double directNormalIrradiance, double sunZenithRadians) {
  const double kz3 = 1.041 * sunZenithRadians * sunZenithRadians * sunZenithRadians;
  return ((diffuseHorizontalIrradiance + directNormalIrradiance) / diffuseHorizontalIrradiance + kz3) / (1 + kz3);
}

double perezSkyBrightness(double diffuseHorizontalIrradiance, double sunZenithRadians, int dayOfYear) {
  return diffuseHorizontalIrradiance * perezAirMass(sunZenithRadians) / extraterrestrialIrradiance(dayOfYear);
}

int perezClearnessBin(double clearness) {
  int bin = 1;
  while (bin <= 7 && clearness >= kBinUpper[bin - 1]) ++bin;
  return bin;
}

PerezCoefficients perezCoefficients(double clearness, double brightness, double sunZenithRadians) {
  PerezCoefficients out;
  out.clearness = std::clamp(clearness, 1.0, 11.9);
  out.brightness = std::max(brightness, 0.01);
  out.bin = perezClearnessBin(out.clearness);
  out.sunZenithRadians = sunZenithRadians;
  const double z = sunZenithRadians;
  const double delta = out.clearness > 1.065 && out.clearness < 2.8 ? std::max(out.brightness, 0.2) : out.brightness;
  const auto& x = kCoefficients[out.bin - 1];
  auto linear = [&](int i) { return x[i][0] + x[i][1] * z + delta * (x[i][2] + x[i][3] * z); };
  out.a = linear(0);
  out.b = linear(1);
  out.e = linear(4);
  if (out.bin == 1) {
    out.c = std::exp(std::pow(delta * (x[2][0] + x[2][1] * z), x[2][2])) - x[2][3];
    out.d = -std::exp(delta * (x[3][0] + x[3][1] * z)) + x[3][2] + delta * x[3][3];
  } else {
    out.c = linear(2);
    out.d = linear(3);
  }
  return out;
}

PerezCoefficients perezSkyCondition(double diffuseHorizontalIrradiance, double directNormalIrradiance, double sunElevationDegrees,
                                    int dayOfYear) {
  const double z = perezModelZenithRadians(sunElevationDegrees);
  return perezCoefficients(perezSkyClearness(diffuseHorizontalIrradiance, directNormalIrradiance, z),
                           perezSkyBrightness(diffuseHorizontalIrradiance, z, dayOfYear), z);
}

double precipitableWaterCentimetres(double dewPointCelsius) { return std::exp(0.07 * dewPointCelsius - 0.075); }

double perezDiffuseEfficacy(const PerezCoefficients& sky, double precipitableWaterCm) {
  const auto& k = kDiffuseEfficacy[sky.bin - 1];
  return k[0] + k[1] * precipitableWaterCm + k[2] * std::cos(sky.sunZenithRadians) + k[3] * std::log(sky.brightness);
}

double perezDirectEfficacy(const PerezCoefficients& sky, double precipitableWaterCm) {
  const auto& k = kDirectEfficacy[sky.bin - 1];
  return std::max(0.0, k[0] + k[1] * precipitableWaterCm + k[2] * std::exp(5.73 * sky.sunZenithRadians - 5) + k[3] * sky.brightness);
}

Result<PerezHourSky> perezSkyForHour(const WeatherData& weather, const WeatherHour& hour, const Vec3& north) {
  PerezHourSky out;
  out.sun = weatherSunPosition(weather.location, hour);
  out.sunInSky = out.sun.elevationDegrees() > -kSunDiameterDegrees / 2;
  out.sunIlluminanceLux = out.sunInSky ? hour.directNormalIlluminance : 0;
  if (!(hour.diffuseHorizontalIlluminance > 0) || !(hour.diffuseHorizontalIrradiance > 0)) return out;
  out.coefficients = perezSkyCondition(hour.diffuseHorizontalIrradiance, hour.directNormalIrradiance, out.sun.elevationDegrees(),
                                       hour.dayOfYear());
  // The sky's sun is the model's: on the horizon in twilight, 3° from the zenith at most.
  const double modelElevation = 90 - out.coefficients.sunZenithRadians / kRadians;
  Result<SkyModel> sky = SkyModel::perez(out.coefficients, out.sun.azimuthDegrees, modelElevation, 1, north);
  if (!sky) {
    const std::string where = weather.path.empty() ? std::string() : weather.path + ":" + std::to_string(hour.line) + ": ";
    return Error{where + std::to_string(hour.month) + "/" + std::to_string(hour.day) + " hour " + std::to_string(hour.hour) + ": " +
                 sky.error().message};
  }
  out.sky = sky->withHorizontalIlluminance(hour.diffuseHorizontalIlluminance);
  return out;
}

}  // namespace lambert
