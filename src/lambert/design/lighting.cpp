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
  // Every point at once, so that one parallel pass covers them: the points, the grids' and the
  // observers' eyes (facing their lines of sight).
  std::vector<CalculationPoint> all = request.points;
  for (const CalculationGrid& grid : grids) all.insert(all.end(), grid.points.begin(), grid.points.end());
  for (const GlareObserverSpec& o : request.glareObservers) {
    const Vec3 sight{o.viewDirection.x, 0, o.viewDirection.z};
    if (!(length(sight) > 0)) return Error{"glare observer \"" + o.name + "\": its view direction has no horizontal part (UGR's line of sight is horizontal)"};
    all.push_back({o.eye, normalize(sight)});
  }
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
  std::size_t eye = all.size() - request.glareObservers.size();
  for (const GlareObserverSpec& o : request.glareObservers) {
    GlareRating g;
    g.observer = o;
    g.atEye = (*measured)[eye++];
    UgrObserver observer{o.eye, o.viewDirection, backgroundLuminanceFromIndirect(illuminanceLux(g.atEye.indirect))};
    if (!(observer.backgroundLuminance > 0)) observer.backgroundLuminance = 1e-9;  // a black room: no background, UGR unbounded
    Result<UgrResult> rating = unifiedGlareRating(solution.lights(), scene.metresPerUnit, observer);
    if (!rating) return Error{"glare observer \"" + o.name + "\": " + rating.error().message};
    g.rating = std::move(*rating);
    results.glare.push_back(std::move(g));
  }
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

std::vector<GlareObserverSpec> defaultGlareObservers(const Scene& scene) {
  const Bounds b = sceneBounds(scene);
  const double inset = 0.5 / scene.metresPerUnit, eyeHeight = b.lo.y + 1.2 / scene.metresPerUnit;
  const double cx = 0.5 * (b.lo.x + b.hi.x), cz = 0.5 * (b.lo.z + b.hi.z);
  return {{"west side, looking east", {b.lo.x + inset, eyeHeight, cz}, {1, 0, 0}},
          {"east side, looking west", {b.hi.x - inset, eyeHeight, cz}, {-1, 0, 0}},
          {"north side, looking south", {cx, eyeHeight, b.lo.z + inset}, {0, 0, 1}},
          {"south side, looking north", {cx, eyeHeight, b.hi.z - inset}, {0, 0, -1}}};
}

std::vector<std::string> lightLabels(std::span<const Light> lights) {
  std::vector<std::string> labels;
  int k = 0;
  for (const Light& light : lights) {
    const bool placed = light.kind == LightKind::Luminaire || light.kind == LightKind::Point || light.kind == LightKind::Spot;
    // Appended, not "L" + to_string(…): GCC 12's -Wrestrict misfires on that operator+.
    std::string label = placed ? std::string("L") : light.name;
    if (placed) label += std::to_string(++k);
    labels.push_back(std::move(label));
  }
  return labels;
}

FalseColourOptions planOptions(const Scene& scene, std::span<const Light> lights) {
  FalseColourOptions options;
  options.metresPerUnit = scene.metresPerUnit;
  const std::vector<std::string> labels = lightLabels(lights);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    if (light.kind == LightKind::Sky && light.sky) options.north = light.sky->north();
    if (light.kind == LightKind::Luminaire || light.kind == LightKind::Point || light.kind == LightKind::Spot)
      options.luminaires.push_back({light.position, light.kind == LightKind::Point ? Vec3{0, -1, 0} : light.direction, labels[i]});
  }
  return options;
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
