#pragma once
// The lighting-design options `solve` and `report` share: calculation points, work planes and
// grids on surfaces (design/lighting.h), read from the command line into a LightingRequest.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lambert/core/stats.h"
#include "lambert/design/lighting.h"
#include "options.h"

namespace lambert::cli {

struct LightingCommandOptions : GivenOptions {
  std::string points;                 // --points IN.csv
  std::vector<double> workPlanes;     // --work-plane HEIGHT (metres above the floor), repeatable
  std::vector<std::string> grids;     // --grid SURFACE (a surface's or material's name), repeatable
  double spacingMetres = 0;           // --grid-spacing; 0: EN 12464-1's
  double marginMetres = 0;            // --work-plane-margin
  int indirectRays = IlluminanceOptions{}.indirectRays;
  bool any() const { return !points.empty() || !workPlanes.empty() || !grids.empty(); }
};

void addLightingOptions(CLI::App& command, LightingCommandOptions& options);
// The request the options make for a scene (reading --points' file); an Error names what is wrong.
Result<LightingRequest> lightingRequest(const Scene& scene, const LightingCommandOptions& options, PointsTable* pointsTable,
                                        bool showProgress);
// Each grid's figures (E_avg, E_min, E_max, U₀, E_min/E_max in lux) and the time taken.
void addLightingStats(Stats& stats, const LightingResults& results);

}  // namespace lambert::cli
