#include "lambert/design/daylight_coefficients.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <vector>

#include "lambert/core/photometric.h"
#include "lambert/design/calculation_grid.h"
#include "lambert/engine/radiosity.h"
#include "lambert/light/sun.h"
#include "lambert/light/perez_sky.h"
#include "lambert/load/epw.h"
#include "lambert/load/scene_file.h"
#include "lambert/mesh/mesh.h"
#include "lambert/reference/reference.h"

namespace lambert {
namespace {

// The daylit office of scenes/daylight/ turned so that its window faces south (north +z), the
// test week's weather and a 0.6 m work plane at 0.8 m (49 sensors).
constexpr Vec3 kNorth{0, 0, 1};
struct SouthOffice {
  Scene scene;
  WeatherData weather;
  CalculationGrid grid;
};
SouthOffice southOffice() {
  SouthOffice office{loadScene(std::string(LAMBERT_SOURCE_DIR) + "/scenes/daylight/office-overcast.json").value(),
                     readEpw(std::string(LAMBERT_SOURCE_DIR) + "/tests/weather/boulder-week.epw").value(), {}};
  WorkPlaneSpec plane;
  plane.spacingMetres = 0.6;
  office.grid = workPlaneGrid(office.scene, plane).value();
  return office;
}

// The daylit office (scenes/daylight/) with its window facing south (north +z), on a 0.6 m work
// plane, under a dozen hours of the test week (tests/weather/boulder-week.epw: Perez skies from
// overcast to clear, with and without sun): the coefficients' illuminance against a direct solve of
// that hour's sky and sun (the engine solved with both lights, refined for them, measured by the
// illuminance meter) at every sensor: without direct sun (overcast hours) within 2% (1.1% measured);
// with the sun in the room but on surfaces the sensors do not see (the floor under an up-facing work
// plane), within 4% (3.7%). Where the sensors see a sunlit wall, a sensor beside it differs by 27%:
// there the path tracer sides with the coefficients (TheSunsReflectionsAgreeWithThePathTracer
// below), and the test holds each such hour's bias and RMS over the sensors (measured +0.6 to
// +1.0%, RMS at most 4.1%).
TEST(DaylightCoefficientsTest, EachHourIsADirectSolveOfItsSkyAndSun) {
  const SouthOffice office = southOffice();
  const Scene* scene = &office.scene;
  const WeatherData* weather = &office.weather;
  const CalculationGrid* grid = &office.grid;
  const Vec3 north = kNorth;
  // (day 0–6, hour ending): mornings, noons and afternoons of each kind of day.
  const std::pair<int, int> sampled[] = {{0, 9}, {0, 13}, {1, 11}, {1, 15}, {2, 10}, {2, 14}, {3, 12}, {3, 17}, {4, 9}, {5, 12}, {5, 16}, {6, 13}};
  std::vector<PerezHourSky> skies;
  std::vector<Vec3> suns;
  for (auto [day, hour] : sampled) {
    skies.push_back(perezSkyForHour(*weather, weather->hours[static_cast<std::size_t>(day * 24 + hour - 1)], north).value());
    ASSERT_TRUE(skies.back().sky);
    suns.push_back(skyDirection(skies.back().sun.azimuthDegrees, skies.back().sun.elevationDegrees(), north));
  }
  DaylightCoefficientOptions options;
  options.north = north;
  Result<DaylightCoefficients> dc = computeDaylightCoefficients(*scene, grid->points, suns, options, RadiosityOptions{});
  ASSERT_TRUE(dc) << dc.error().message;
  const std::size_t n = grid->points.size(), patches = static_cast<std::size_t>(dc->sky.count());
  int sunnyHours = 0;
  for (std::size_t h = 0; h < skies.size(); ++h) {
    const PerezHourSky& hour = skies[h];
    const bool sun = hour.sunInSky && hour.sunIlluminanceLux > 0;
    std::vector<double> luminance(patches), fine(static_cast<std::size_t>(dc->directSky.count()));
    for (std::size_t p = 0; p < patches; ++p) luminance[p] = dc->sky.meanLuminance(*hour.sky, static_cast<int>(p));
    for (std::size_t q = 0; q < fine.size(); ++q) fine[q] = dc->directSky.meanLuminance(*hour.sky, static_cast<int>(q));
    Scene lit = *scene;
    lit.lights.clear();
    Light sky;
    sky.name = "sky";
    sky.kind = LightKind::Sky;
    sky.sky = std::make_shared<SkyModel>(*hour.sky);
    lit.lights.push_back(sky);
    if (sun) {
      Light light;
      light.name = "sun";
      light.kind = LightKind::Directional;
      light.direction = -suns[h];
      light.irradiance = Rgb::gray(hour.sunIlluminanceLux / kLumensPerWatt);
      lit.lights.push_back(light);
    }
    auto engine = Radiosity::create(lit, RadiosityOptions{});
    ASSERT_TRUE(engine);
    ASSERT_TRUE((*engine)->solve());
    const std::vector<PointIrradiance> measured = IlluminanceMeter((*engine)->solution()).measure(grid->points).value();
    double worst = 0, sumSq = 0, bias = 0;
    bool sunInRoom = false;
    for (std::size_t s = 0; s < n; ++s) {
      double e = 0;
      for (std::size_t p = 0; p < patches; ++p) e += dc->skyIndirect[s * patches + p] * luminance[p];
      for (std::size_t q = 0; q < fine.size(); ++q) e += dc->skyDirect[s * fine.size() + q] * fine[q];
      if (sun) {
        e += hour.sunIlluminanceLux * (dc->sunDirect[h * n + s] + dc->sunInterreflected(h, s));
        sunInRoom |= dc->sunReflected[h * n + s] > 0;
      }
      const double error = e / illuminanceLux(measured[s].total()) - 1;
      worst = std::max(worst, std::fabs(error));
      sumSq += error * error;
      bias += error;
    }
    const double rms = std::sqrt(sumSq / n);
    bias /= n;
    std::printf("hour %zu (%d/%d hour %d, ε %.2f, sun %.0f° high, %.0f lx%s): bias %+.2f%%, rms %.2f%%, worst %.2f%%\n", h,
                weather->hours[static_cast<std::size_t>(sampled[h].first * 24 + sampled[h].second - 1)].month,
                weather->hours[static_cast<std::size_t>(sampled[h].first * 24 + sampled[h].second - 1)].day, sampled[h].second,
                hour.coefficients.clearness, hour.sun.elevationDegrees(), sun ? hour.sunIlluminanceLux : 0.0, sunInRoom ? ", in the room" : "",
                100 * bias, 100 * rms, 100 * worst);
    if (!sunInRoom) {
      EXPECT_LT(worst, 0.04) << "hour " << h;
      if (!sun) {
        EXPECT_LT(worst, 0.02) << "hour " << h;
      }
    } else {
      EXPECT_LT(std::fabs(bias), 0.025) << "hour " << h;
      EXPECT_LT(rms, 0.06) << "hour " << h;
    }
    sunnyHours += sun;
  }
  EXPECT_GE(sunnyHours, 8);
}

// The sun's light beyond its direct light, where the direct solve's meter and the coefficients
// part: the test week's 6/19 8–9 am, the sun alone (84,455 lx, 43° high) through the south window onto
// the east wall, at work-plane sensors near it and across the room, against the path tracer
// (reference/reference.h, 16,384 paths a sensor: its noise about 1%). The coefficients trace the
// sun's first reflection (2,048 rays a sensor) and interpolate the rest; the meter reads the direct
// solve's vertex irradiance, interpolated across the sun patch's edge on the wall.
TEST(DaylightCoefficientsTest, TheSunsReflectionsAgreeWithThePathTracer) {
  const SouthOffice office = southOffice();
  const Scene* scene = &office.scene;
  const WeatherData* weather = &office.weather;
  const CalculationGrid& grid = office.grid;
  const Vec3 north = kNorth;
  const PerezHourSky hour = perezSkyForHour(*weather, weather->hours[8], north).value();
  ASSERT_GT(hour.sunIlluminanceLux, 80000);
  const Vec3 toSun = skyDirection(hour.sun.azimuthDegrees, hour.sun.elevationDegrees(), north);
  DaylightCoefficientOptions options;
  options.north = north;
  const std::vector<Vec3> suns{toSun};
  Result<DaylightCoefficients> dc = computeDaylightCoefficients(*scene, grid.points, suns, options, RadiosityOptions{});
  ASSERT_TRUE(dc) << dc.error().message;
  Scene lit = *scene;
  lit.lights.clear();
  Light sun;
  sun.name = "sun";
  sun.kind = LightKind::Directional;
  sun.direction = -toSun;
  sun.irradiance = Rgb::gray(hour.sunIlluminanceLux / kLumensPerWatt);
  lit.lights.push_back(sun);
  ReferenceOptions paths;
  paths.vertexSamples = 16384;
  paths.showProgress = false;
  const ReferenceRenderer tracer(lit, subdivideScene(lit, 0.25), paths);
  auto engine = Radiosity::create(lit, RadiosityOptions{});
  ASSERT_TRUE(engine);
  ASSERT_TRUE((*engine)->solve());
  const std::vector<PointIrradiance> meter = IlluminanceMeter((*engine)->solution()).measure(grid.points).value();
  double coefficientsWorst = 0, meterWorst = 0;
  for (std::size_t s : {0, 1, 5, 6, 7, 24, 40}) {
    const double traced = illuminanceLux(tracer.irradianceAt(grid.points[s].position, grid.points[s].normal, 0, s));
    const double coefficients = hour.sunIlluminanceLux * (dc->sunDirect[s] + dc->sunInterreflected(0, s));
    const double measured = illuminanceLux(meter[s].total());
    std::printf("sensor %zu: path tracer %.0f lx, coefficients %.0f, meter %.0f\n", s, traced, coefficients, measured);
    coefficientsWorst = std::max(coefficientsWorst, std::fabs(coefficients / traced - 1));
    meterWorst = std::max(meterWorst, std::fabs(measured / traced - 1));
  }
  // Measured: the coefficients within 27% at every sensor (sensor 5, 0.3 m from the sun patch; 5%
  // at sensor 6 beside it), the meter 74% off at sensor 6 (157 lx where the paths find 614).
  EXPECT_LT(coefficientsWorst, 0.3);
  std::printf("worst: coefficients %.0f%%, meter %.0f%%\n", 100 * coefficientsWorst, 100 * meterWorst);
}

// A scene lambert's authors did not write: RenderPark's office3 (fetched corpus; its roof is open to
// the sky, its glass opaque here), on the 0.6 m work plane, under an overcast and a sunny hour of the
// test week: the coefficients against the path tracer (1,024 paths a sensor, the sky's next-event
// estimate from 1,024 directions) at every fifth sensor, daylight alone (the scene's emitting
// surfaces dark, as the coefficients count it). Runs where LAMBERT_CORPUS names the fetched corpus
// (CI has no network: its files are RenderPark's, not committed).
TEST(DaylightCoefficientsTest, RenderParksOffice3AgreesWithThePathTracer) {
  const char* corpus = std::getenv("LAMBERT_CORPUS");
  if (!corpus) GTEST_SKIP() << "set LAMBERT_CORPUS to scripts/fetch-corpus.py's folder";
  Result<Scene> scene = loadScene(std::string(corpus) + "/renderpark/etc/office3/office.mgf");
  ASSERT_TRUE(scene) << scene.error().message;
  const WeatherData weather = readEpw(std::string(LAMBERT_SOURCE_DIR) + "/tests/weather/boulder-week.epw").value();
  WorkPlaneSpec plane;
  plane.spacingMetres = 0.6;
  const CalculationGrid grid = workPlaneGrid(*scene, plane).value();
  const Vec3 north{0, 0, -1};
  const int hours[] = {24 + 12, 5 * 24 + 11};  // 6/20 11–12 (overcast), 6/24 10–11 (clear)
  std::vector<PerezHourSky> skies;
  std::vector<Vec3> suns;
  for (int h : hours) {
    skies.push_back(perezSkyForHour(weather, weather.hours[static_cast<std::size_t>(h)], north).value());
    suns.push_back(skyDirection(skies.back().sun.azimuthDegrees, skies.back().sun.elevationDegrees(), north));
  }
  DaylightCoefficientOptions options;
  options.north = north;
  Result<DaylightCoefficients> dc = computeDaylightCoefficients(*scene, grid.points, suns, options, RadiosityOptions{});
  ASSERT_TRUE(dc) << dc.error().message;
  const std::size_t n = grid.points.size(), patches = static_cast<std::size_t>(dc->sky.count());
  for (std::size_t h = 0; h < skies.size(); ++h) {
    const PerezHourSky& hour = skies[h];
    Scene lit = *scene;
    lit.lights.clear();
    for (Surface& surface : lit.surfaces) surface.emittedRadiance = {};  // daylight alone, as the coefficients count it
    Light sky;
    sky.name = "sky";
    sky.kind = LightKind::Sky;
    sky.sky = std::make_shared<SkyModel>(*hour.sky);
    sky.skyDirections = 1024;
    lit.lights.push_back(sky);
    const bool sun = hour.sunInSky && hour.sunIlluminanceLux > 0;
    if (sun) {
      Light light;
      light.name = "sun";
      light.kind = LightKind::Directional;
      light.direction = -suns[h];
      light.irradiance = Rgb::gray(hour.sunIlluminanceLux / kLumensPerWatt);
      lit.lights.push_back(light);
    }
    ReferenceOptions paths;
    paths.vertexSamples = 1024;
    paths.showProgress = false;
    const ReferenceRenderer tracer(lit, subdivideScene(lit, 0.5), paths);
    auto engine = Radiosity::create(lit, RadiosityOptions{});
    ASSERT_TRUE(engine);
    ASSERT_TRUE((*engine)->solve());
    const std::vector<PointIrradiance> meter = IlluminanceMeter((*engine)->solution()).measure(grid.points).value();
    std::vector<double> fine(static_cast<std::size_t>(dc->directSky.count())), coarse(patches);
    for (std::size_t q = 0; q < fine.size(); ++q) fine[q] = dc->directSky.meanLuminance(*hour.sky, static_cast<int>(q));
    for (std::size_t p = 0; p < patches; ++p) coarse[p] = dc->sky.meanLuminance(*hour.sky, static_cast<int>(p));
    double worst = 0, bias = 0;
    int count = 0;
    for (std::size_t s = 0; s < n; s += 5) {
      double e = 0;
      for (std::size_t q = 0; q < fine.size(); ++q) e += dc->skyDirect[s * fine.size() + q] * fine[q];
      for (std::size_t p = 0; p < patches; ++p) e += dc->skyIndirect[s * patches + p] * coarse[p];
      if (sun) e += hour.sunIlluminanceLux * (dc->sunDirect[h * n + s] + dc->sunInterreflected(h, s));
      const double traced = illuminanceLux(tracer.irradianceAt(grid.points[s].position, grid.points[s].normal, 0, s));
      const double error = e / traced - 1;
      worst = std::max(worst, std::fabs(error));
      bias += error;
      ++count;
      std::printf("office3 hour %zu sensor %zu: path tracer %.0f lx, coefficients %.0f, direct solve's meter %.0f\n", h, s, traced, e,
                  illuminanceLux(meter[s].total()));
    }
    std::printf("office3 hour %zu (sun %s): bias %+.2f%%, worst %.2f%% over %d sensors\n", h, sun ? "in" : "out", 100 * bias / count, 100 * worst, count);
    // Measured: overcast bias +1.4%, worst 3.7% (the paths' own noise about 1–2%); sunny bias −4.9%,
    // worst 17.5% (sensor 5, beside sunlit furniture: the sun's first reflection by fixed directions).
    EXPECT_LT(std::fabs(bias / count), sun ? 0.07 : 0.03) << h;
    EXPECT_LT(worst, sun ? 0.2 : 0.06) << h;
  }
}

}  // namespace
}  // namespace lambert
