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
#include "lambert/design/ugr.h"

namespace lambert {

class SolutionView;

// An observer whose discomfort glare is rated (design/ugr.h): an eye and a horizontal line of sight.
struct GlareObserverSpec {
  std::string name;
  Vec3 eye;            // scene frame and units
  Vec3 viewDirection;  // its horizontal part is the line of sight
};

struct LightingRequest {
  std::vector<WorkPlaneSpec> workPlanes;
  std::vector<SurfaceGridSpec> surfaceGrids;
  std::vector<CalculationPoint> points;  // scene frame
  std::vector<GlareObserverSpec> glareObservers;
  IlluminanceOptions illuminance;
};

// An observer's UGR (CIE 117): the background luminance L_b is the indirect illuminance at the eye,
// on a plane facing the line of sight, over π (measured as a calculation point is).
struct GlareRating {
  GlareObserverSpec observer;
  PointIrradiance atEye;  // the eye's irradiance facing the line of sight
  UgrResult rating;
};

// The usual observers of a room's UGR where none is given: seated eyes (1.2 m above the floor) at
// the middle of each side of the scene's footprint, 0.5 m in, looking across the room to the far side.
std::vector<GlareObserverSpec> defaultGlareObservers(const Scene& scene);

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
  std::vector<GlareRating> glare;           // per requested observer
  double setupSeconds = 0;              // the meter's setup (the solution's vertex irradiance)
  double measureSeconds = 0;            // every point of every grid and the points
  std::uint64_t pointsMeasured = 0;
  std::uint64_t raysCast = 0;
};

// An Error names the work plane or grid that cannot be laid (design/calculation_grid.h).
Result<LightingResults> measureLighting(const SolutionView& solution, const LightingRequest& request);

// The plan drawing's options for a scene (design/false_colour.h): its unit, its north (a sky's or
// sun's where one gives it, else −z) and its luminaires, labelled L1, L2, … in the lights' order.
FalseColourOptions planOptions(const Scene& scene, std::span<const Light> lights);
// A light's label in plans and reports: "L<k>" for the k-th luminaire, point or spot (1-based), else its name.
std::vector<std::string> lightLabels(std::span<const Light> lights);

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
