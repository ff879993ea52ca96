#include "lambert/design/lighting.h"

#include <cctype>
#include <cstdio>

#include "lambert/core/photometric.h"
#include "lambert/core/timer.h"
#include "lambert/method/solution.h"
#include "lambert/io/png.h"
#include "lambert/light/sky.h"

namespace lambert {

Result<LightingResults> measureLighting(const SolutionView& solution, const LightingRequest& request) {
  LightingResults results;
  const Scene& scene = solution.scene();
  std::vector<CalculationGrid> grids;
  for (const WorkPlaneSpec& spec : request.workPlanes) {
    Result<CalculationGrid> grid = workPlaneGrid(scene, spec);
    if (!grid) return grid.error();
    grids.push_back(std::move(*grid));
  }
  for (const SurfaceGridSpec& spec : request.surfaceGrids) {
    Result<CalculationGrid> grid = surfaceGrid(scene, spec);
    if (!grid) return grid.error();
    grids.push_back(std::move(*grid));
  }
  // Every point at once, so that one parallel pass covers them.
  std::vector<CalculationPoint> all = request.points;
  for (const CalculationGrid& grid : grids) all.insert(all.end(), grid.points.begin(), grid.points.end());
  if (all.empty()) return results;
  const IlluminanceMeter meter(solution, request.illuminance);
  results.setupSeconds = meter.setupSeconds();
  const Timer timer;
  Result<std::vector<PointIrradiance>> measured = meter.measure(all);
  if (!measured) return measured.error();
  results.measureSeconds = timer.seconds();
  results.pointsMeasured = all.size();
  results.raysCast = meter.raysCast();
  std::size_t next = request.points.size();
  results.points.assign(measured->begin(), measured->begin() + static_cast<std::ptrdiff_t>(next));
  // A daylight factor where the scene is lit by an overcast sky alone.
  const SkyModel* sky = daylightFactorSky(scene);
  if (sky && !isOvercast(*sky)) sky = nullptr;
  if (sky) results.skyHorizontalLux = sky->horizontalIlluminance();
  auto daylightFactors = [&](const std::vector<PointIrradiance>& irradiance) {
    std::vector<double> df;
    if (sky)
      for (const PointIrradiance& e : irradiance) df.push_back(daylightFactorPercent(illuminanceLux(e.total()), *sky));
    return df;
  };
  results.pointDaylightFactor = daylightFactors(results.points);
  for (CalculationGrid& grid : grids) {
    MeasuredGrid m;
    m.irradiance.assign(measured->begin() + static_cast<std::ptrdiff_t>(next),
                        measured->begin() + static_cast<std::ptrdiff_t>(next + grid.points.size()));
    next += grid.points.size();
    for (const PointIrradiance& e : m.irradiance) m.lux.push_back(illuminanceLux(e.total()));
    m.statistics = gridStatistics(m.lux);
    m.daylightFactor = daylightFactors(m.irradiance);
    m.daylight = gridStatistics(m.daylightFactor);
    m.grid = std::move(grid);
    results.grids.push_back(std::move(m));
  }
  return results;
}

PointsTable gridTable(const CalculationGrid& grid, const FileFrame& frame) {
  PointsTable table;
  table.header = {"x", "y", "z", "nx", "ny", "nz"};
  char buffer[64];
  auto text = [&](double v) {
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return std::string(buffer);
  };
  for (const CalculationPoint& p : grid.points) {
    const Vec3 x = frame.filePoint(p.position);
    // The normal back into the file's frame: the inverse map of a direction, as filePoint less its offset.
    const Vec3 n = normalize(frame.filePoint(frame.offset + p.normal));
    table.rows.push_back({text(x.x), text(x.y), text(x.z), text(n.x), text(n.y), text(n.z)});
    table.points.push_back(p);
  }
  return table;
}

std::string gridFileStem(const std::string& name) {
  std::string stem;
  for (char c : name) stem += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return stem.empty() ? std::string("grid") : stem;
}

Result<std::vector<std::string>> writeGridFiles(const std::string& prefix, const LightingResults& results, const FileFrame& frame,
                                                const FalseColourOptions& image) {
  std::vector<std::string> written;
  for (std::size_t g = 0; g < results.grids.size(); ++g) {
    const MeasuredGrid& m = results.grids[g];
    std::string stem = gridFileStem(m.grid.name);
    for (std::size_t h = 0; h < g; ++h)
      if (gridFileStem(results.grids[h].grid.name) == stem) stem.append(1, '-').append(std::to_string(g + 1));
    const std::string csv = prefix + stem + ".csv", png = prefix + stem + ".png";
    if (Status ok = writePointsCsv(csv, gridTable(m.grid, frame), m.irradiance, m.daylightFactor); !ok) return ok.error();
    const FalseColourImage picture = falseColourImage(m.grid, m.lux, image);
    if (Status ok = writePng(png, picture.width, picture.height, picture.rgb); !ok) return ok.error();
    written.push_back(csv);
    written.push_back(png);
  }
  return written;
}

}  // namespace lambert
