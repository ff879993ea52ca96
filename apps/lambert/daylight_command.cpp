// `lambert daylight`: a year of daylight on a work plane from a weather file (design/annual_daylight.h,
// daylight coefficients), and the climate-based metrics a LEED or LM-83 calculation asks for
// (design/daylight_metrics.h): sDA300/50%, ASE1000,250h, UDI, DA, cDA, each sensor's mean and
// percentiles; written as a CSV per sensor, a plan per metric, and a report page (HTML or PDF).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "commands.h"
#include "lambert/core/atomic_file.h"
#include "lambert/core/text.h"
#include "lambert/core/timer.h"
#include "lambert/design/annual_daylight.h"
#include "lambert/design/lighting.h"
#include "lambert/io/png.h"
#include "lambert/load/epw.h"
#include "lambert/version.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct DaylightCommandOptions {
  SolvingOptions solve;
  std::string weather;
  double workPlaneMetres = 0.8;
  double spacingMetres = 0.6;
  double marginMetres = 0;
  std::vector<std::string> metrics{"sDA", "ASE", "UDI"};
  std::string occupied = "8-18";
  DaylightMetricsOptions thresholds;
  std::vector<double> udi;  // --udi LOW,HIGH
  int skySubdivisions = 1, directSkySubdivisions = 4, sunSubdivisions = 4;
  std::string output;  // PREFIX: PREFIX.csv, PREFIX-<metric>.png
  std::vector<std::string> reports;
  std::string hourly;  // CSV of every hour at every sensor
  std::vector<double> north;  // --north X,Y,Z in the scene file's frame
};

std::string lowercase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// A threshold as it is written: 300, 0.5, 2.5 (at most 6 significant digits).
std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

struct MetricChoice {
  const char* name;
  std::vector<DaylightMetric> plans;
};
const MetricChoice kMetrics[] = {{"sDA", {DaylightMetric::DaylightAutonomy}},
                                 {"DA", {DaylightMetric::DaylightAutonomy}},
                                 {"cDA", {DaylightMetric::ContinuousDaylightAutonomy}},
                                 {"ASE", {DaylightMetric::SunlitHours}},
                                 {"UDI", {DaylightMetric::UdiFellShort, DaylightMetric::UdiUseful, DaylightMetric::UdiExceeded}}};

const char* planName(DaylightMetric metric) {
  switch (metric) {
    case DaylightMetric::DaylightAutonomy: return "da";
    case DaylightMetric::ContinuousDaylightAutonomy: return "cda";
    case DaylightMetric::UdiFellShort: return "udi-fell-short";
    case DaylightMetric::UdiUseful: return "udi-useful";
    case DaylightMetric::UdiExceeded: return "udi-exceeded";
    case DaylightMetric::SunlitHours: return "sunlit-hours";
  }
  return "metric";
}

Status writeHourlyCsv(const std::string& path, const AnnualIlluminance& a) {
  std::ostringstream out;
  out << "month,day,hour";
  for (std::size_t s = 0; s < a.sensors; ++s) out << ",E" << s + 1;
  out << "\n";
  char buffer[32];
  for (std::size_t h = 0; h < a.hours.size(); ++h) {
    out << a.hours[h].month << ',' << a.hours[h].day << ',' << a.hours[h].hour;
    for (std::size_t s = 0; s < a.sensors; ++s) {
      std::snprintf(buffer, sizeof buffer, ",%.1f", a.totalLux[h * a.sensors + s]);
      out << buffer;
    }
    out << "\n";
  }
  const std::string text = out.str();
  return writeFileAtomically(path, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

int runDaylight(DaylightCommandOptions o) {
  const Timer total;
  const std::string command = "daylight";
  // What is asked for, checked before any work.
  std::vector<DaylightMetric> plans;
  for (const std::string& name : o.metrics) {
    const MetricChoice* found = nullptr;
    for (const MetricChoice& m : kMetrics)
      if (lowercase(name) == lowercase(m.name)) found = &m;
    if (!found) return fail(command, "--metrics: \"" + name + "\" is not one of sDA, ASE, UDI, DA, cDA");
    for (DaylightMetric p : found->plans)
      if (std::find(plans.begin(), plans.end(), p) == plans.end()) plans.push_back(p);
  }
  {
    double first = 0, last = 0;
    char dash = 0;
    std::istringstream in(o.occupied);
    if (!(in >> first >> dash >> last) || dash != '-' || !(in >> std::ws).eof())
      return fail(command, "--occupied \"" + o.occupied + "\": give FIRST-LAST in hours of local standard time, e.g. 8-18");
    o.thresholds.firstOccupiedHour = first;
    o.thresholds.lastOccupiedHour = last;
  }
  if (!o.udi.empty()) {
    if (o.udi.size() != 2) return fail(command, "--udi: give LOW,HIGH in lux, e.g. 100,2000");
    o.thresholds.udiLowerLux = o.udi[0];
    o.thresholds.udiUpperLux = o.udi[1];
  }
  for (const std::string& report : o.reports) {
    const std::string e = lowercaseExtension(report);
    if (e != ".html" && e != ".htm" && e != ".pdf") return fail(command, "--report " + report + ": give a path ending in .html or .pdf");
  }
  Result<WeatherData> weather = readEpw(o.weather);
  if (!weather) return fail(command, weather.error().message);
  std::optional<Scene> scene = findScene(command, o.solve);
  if (!scene) return 2;
  Result<RadiosityOptions> engineOptions = radiosityOptions(*scene, o.solve);
  if (!engineOptions) return fail(command, engineOptions.error().message);
  WorkPlaneSpec plane;
  plane.heightMetres = o.workPlaneMetres;
  plane.spacingMetres = o.spacingMetres;
  plane.marginMetres = o.marginMetres;
  Result<CalculationGrid> grid = workPlaneGrid(*scene, plane);
  if (!grid) return fail(command, grid.error().message);
  FalseColourOptions planFrame = planOptions(*scene, {});
  for (const Light& light : scene->lights)
    if (light.kind == LightKind::Sky && light.sky) planFrame.north = light.sky->north();
  if (!o.north.empty()) {
    const Vec3 north = o.north.size() == 3 ? scene->fileFrame.sceneDirection({o.north[0], o.north[1], o.north[2]}) : Vec3{};
    if (!(std::fabs(north.x) + std::fabs(north.z) > 1e-9))
      return fail(command, "--north: give X,Y,Z, a direction with a horizontal part, in the scene file's frame");
    planFrame.north = normalize(Vec3{north.x, 0, north.z});
  }

  AnnualDaylightOptions options;
  options.coefficients.north = planFrame.north;
  options.coefficients.skySubdivisions = o.skySubdivisions;
  options.coefficients.directSkySubdivisions = o.directSkySubdivisions;
  options.coefficients.sunSubdivisions = o.sunSubdivisions;
  options.coefficients.showProgress = !o.solve.quiet && !o.solve.json;
  options.cacheDirectory = engineOptions->cacheDirectory;
  Result<AnnualDaylight> year = annualDaylight(*scene, grid->points, *weather, options, *engineOptions);
  if (!year) return fail(command, year.error().message);
  Result<DaylightMetrics> metrics = daylightMetrics(year->illuminance, o.thresholds);
  if (!metrics) return fail(command, metrics.error().message);

  // The files.
  std::string csv;
  std::vector<std::string> written;
  if (!o.output.empty()) {
    csv = o.output + ".csv";
    if (Status ok = writeDaylightCsv(csv, *grid, scene->fileFrame, *metrics, o.thresholds); !ok) return fail(command, ok.error().message);
    written.push_back(csv);
    for (DaylightMetric metric : plans) {
      const FalseColourImage image = daylightPlan(*grid, *metrics, metric, o.thresholds, planFrame);
      const std::string path = o.output + "-" + planName(metric) + ".png";
      if (Status ok = writePng(path, image.width, image.height, image.rgb); !ok) return fail(command, ok.error().message);
      written.push_back(path);
    }
  }
  if (!o.hourly.empty()) {
    if (Status ok = writeHourlyCsv(o.hourly, year->illuminance); !ok) return fail(command, ok.error().message);
    written.push_back(o.hourly);
  }
  if (!o.reports.empty()) {
    LightingReport report;
    report.title = "Annual daylight: " + scene->name;
    report.subtitle = weather->location.city + ", " + weather->location.country + " (" + std::filesystem::path(o.weather).filename().string() +
                      "), lambert " + version();
    report.pages.push_back(daylightReportPage(*metrics, *grid, o.thresholds, planFrame, csv.empty() ? std::string() : std::filesystem::path(csv).filename().string()));
    for (const std::string& path : o.reports) {
      if (Status ok = writeReportFile(report, path); !ok) return fail(command, ok.error().message);
      written.push_back(path);
    }
  }

  Stats stats;
  stats.add("scene", "scene", scene->name);
  stats.add("weather", "weather", weather->location.city + ", " + weather->location.country);
  // Daylight alone: the scene's own lights and skies (the weather file gives each hour's) and
  // emitting surfaces are left out, and the figures say so.
  std::int64_t leftOut = static_cast<std::int64_t>(scene->lights.size());
  for (const Surface& surface : scene->surfaces) leftOut += surface.emittedRadiance.maxComponent() > 0;
  if (leftOut > 0) stats.add("lights_left_out", "scene lights and emitting surfaces left out (daylight only)", leftOut);
  stats.add("sensors", "sensors", static_cast<std::int64_t>(grid->points.size()));
  stats.add("hours", "hours in the file", static_cast<std::int64_t>(weather->hours.size()));
  stats.add("daylight_hours", "hours with daylight", static_cast<std::int64_t>(year->daylightHours));
  stats.add("sun_hours", "hours with sun", static_cast<std::int64_t>(year->sunHours));
  stats.add("occupied_hours", "occupied hours", static_cast<std::int64_t>(metrics->occupiedHours));
  for (const std::string& name : o.metrics) {
    const std::string m = lowercase(name);
    if (m == "sda") stats.add("sda_percent", "sDA" + number(o.thresholds.sdaLux) + "/" + number(100 * o.thresholds.sdaTimeFraction) + "%", metrics->spatialDaylightAutonomy, "%");
    if (m == "ase") stats.add("ase_percent", "ASE" + number(o.thresholds.aseLux) + "," + number(o.thresholds.aseHours) + "h", metrics->annualSunlightExposure, "%");
    if (m == "udi") {
      stats.add("udi_fell_short_percent", "UDI fell short (mean)", metrics->meanUdiFellShort, "%");
      stats.add("udi_useful_percent", "UDI useful (mean)", metrics->meanUdiUseful, "%");
      stats.add("udi_exceeded_percent", "UDI exceeded (mean)", metrics->meanUdiExceeded, "%");
    }
    if (m == "da") stats.add("da_percent", "DA" + number(o.thresholds.daLux) + " (mean)", metrics->meanDaylightAutonomy, "%");
    if (m == "cda") stats.add("cda_percent", "cDA" + number(o.thresholds.daLux) + " (mean)", metrics->meanContinuousDaylightAutonomy, "%");
  }
  if (o.thresholds.blinds) stats.add("blinds_closed_hours", "hours with the blinds closed", static_cast<std::int64_t>(metrics->blindsClosedHours));
  stats.add("sky_patches", "sky patches (interreflected, sky component)", std::to_string(year->skyPatches) + ", " + std::to_string(year->directSkyPatches));
  stats.add("basis_suns", "basis suns", static_cast<std::int64_t>(year->basisSuns));
  stats.add("coefficients_cached", "coefficients read from the cache", std::string(year->coefficientsFromCache ? "yes" : "no"));
  stats.add("coefficient_seconds", "daylight coefficients", year->coefficientSeconds, "s");
  stats.add("hourly_seconds", "every hour", year->hourlySeconds, "s");
  std::string files;
  for (const std::string& f : written) files += (files.empty() ? "" : ", ") + f;
  if (!files.empty()) stats.add("written", "written", files);
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.solve.json, o.solve.quiet);
  return 0;
}

}  // namespace

std::function<int()> addDaylightCommand(CLI::App& app) {
  auto o = std::make_shared<DaylightCommandOptions>();
  CLI::App* cmd = app.add_subcommand("daylight", "A year of daylight from a weather file (EPW) by daylight coefficients: "
                                                 "sDA, ASE, UDI, DA on a work plane (IES LM-83, LEED v4.1)");
  addSolveOptions(*cmd, o->solve);
  cmd->add_option("--weather", o->weather, "The weather file: EnergyPlus EPW (hourly direct normal and diffuse horizontal light)")->required();
  cmd->add_option("--work-plane", o->workPlaneMetres, "The work plane's height above the floor, metres")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--grid-spacing", o->spacingMetres, "Sensor spacing on the work plane, metres (LM-83: at most 0.61)")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--work-plane-margin", o->marginMetres, "Border left out of the work plane, metres")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--metrics", o->metrics, "Metrics printed and drawn: sDA, ASE, UDI, DA, cDA (the CSV has them all)")->delimiter(',')->capture_default_str();
  cmd->add_option("--occupied", o->occupied, "Occupied hours, local standard time, FIRST-LAST")->capture_default_str();
  cmd->add_option("--sda-lux", o->thresholds.sdaLux, "sDA's illuminance threshold, lux")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--ase-lux", o->thresholds.aseLux, "ASE's direct-sun threshold, lux")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--ase-hours", o->thresholds.aseHours, "ASE's hours a year")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--da-lux", o->thresholds.daLux, "Daylight autonomy's threshold, lux")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--udi", o->udi, "UDI's bands: LOW,HIGH lux (default 100,2000)")->delimiter(',');
  cmd->add_flag("--blinds", o->thresholds.blinds, "LM-83's blinds: closed in an hour where more than 2% of the sensors get over --ase-lux of direct sun");
  cmd->add_option("--blinds-transmittance", o->thresholds.blindsTransmittance, "What closed blinds let through of the sky's light (direct sun blocked)")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--north", o->north, "North: X,Y,Z in the scene file's frame (its horizontal part; default: the scene's sky's, else -z)")
      ->delimiter(',');
  cmd->add_option("--sky-subdivisions", o->skySubdivisions, "Reinhart MF of the sky patches for interreflected light (1: Tregenza's 145)")->capture_default_str()->check(CLI::Range(1, 8));
  cmd->add_option("--direct-sky-subdivisions", o->directSkySubdivisions, "Reinhart MF of the sky patches for the sky component")->capture_default_str()->check(CLI::Range(1, 16));
  cmd->add_option("--sun-subdivisions", o->sunSubdivisions, "Reinhart MF of the patches whose centres are the basis suns")->capture_default_str()->check(CLI::Range(1, 16));
  cmd->add_option("-o,--output", o->output, "Write PREFIX.csv (every sensor's metrics) and PREFIX-<metric>.png (plans)");
  cmd->add_option("--report", o->reports, "A report page: .html or .pdf (repeatable)");
  cmd->add_option("--hourly", o->hourly, "Write every hour's illuminance at every sensor (CSV, lux)");
  return [o] { return runDaylight(*o); };
}

}  // namespace lambert::cli
