#include "lambert/design/daylight_coefficients.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "lambert/core/photometric.h"
#include "lambert/design/calculation_grid.h"
#include "lambert/engine/radiosity.h"
#include "lambert/light/sun.h"
#include "lambert/load/scene_file.h"

namespace lambert {
namespace {

struct Hour {
  int cieType;
  double sunAzimuth, sunElevation;  // degrees
  double skyLux, sunLux;            // horizontal diffuse illuminance, direct normal illuminance
};

// The daylit office (scenes/daylight/) with its window facing south (north +z), on a 0.6 m work
// plane: for a dozen skies and suns, the coefficients' illuminance is what a direct solve of that
// hour's sky and sun gives at every sensor (the engine solved with both lights, measured by the
// illuminance meter), within 2%.
TEST(DaylightCoefficientsTest, EachHourIsADirectSolveOfItsSkyAndSun) {
  Result<Scene> scene = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/scenes/daylight/office-overcast.json");
  ASSERT_TRUE(scene) << scene.error().message;
  const Vec3 north{0, 0, 1};
  WorkPlaneSpec plane;
  plane.spacingMetres = 0.6;
  Result<CalculationGrid> grid = workPlaneGrid(*scene, plane);
  ASSERT_TRUE(grid);
  const std::vector<Hour> hours = {
      {1, 180, 30, 12000, 0},     {3, 150, 20, 18000, 0},      {5, 200, 50, 15000, 0},      {7, 180, 15, 20000, 30000},
      {12, 190, 35, 14000, 70000}, {12, 130, 25, 12000, 60000}, {12, 230, 45, 15000, 80000}, {13, 170, 10, 8000, 40000},
      {14, 210, 28, 16000, 65000}, {9, 160, 40, 25000, 20000},  {11, 175, 60, 20000, 85000}, {15, 120, 8, 6000, 25000}};
  std::vector<Vec3> suns;
  for (const Hour& h : hours) suns.push_back(skyDirection(h.sunAzimuth, h.sunElevation, north));
  DaylightCoefficientOptions options;
  options.north = north;
  options.indirectRays = std::getenv("DC_RAYS") ? std::atoi(std::getenv("DC_RAYS")) : 256;
  options.directSkySubdivisions = std::getenv("DC_DIRMF") ? std::atoi(std::getenv("DC_DIRMF")) : 4;
  options.sunSubdivisions = std::getenv("DC_SUNMF") ? std::atoi(std::getenv("DC_SUNMF")) : 4;
  Result<DaylightCoefficients> dc = computeDaylightCoefficients(*scene, grid->points, suns, options, RadiosityOptions{});
  ASSERT_TRUE(dc) << dc.error().message;
  const std::size_t n = grid->points.size(), patches = static_cast<std::size_t>(dc->sky.count()), basis = dc->basisSunPatch.size();
  std::printf("coefficients: %zu sensors, %zu patches, %zu basis suns, %.2f s\n", n, patches, basis, dc->seconds);
  double worstOverall = 0;
  for (std::size_t h = 0; h < hours.size(); ++h) {
    const Hour& hour = hours[h];
    const SkyModel model = SkyModel::cieStandard(hour.cieType, hour.sunAzimuth, hour.sunElevation, 1000, north).value().withHorizontalIlluminance(hour.skyLux);
    std::vector<double> luminance(patches), fine(static_cast<std::size_t>(dc->directSky.count()));
    for (std::size_t p = 0; p < patches; ++p) luminance[p] = dc->sky.meanLuminance(model, static_cast<int>(p));
    for (std::size_t q = 0; q < fine.size(); ++q) fine[q] = dc->directSky.meanLuminance(model, static_cast<int>(q));
    Scene lit = *scene;
    lit.lights.clear();
    Light sky;
    sky.name = "sky";
    sky.kind = LightKind::Sky;
    sky.sky = std::make_shared<SkyModel>(model);
    lit.lights.push_back(sky);
    if (hour.sunLux > 0) {
      Light sun;
      sun.name = "sun";
      sun.kind = LightKind::Directional;
      sun.direction = -suns[h];
      sun.irradiance = Rgb::gray(hour.sunLux / kLumensPerWatt);
      lit.lights.push_back(sun);
    }
    auto engine = Radiosity::create(lit, RadiosityOptions{});
    ASSERT_TRUE(engine);
    ASSERT_TRUE((*engine)->solve());
    const IlluminanceMeter meter((*engine)->solution());
    const std::vector<PointIrradiance> measured = meter.measure(grid->points).value();
    double worst = 0, sumSq = 0, bias = 0;
    for (std::size_t s = 0; s < n; ++s) {
      double e = 0, skyDirect = 0, skyIndirect = 0, sunDirect = 0, sunIndirect = 0;
      for (std::size_t p = 0; p < patches; ++p) skyIndirect += dc->skyIndirect[s * patches + p] * luminance[p];
      for (std::size_t q = 0; q < fine.size(); ++q) skyDirect += dc->skyDirect[s * fine.size() + q] * fine[q];
      if (hour.sunLux > 0) sunDirect = hour.sunLux * dc->sunDirect[h * n + s], sunIndirect = hour.sunLux * (dc->sunReflected[h * n + s] + dc->sunIndirect[s * basis + dc->basisSunOf[h]]);
      e = skyDirect + skyIndirect + sunDirect + sunIndirect;
      const double direct = illuminanceLux(measured[s].total());
      const double error = e / direct - 1;
      if (std::fabs(error) > worst)
        std::printf("  sensor %zu: sky %.0f/%.0f sun %.0f/%.0f indirect %.0f/%.0f\n", s, skyDirect, illuminanceLux(measured[s].sky), sunDirect,
                    illuminanceLux(measured[s].sun), skyIndirect + sunIndirect, illuminanceLux(measured[s].indirect));
      worst = std::max(worst, std::fabs(error));
      sumSq += error * error;
      bias += error;
    }
    std::printf("hour %zu (CIE %d, sun %g/%g): bias %+.2f%%, rms %.2f%%, worst %.2f%%\n", h, hour.cieType, hour.sunAzimuth, hour.sunElevation,
                100 * bias / n, 100 * std::sqrt(sumSq / n), 100 * worst);
    worstOverall = std::max(worstOverall, worst);
  }
  EXPECT_LT(worstOverall, 0.02);
}

}  // namespace
}  // namespace lambert
