#include "lighting_options.h"

namespace lambert::cli {

void addLightingOptions(CLI::App& cmd, LightingCommandOptions& o) {
  o.command = &cmd;
  cmd.add_option("--points", o.points,
                 "Illuminance at points: a CSV of x,y,z,nx,ny,nz in the scene file's frame and unit (docs/photometry.md)");
  cmd.add_option("--work-plane", o.workPlanes,
                 "A work plane this many metres above the floor, over the scene's footprint (repeatable); lux, E_avg, U0")
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--grid", o.grids, "A calculation grid on the surfaces of this name or material (repeatable), e.g. floor");
  cmd.add_option("--grid-spacing", o.spacingMetres, "Grid spacing in metres for --work-plane and --grid")
      ->check(CLI::PositiveNumber)
      ->default_str("EN 12464-1's: 0.2 x 5^log10(d)");
  cmd.add_option("--work-plane-margin", o.marginMetres, "Border left out of each --work-plane, metres (EN 12464-1: 0.5 by walls)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd.add_option("--illuminance-rays", o.indirectRays, "Hemisphere rays per point for the reflected light")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
}

Result<LightingRequest> lightingRequest(const Scene& scene, const LightingCommandOptions& o, PointsTable* pointsTable, bool showProgress) {
  LightingRequest request;
  if (!o.any())
    if (Status ok = refuseGiven(o, {"--grid-spacing", "--work-plane-margin", "--illuminance-rays"},
                                "it sets up --points, --work-plane or --grid, and none is asked for");
        !ok)
      return ok.error();
  if (o.workPlanes.empty())
    if (Status ok = refuseGiven(o, {"--work-plane-margin"}, "it trims --work-plane, which is not asked for"); !ok) return ok.error();
  for (double height : o.workPlanes) {
    WorkPlaneSpec spec;
    char name[64];
    std::snprintf(name, sizeof name, "work plane %.2f m", height);
    spec.name = name;
    spec.heightMetres = height;
    spec.spacingMetres = o.spacingMetres;
    spec.marginMetres = o.marginMetres;
    request.workPlanes.push_back(spec);
  }
  for (const std::string& surface : o.grids) {
    SurfaceGridSpec spec;
    spec.surface = surface;
    spec.spacingMetres = o.spacingMetres;
    request.surfaceGrids.push_back(spec);
  }
  if (!o.points.empty()) {
    Result<PointsTable> table = readPointsCsv(o.points, scene.fileFrame);
    if (!table) return table.error();
    request.points = table->points;
    if (pointsTable) *pointsTable = std::move(*table);
  }
  request.illuminance.indirectRays = o.indirectRays;
  request.illuminance.showProgress = showProgress;
  return request;
}

void addLightingStats(Stats& stats, const LightingResults& results) {
  for (std::size_t g = 0; g < results.grids.size(); ++g) {
    const MeasuredGrid& m = results.grids[g];
    const std::string key = "grid" + std::to_string(g + 1) + "_", label = m.grid.name + ": ";
    stats.add(key + "name", label + "calculation surface", m.grid.name);
    stats.add(key + "points", label + "points", static_cast<std::int64_t>(m.statistics.points));
    stats.add(key + "spacing", label + "spacing", m.grid.spacingU, "scene units");
    stats.add(key + "e_avg", label + "E_avg", m.statistics.average, "lx");
    stats.add(key + "e_min", label + "E_min", m.statistics.minimum, "lx");
    stats.add(key + "e_max", label + "E_max", m.statistics.maximum, "lx");
    stats.add(key + "u0", label + "U0 = E_min/E_avg", m.statistics.uniformity);
    stats.add(key + "min_over_max", label + "E_min/E_max", m.statistics.minOverMax);
    if (!m.daylightFactor.empty()) {
      stats.add(key + "df_avg", label + "daylight factor, mean", m.daylight.average, "%");
      stats.add(key + "df_min", label + "daylight factor, least", m.daylight.minimum, "%");
      stats.add(key + "df_max", label + "daylight factor, most", m.daylight.maximum, "%");
    }
  }
  if (results.skyHorizontalLux > 0) stats.add("sky_horizontal_lux", "overcast sky, unobstructed horizontal illuminance", results.skyHorizontalLux, "lx");
  stats.add("illuminance_points", "illuminance points", static_cast<std::int64_t>(results.pointsMeasured));
  stats.add("illuminance_setup_seconds", "illuminance setup time (vertex irradiance)", results.setupSeconds, "s");
  stats.add("illuminance_seconds", "illuminance time", results.measureSeconds, "s");
  stats.add("illuminance_rays", "illuminance rays", static_cast<std::int64_t>(results.raysCast));
}

}  // namespace lambert::cli
