#pragma once
// Climate-based annual daylight metrics from a year of hourly illuminance at sensor points (a work
// plane's grid, design/calculation_grid.h), as pure functions over plain data: per sensor, and over
// the area the sensors sample (each sensor standing for an equal share of it, as a regular grid's do).
//
//  - Daylight autonomy DA (Reinhart & Walkenhorst 2001, Reinhart, Mardaljevic & Rogers, LEUKOS 3(1)
//    2006): the percentage of occupied hours with E ≥ daLux.
//  - Continuous daylight autonomy cDA (Rogers 2006, in Reinhart et al. 2006): the same, with an hour
//    below the threshold counting E/daLux (partial credit).
//  - Useful daylight illuminance UDI (Nabil & Mardaljevic, Lighting Res. Technol. 37(1) 2005 and
//    Energy Build. 38 2006): the percentage of occupied hours that "fell short" (E < 100 lx), were
//    "useful" (100 ≤ E ≤ 2000 lx, both ends in the band, as Nabil & Mardaljevic's ranges "100–2000 lux"
//    and the common implementations, Honeybee's among them, read it) or "exceeded" (E > 2000 lx); the
//    three add up to 100 %. Both limits are options.
//  - Spatial daylight autonomy sDA300/50% (IES LM-83-12 §2): the percentage of sensors whose E ≥ 300 lx
//    ("meets or exceeds") in at least 50 % of the occupied hours, blinds operated by the rule below.
//  - Annual sunlight exposure ASE1000,250h (IES LM-83-12 §3; the IES's definition: "the percentage of
//    the horizontal work plane that exceeds a specified direct sunlight illuminance level more than a
//    specified number of hours per year ... with all operable shading devices retracted"): the
//    percentage of sensors whose direct sun alone (no sky, no interreflection) is 1000 lx or more in
//    more than 250 occupied hours. "1000 lx or more" is LM-83 §2.2.6's definition of direct sun
//    ("1,000 lux or more of direct beam sunlight ... with no contribution from reflected light"),
//    used for both ASE and the blinds rule; an hour is counted when > 250 hours, not at 250.
//  - Per sensor also the mean and chosen percentiles of E over the occupied hours.
//
// Occupied hours. LM-83 analyses 8 am to 6 pm local standard time, every day: 3,650 hours a year.
// Rows carry the EPW convention: hour h (1..24) is the hour ending at h:00, the interval [h−1, h);
// a row is occupied when its interval lies within [firstOccupiedHour, lastOccupiedHour): hour 9
// (8–9 am) is, hour 8 (7–8 am) is not, hour 18 (5–6 pm) is, hour 19 is not.
//
// Blinds (LM-83 §2.2.6, option `blinds`). In an occupied hour where more than blindsSensorShare (2 %)
// of the sensors receive direct sun (≥ aseLux direct-only illuminance), the blinds close for that
// hour, and every sensor then receives (E_total − E_sun) × blindsTransmittance. This is a
// simplification of what LM-83 asks (a separate simulation of the blinds-closed state, per window
// group, with the blinds' own optics): one group for the whole grid; all direct sun stopped; the
// sky's and the interreflected light scaled by one diffuse transmittance. Its default 0.25 is DAYSIM's
// "simple dynamic shading" model (Reinhart's DAYSIM header keyword: "when lowered the blinds transmit
// 25% of diffuse daylight and block all direct solar radiation"); Honeybee's LEED option 1
// post-processing (honeybee-radiance-postprocess, leed.py) scales the aperture group's light by a
// shade transmittance of 0.05 instead (0.2 and 0.02 in earlier releases). The blinds change DA, cDA,
// UDI, the mean and percentiles and sDA; never ASE (blinds retracted, by definition).
//
// Criteria (recorded on the result, not imposed):
//  - LM-83-12 §2.1.3 as widely quoted: sDA300/50% ≥ 55 % "nominally accepted", ≥ 75 % "preferred";
//    ASE1000,250h > 10 % "likely to result in visual discomfort" (Arch Lighting / IES Daylight Metrics
//    Committee summaries; the standard itself was not at hand).
//  - LEED v4.1 BD+C EQ credit Daylight, option 1 (USGBC credit language, quoted on LEEDuser): the
//    average sDA300/50% of the regularly occupied floor area ≥ 40 % → 1 point, ≥ 55 % → 2, ≥ 75 % → 3;
//    every regularly occupied space ≥ 55 % → 1 more point where 1 or 2 were achieved; a space with
//    ASE1000,250h > 10 % must "identify how the space is designed to address glare" — v4.1 awards the
//    points regardless. LEED v4 (2013) differed: 55 % → 2 points, 75 % → 3, and ASE ≤ 10 % was
//    required (ClimateStudio's documentation: v4.0 disqualifies areas with too much sun, v4.1 does not).
//    Healthcare's 1–2 point scale is not implemented.
//
// Cost: one pass over the hours × sensors matrix, then a sort of each sensor's occupied hours for
// the percentiles (O(S·H log H)); memory S·H_occupied floats. Failure modes: an Error for sizes that
// disagree, an hour out of its range, a negative or non-finite illuminance, options out of range,
// no occupied hour — each naming what is wrong.
#include <span>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/design/calculation_grid.h"
#include "lambert/design/false_colour.h"
#include "lambert/design/points_file.h"
#include "lambert/design/report.h"

namespace lambert {

struct DaylightHourInfo {
  int month = 1, day = 1, hour = 1;  // EPW convention: hour 1..24 = the hour ENDING at that local standard clock time
};

struct AnnualIlluminance {
  std::size_t sensors = 0;
  std::vector<DaylightHourInfo> hours;  // one per row
  std::vector<float> totalLux;          // hours × sensors, hour-major: row h holds every sensor's illuminance in that hour (sky + sun, direct + interreflected)
  std::vector<float> directSunLux;      // hours × sensors: the sun's direct light alone (no sky, no interreflection), as LM-83's ASE asks
};

struct DaylightMetricsOptions {
  double firstOccupiedHour = 8, lastOccupiedHour = 18;  // local standard time, 0 ≤ first < last ≤ 24 (module comment)
  double sdaLux = 300, sdaTimeFraction = 0.5;           // sDA300/50%: E ≥ sdaLux in ≥ sdaTimeFraction of the occupied hours
  double aseLux = 1000, aseHours = 250;                 // ASE1000,250h: direct sun ≥ aseLux in > aseHours occupied hours
  double udiLowerLux = 100, udiUpperLux = 2000;         // UDI: fell short E < lower, useful lower ≤ E ≤ upper, exceeded E > upper
  double daLux = 300;                                   // DA: E ≥ daLux; cDA: min(1, E/daLux) per hour
  bool blinds = false;                                  // LM-83 §2.2.6's rule (module comment)
  double blindsSensorShare = 0.02;                      // blinds close where more than this share of sensors see direct sun
  double blindsTransmittance = 0.25;                    // (E − E_sun) × this with the blinds closed (DAYSIM's 25 %; module comment)
  std::vector<double> percentiles = {10, 50, 90};       // of E over the occupied hours, 0..100
};

struct SensorDaylight {
  double daylightAutonomy = 0;            // % of occupied hours
  double continuousDaylightAutonomy = 0;  // % of occupied hours
  double udiFellShort = 0, udiUseful = 0, udiExceeded = 0;  // % of occupied hours, adding up to 100
  double meanLux = 0;                     // mean E over the occupied hours, lx
  double sunlitHours = 0;                 // occupied hours with direct sun ≥ aseLux (blinds open), h
  std::vector<double> percentileLux;      // per DaylightMetricsOptions::percentiles, lx
  bool sdaPass = false;                   // E ≥ sdaLux in ≥ sdaTimeFraction of the occupied hours
  bool aseExceeded = false;               // sunlitHours > aseHours
};

// LEED v4.1 BD+C EQ Daylight option 1 (module comment).
struct LeedDaylightPoints {
  double averageSda = 0;            // area-weighted over the spaces, %
  int averagePoints = 0;            // 0..3 from the average: ≥ 40, 55, 75 %
  bool everySpaceAtLeast55 = false;
  int points = 0;                   // averagePoints, + 1 where every space ≥ 55 % and averagePoints is 1 or 2
  bool glareStrategyRequired = false;  // some space has ASE1000,250h > 10 %
};
// Each space's sDA (%), ASE (%) and floor area (any unit); an Error for sizes that disagree or none.
Result<LeedDaylightPoints> leedV41DaylightPoints(std::span<const double> sdaPercent, std::span<const double> asePercent,
                                                 std::span<const double> areas);

struct DaylightMetrics {
  std::vector<SensorDaylight> sensors;
  double spatialDaylightAutonomy = 0;  // sDA, % of sensors
  double annualSunlightExposure = 0;   // ASE, % of sensors
  // Area means (over the sensors) of the per-sensor figures.
  double meanDaylightAutonomy = 0, meanContinuousDaylightAutonomy = 0;  // %
  double meanUdiFellShort = 0, meanUdiUseful = 0, meanUdiExceeded = 0;  // %
  double meanLux = 0;                                                   // lx
  int occupiedHours = 0;
  int blindsClosedHours = 0;  // occupied hours with the blinds closed (0 unless options.blinds)
  // LM-83-12's criteria.
  bool lm83SdaNominallyAccepted = false;  // sDA ≥ 55 %
  bool lm83SdaPreferred = false;          // sDA ≥ 75 %
  bool lm83AseLikelyDiscomfort = false;   // ASE > 10 %
  LeedDaylightPoints leed;                // the grid taken as one regularly occupied space
};

Result<DaylightMetrics> daylightMetrics(const AnnualIlluminance& illuminance, const DaylightMetricsOptions& options = {});

// The per-sensor columns' names, with the thresholds and unit in each (e.g. "DA_300lx_pct",
// "UDI_100-2000lx_pct", "E_p50_lx", "sun_hours_1000lx_h", "sDA_pass" 0/1).
std::vector<std::string> daylightCsvColumns(const DaylightMetricsOptions& options);
// One row per sensor: the table's columns (x, y, z, nx, ny, nz: design/points_file.h), then
// daylightCsvColumns; written atomically.
Status writeDaylightCsv(const std::string& path, const PointsTable& table, const DaylightMetrics& metrics, const DaylightMetricsOptions& options);
// The same for a grid's points, in the scene file's frame (design/lighting.h gridTable).
Status writeDaylightCsv(const std::string& path, const CalculationGrid& grid, const FileFrame& frame, const DaylightMetrics& metrics,
                        const DaylightMetricsOptions& options);

enum class DaylightMetric { DaylightAutonomy, ContinuousDaylightAutonomy, UdiFellShort, UdiUseful, UdiExceeded, SunlitHours };
// The metric per sensor (%, or hours for SunlitHours), in the sensors' order.
std::vector<double> daylightMetricValues(const DaylightMetrics& metrics, DaylightMetric metric);
// Its plan (design/false_colour.h): a percentage on a 0–100 % scale with lines at 25, 50 and 75 %;
// sunlit hours on a scale from 0 to the greatest (rounded up), a line at aseHours among its levels.
// `plan` gives the drawing's frame (design/lighting.h planOptions); its title, unit and levels are replaced.
FalseColourImage daylightPlan(const CalculationGrid& grid, const DaylightMetrics& metrics, DaylightMetric metric,
                              const DaylightMetricsOptions& options, const FalseColourOptions& plan = {});

// A report page (design/report.h): the spatial metrics against LM-83's and LEED v4.1's criteria
// (PASS/FAIL, points), the options used, and the plans of DA, cDA, the three UDI bands and the
// sunlit hours. `csvFile`: where writeDaylightCsv wrote the per-sensor values (named on the page), or empty.
ReportPage daylightReportPage(const DaylightMetrics& metrics, const CalculationGrid& grid, const DaylightMetricsOptions& options,
                              const FalseColourOptions& plan = {}, const std::string& csvFile = {});

}  // namespace lambert
