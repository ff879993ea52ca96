#pragma once
// Calculation points as a lighting designer's tools exchange them: a CSV of x, y, z, nx, ny, nz
// (the scene file's own frame and unit; for an MGF file z up, as the file writes them), one
// point per row, and the same rows written back with the illuminance appended in lux:
// E_direct (lights, skies, suns and emitting surfaces), E_sky and E_sun (the skies' and suns' parts
// of E_direct), E_indirect, E = E_direct + E_indirect (design/illuminance.h, core/photometric.h).
//
// Read liberally: a header row (most of its fields not numbers) names the columns (any order, any case, other columns kept and
// written back; without nx, ny, nz every point faces the file's up, with a warning); without a
// header the first six columns are x, y, z, nx, ny, nz. Fields are separated by commas,
// semicolons, tabs or spaces; blank lines and lines starting with # are skipped; a normal need not
// be of unit length. A row that cannot be read (too few fields, a field that is not a number, a
// zero normal) is refused with the file and line.
#include <span>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/design/illuminance.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct PointsTable {
  std::vector<std::string> header;             // the columns' names (x, y, z, nx, ny, nz without a header row)
  std::vector<std::vector<std::string>> rows;  // each point's fields as the file wrote them
  std::vector<CalculationPoint> points;        // in the scene's frame and units (through `frame`)
};

Result<PointsTable> readPointsCsv(const std::string& path, const FileFrame& frame);

// The table's columns and rows, then E_direct, E_sky, E_sun, E_indirect and E in lux per point (and DF in %
// when daylightFactorPercent is not empty), written atomically.
Status writePointsCsv(const std::string& path, const PointsTable& table, std::span<const PointIrradiance> irradiance,
                      std::span<const double> daylightFactorPercent = {});

// The table's columns and rows, then the named columns (their names should carry their unit, e.g.
// "DA_300lx_pct"), `values` row-major (rows × columns.size()), each written as %.6g; atomically.
// writePointsCsv and the daylight metrics' file (design/daylight_metrics.h) are both this.
Status writePointsCsvColumns(const std::string& path, const PointsTable& table, std::span<const std::string> columns,
                             std::span<const double> values);

}  // namespace lambert
