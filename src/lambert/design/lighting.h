#pragma once
// A solved scene's lighting-design results in one call: illuminance on work planes, on grids over
// chosen surfaces and at given points (design/illuminance.h, design/calculation_grid.h), each
// grid with its statistics; and the files a designer keeps: per grid a CSV of its points and a
// false-colour PNG with isolux lines (design/false_colour.h).
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/design/calculation_grid.h"
#include "lambert/design/false_colour.h"
#include "lambert/design/illuminance.h"
#include "lambert/design/points_file.h"

namespace lambert {

class SolutionView;

struct LightingRequest {
  std::vector<WorkPlaneSpec> workPlanes;
  std::vector<SurfaceGridSpec> surfaceGrids;
  std::vector<CalculationPoint> points;  // scene frame
  IlluminanceOptions illuminance;
};

struct MeasuredGrid {
  CalculationGrid grid;
  std::vector<PointIrradiance> irradiance;  // per grid point, W/m²
  std::vector<double> lux;                  // per grid point, illuminanceLux(total)
  GridStatistics statistics;                // of lux
  // Under an overcast sky that alone lights the scene (light/sky.h daylightFactorSky, isOvercast):
  // the daylight factor per point, DF = 100 · E / E_h,unobstructed (%), and its statistics; else empty.
  std::vector<double> daylightFactor;
  GridStatistics daylight;
};

struct LightingResults {
  std::vector<MeasuredGrid> grids;
  std::vector<PointIrradiance> points;  // per requested point
  std::vector<double> pointDaylightFactor;  // per requested point, % (as MeasuredGrid::daylightFactor)
  double skyHorizontalLux = 0;              // E_h of the sky the daylight factors are taken under; 0: none
  double setupSeconds = 0;              // the meter's setup (the solution's vertex irradiance)
  double measureSeconds = 0;            // every point of every grid and the points
  std::uint64_t pointsMeasured = 0;
  std::uint64_t raysCast = 0;
};

// An Error names the work plane or grid that cannot be laid (design/calculation_grid.h).
Result<LightingResults> measureLighting(const SolutionView& solution, const LightingRequest& request);

// A grid's points as a points table (x, y, z, nx, ny, nz in the scene file's frame, through
// `frame`), for writePointsCsv.
PointsTable gridTable(const CalculationGrid& grid, const FileFrame& frame);

// A file-name-safe form of a grid's name: letters and digits kept, the rest "-".
std::string gridFileStem(const std::string& name);

// Writes <prefix><stem>.csv and <prefix><stem>.png for each grid (prefix a folder with a
// trailing "/", or a file-name prefix); returns the paths written.
Result<std::vector<std::string>> writeGridFiles(const std::string& prefix, const LightingResults& results, const FileFrame& frame,
                                                const FalseColourOptions& image = {});

}  // namespace lambert
