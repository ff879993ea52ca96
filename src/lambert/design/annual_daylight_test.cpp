#include "lambert/design/annual_daylight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "lambert/light/perez_sky.h"
#include "lambert/light/sun.h"
#include "lambert/load/epw.h"
#include "lambert/load/scene_file.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

// The black shoebox: 4 × 4 × 3 m, ρ = 0 everywhere, a 1 × 1 m opening in the middle of its roof
// (x, z in [1.5, 2.5] at y = 3), and the test week's weather.
constexpr double kRoof = 3, kOpeningLo = 1.5, kOpeningHi = 2.5;
struct Shoebox {
  Scene scene;
  WeatherData weather;
};
Shoebox shoebox() {
  std::ostringstream json;
  json << R"({"version": 1, "name": "shoebox", "unit": "m", "materials": [{"name": "black", "albedo": [0, 0, 0]}], "surfaces": [)"
       << R"({"name": "floor", "material": "black", "vertices": [[0,0,0],[0,0,4],[4,0,4],[4,0,0]]},)"
       << R"({"name": "south", "material": "black", "vertices": [[0,0,4],[0,3,4],[4,3,4],[4,0,4]]},)"
       << R"({"name": "north", "material": "black", "vertices": [[0,0,0],[4,0,0],[4,3,0],[0,3,0]]},)"
       << R"({"name": "west", "material": "black", "vertices": [[0,0,0],[0,3,0],[0,3,4],[0,0,4]]},)"
       << R"({"name": "east", "material": "black", "vertices": [[4,0,0],[4,0,4],[4,3,4],[4,3,0]]},)"
       << R"({"name": "roof north", "material": "black", "vertices": [[0,3,0],[4,3,0],[4,3,1.5],[0,3,1.5]]},)"
       << R"({"name": "roof south", "material": "black", "vertices": [[0,3,2.5],[4,3,2.5],[4,3,4],[0,3,4]]},)"
       << R"({"name": "roof west", "material": "black", "vertices": [[0,3,1.5],[1.5,3,1.5],[1.5,3,2.5],[0,3,2.5]]},)"
       << R"({"name": "roof east", "material": "black", "vertices": [[2.5,3,1.5],[4,3,1.5],[4,3,2.5],[2.5,3,2.5]]}]})";
  const std::filesystem::path dir = testing::scratchDirectory("annual_daylight", "shoebox");
  const std::string path = (dir / "shoebox.json").string();
  std::ofstream(path) << json.str();
  return {loadScene(path).value(), readEpw(std::string(LAMBERT_SOURCE_DIR) + "/tests/weather/boulder-week.epw").value()};
}

// A black shoebox (4 × 4 × 3 m, every surface ρ = 0) lit through a 1 × 1 m opening in the middle of
// its roof: nothing is reflected, so each sensor's illuminance is the sky it sees through the opening
// plus the sun where the sun's ray passes through it, both integrable by hand. Each hour of the test
// week (tests/weather/boulder-week.epw, all seven kinds of sky) is integrated here over the opening,
// E = ∫ L(ω) cos θ dω = Σ L(x − p) h² / r⁴ ΔA on a 200 × 200 grid of the opening's plane (h its height
// above the sensor, r the distance), with the hour's Perez sky, and the sun added where its ray from
// the sensor crosses the opening. The year's computation (coefficients, patch luminances, products)
// must give the same hours within 3% (1 lx), and the same metrics.
TEST(AnnualDaylightTest, ABlackShoeboxUnderARoofOpeningIsItsSkyByQuadrature) {
  const double roof = kRoof, lo = kOpeningLo, hi = kOpeningHi;
  const Shoebox box = shoebox();
  const Scene* scene = &box.scene;
  const WeatherData* weather = &box.weather;
  const std::vector<CalculationPoint> sensors = {{{2, 0.8, 2}, {0, 1, 0}}, {{2.6, 0.8, 1.7}, {0, 1, 0}}, {{1, 0.8, 3}, {0, 1, 0}}, {{2, 0.8, 1.35}, {0, 1, 0}}};

  const Vec3 north{0, 0, -1};
  AnnualDaylightOptions options;
  Result<AnnualDaylight> year = annualDaylight(*scene, sensors, *weather, options, RadiosityOptions{});
  ASSERT_TRUE(year) << year.error().message;
  const std::size_t n = sensors.size(), hours = weather->hours.size();
  ASSERT_EQ(year->illuminance.totalLux.size(), hours * n);

  AnnualIlluminance expected;
  expected.sensors = n;
  expected.hours = year->illuminance.hours;
  expected.totalLux.assign(hours * n, 0.0f);
  expected.directSunLux.assign(hours * n, 0.0f);
  constexpr int kGrid = 200;
  const double cell = (hi - lo) / kGrid;
  double worst = 0;
  int sunlitHours = 0;
  for (std::size_t h = 0; h < hours; ++h) {
    const PerezHourSky hour = perezSkyForHour(*weather, weather->hours[h], north).value();
    for (std::size_t s = 0; s < n; ++s) {
      const Vec3 p = sensors[s].position;
      const double height = roof - p.y;
      double e = 0;
      if (hour.sky)
        for (int i = 0; i < kGrid; ++i)
          for (int j = 0; j < kGrid; ++j) {
            const Vec3 d{lo + (i + 0.5) * cell - p.x, height, lo + (j + 0.5) * cell - p.z};
            const double r2 = lengthSquared(d);
            e += hour.sky->luminance(d) * height * height / (r2 * r2) * cell * cell;
          }
      if (hour.sunInSky && hour.sunIlluminanceLux > 0) {
        const Vec3 toSun = skyDirection(hour.sun.azimuthDegrees, hour.sun.elevationDegrees(), north);
        if (toSun.y > 0) {
          const double t = height / toSun.y;
          const double x = p.x + toSun.x * t, z = p.z + toSun.z * t;
          if (x > lo && x < hi && z > lo && z < hi) {
            expected.directSunLux[h * n + s] = static_cast<float>(hour.sunIlluminanceLux * toSun.y);
            e += hour.sunIlluminanceLux * toSun.y;
            ++sunlitHours;
          }
        }
      }
      expected.totalLux[h * n + s] = static_cast<float>(e);
      const double got = year->illuminance.totalLux[h * n + s];
      EXPECT_NEAR(got, e, 0.03 * e + 1) << "hour " << h << " sensor " << s;
      if (e > 50) worst = std::max(worst, std::fabs(got / e - 1));
      EXPECT_NEAR(year->illuminance.directSunLux[h * n + s], expected.directSunLux[h * n + s], 1e-3 * expected.directSunLux[h * n + s] + 1e-3);
    }
  }
  EXPECT_GT(sunlitHours, 5);  // the noon sun (73° high in June) reaches the sensor 0.65 m north of the middle
  std::printf("shoebox: worst hour %.2f%% off the quadrature\n", 100 * worst);
  DaylightMetricsOptions metricsOptions;
  metricsOptions.firstOccupiedHour = 0, metricsOptions.lastOccupiedHour = 24;  // the week's every hour
  const DaylightMetrics byHand = daylightMetrics(expected, metricsOptions).value();
  const DaylightMetrics computed = daylightMetrics(year->illuminance, metricsOptions).value();
  for (std::size_t s = 0; s < n; ++s) {
    // One hour of the week is 1/168 = 0.6% of the hours: an hour at a threshold may fall either side.
    EXPECT_NEAR(computed.sensors[s].daylightAutonomy, byHand.sensors[s].daylightAutonomy, 1.2) << s;
    EXPECT_NEAR(computed.sensors[s].udiUseful, byHand.sensors[s].udiUseful, 1.2) << s;
    EXPECT_NEAR(computed.sensors[s].udiExceeded, byHand.sensors[s].udiExceeded, 1.2) << s;
    EXPECT_NEAR(computed.sensors[s].meanLux, byHand.sensors[s].meanLux, 0.02 * byHand.sensors[s].meanLux) << s;
    EXPECT_EQ(computed.sensors[s].sunlitHours, byHand.sensors[s].sunlitHours) << s;
  }
}

// The coefficients kept on disk give the same year bit for bit; a damaged file is a warning and
// computed again; another set of sensors does not read them.
TEST(AnnualDaylightTest, CachedCoefficientsGiveTheSameYearAndADamagedFileIsRecomputed) {
  const Shoebox box = shoebox();
  const std::vector<CalculationPoint> sensors = {{{2, 0.8, 2}, {0, 1, 0}}, {{2, 0.8, 1.35}, {0, 1, 0}}};
  const std::filesystem::path dir = testing::scratchDirectory("annual_daylight", "cache");
  std::filesystem::remove_all(dir);
  AnnualDaylightOptions options;
  options.cacheDirectory = dir.string();
  const AnnualDaylight first = annualDaylight(box.scene, sensors, box.weather, options, RadiosityOptions{}).value();
  EXPECT_FALSE(first.coefficientsFromCache);
  const AnnualDaylight second = annualDaylight(box.scene, sensors, box.weather, options, RadiosityOptions{}).value();
  EXPECT_TRUE(second.coefficientsFromCache);
  EXPECT_EQ(second.illuminance.totalLux, first.illuminance.totalLux);
  EXPECT_EQ(second.illuminance.directSunLux, first.illuminance.directSunLux);
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) files.push_back(entry.path());
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].extension(), ".ldc");
  std::vector<char> bytes = testing::readBytes(files[0]);
  bytes[bytes.size() / 2] ^= 0x5a;
  testing::writeBytes(files[0], bytes);
  const AnnualDaylight third = annualDaylight(box.scene, sensors, box.weather, options, RadiosityOptions{}).value();
  EXPECT_FALSE(third.coefficientsFromCache);
  EXPECT_EQ(third.illuminance.totalLux, first.illuminance.totalLux);
  const std::vector<CalculationPoint> moved = {{{2, 0.8, 2.1}, {0, 1, 0}}, {{2, 0.8, 1.35}, {0, 1, 0}}};
  EXPECT_FALSE(annualDaylight(box.scene, moved, box.weather, options, RadiosityOptions{}).value().coefficientsFromCache);
}

}  // namespace
}  // namespace lambert
