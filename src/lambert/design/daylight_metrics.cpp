#include "lambert/design/daylight_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lambert/design/lighting.h"

namespace lambert {
namespace {

std::string number(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

// a ≥ b·(1 − 1e-12): a count against a fraction of a count, without a product rounded just above
// a whole number (0.29 × 100 = 28.999999999999996) deciding it.
bool atLeast(double count, double bound) { return count >= bound - 1e-9 * std::max(1.0, std::fabs(bound)); }
bool moreThan(double count, double bound) { return count > bound + 1e-9 * std::max(1.0, std::fabs(bound)); }

int daysInMonth(int month) {
  static const int days[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};  // February's 29th allowed (a leap year's file)
  return days[month - 1];
}

// The p-th percentile (0..100) of sorted values: linear between the order statistics, the rank
// r = p/100 · (n − 1) from 0 (numpy's default, Hyndman & Fan's type 7).
double percentileOfSorted(const std::vector<float>& sorted, double p) {
  const double r = p / 100 * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(r));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (r - static_cast<double>(lo)) * (static_cast<double>(sorted[hi]) - sorted[lo]);
}

Status checkOptions(const DaylightMetricsOptions& o) {
  auto finite = [](double v) { return std::isfinite(v); };
  if (!(finite(o.firstOccupiedHour) && finite(o.lastOccupiedHour) && o.firstOccupiedHour >= 0 && o.lastOccupiedHour <= 24 &&
        o.firstOccupiedHour < o.lastOccupiedHour))
    return Error{"daylight metrics: the occupied hours " + number(o.firstOccupiedHour) + " to " + number(o.lastOccupiedHour) +
                 " are not a span of the day (0 ≤ firstOccupiedHour < lastOccupiedHour ≤ 24)"};
  if (!(finite(o.sdaLux) && o.sdaLux > 0)) return Error{"daylight metrics: sdaLux " + number(o.sdaLux) + " must be a positive illuminance (lx)"};
  if (!(o.sdaTimeFraction > 0 && o.sdaTimeFraction <= 1))
    return Error{"daylight metrics: sdaTimeFraction " + number(o.sdaTimeFraction) + " must lie in (0, 1] (LM-83: 0.5)"};
  if (!(finite(o.aseLux) && o.aseLux > 0)) return Error{"daylight metrics: aseLux " + number(o.aseLux) + " must be a positive illuminance (lx)"};
  if (!(finite(o.aseHours) && o.aseHours >= 0)) return Error{"daylight metrics: aseHours " + number(o.aseHours) + " must be a number of hours ≥ 0"};
  if (!(finite(o.udiLowerLux) && finite(o.udiUpperLux) && o.udiLowerLux >= 0 && o.udiLowerLux < o.udiUpperLux))
    return Error{"daylight metrics: the UDI band " + number(o.udiLowerLux) + " to " + number(o.udiUpperLux) +
                 " lx must have 0 ≤ udiLowerLux < udiUpperLux"};
  if (!(finite(o.daLux) && o.daLux > 0)) return Error{"daylight metrics: daLux " + number(o.daLux) + " must be a positive illuminance (lx)"};
  if (!(o.blindsSensorShare >= 0 && o.blindsSensorShare < 1))
    return Error{"daylight metrics: blindsSensorShare " + number(o.blindsSensorShare) + " must lie in [0, 1) (LM-83: 0.02)"};
  if (!(o.blindsTransmittance >= 0 && o.blindsTransmittance <= 1))
    return Error{"daylight metrics: blindsTransmittance " + number(o.blindsTransmittance) + " must lie in [0, 1]"};
  for (double p : o.percentiles)
    if (!(p >= 0 && p <= 100)) return Error{"daylight metrics: the percentile " + number(p) + " must lie in [0, 100]"};
  return Ok{};
}

}  // namespace

Result<LeedDaylightPoints> leedV41DaylightPoints(std::span<const double> sdaPercent, std::span<const double> asePercent,
                                                 std::span<const double> areas) {
  if (sdaPercent.empty()) return Error{"LEED daylight points: no space given"};
  if (asePercent.size() != sdaPercent.size() || areas.size() != sdaPercent.size())
    return Error{"LEED daylight points: " + std::to_string(sdaPercent.size()) + " sDA values, " + std::to_string(asePercent.size()) +
                 " ASE values and " + std::to_string(areas.size()) + " areas; one of each per space needed"};
  LeedDaylightPoints out;
  double area = 0, weighted = 0;
  out.everySpaceAtLeast55 = true;
  for (std::size_t i = 0; i < sdaPercent.size(); ++i) {
    if (!(areas[i] > 0 && std::isfinite(areas[i]))) return Error{"LEED daylight points: space " + std::to_string(i + 1) + "'s area must be positive"};
    area += areas[i];
    weighted += areas[i] * sdaPercent[i];
    out.everySpaceAtLeast55 &= sdaPercent[i] >= 55;
    out.glareStrategyRequired |= asePercent[i] > 10;
  }
  out.averageSda = weighted / area;
  // One space: its own value, not a quotient that could round below a threshold it meets.
  if (sdaPercent.size() == 1) out.averageSda = sdaPercent[0];
  out.averagePoints = out.averageSda >= 75 ? 3 : out.averageSda >= 55 ? 2 : out.averageSda >= 40 ? 1 : 0;
  out.points = out.averagePoints + (out.everySpaceAtLeast55 && (out.averagePoints == 1 || out.averagePoints == 2) ? 1 : 0);
  return out;
}

Result<DaylightMetrics> daylightMetrics(const AnnualIlluminance& in, const DaylightMetricsOptions& options) {
  if (Status ok = checkOptions(options); !ok) return ok.error();
  const std::size_t sensors = in.sensors, rows = in.hours.size();
  if (sensors == 0) return Error{"daylight metrics: no sensors"};
  if (in.totalLux.size() != rows * sensors)
    return Error{"daylight metrics: totalLux holds " + std::to_string(in.totalLux.size()) + " values, not hours × sensors = " + std::to_string(rows) +
                 " × " + std::to_string(sensors)};
  if (in.directSunLux.size() != rows * sensors)
    return Error{"daylight metrics: directSunLux holds " + std::to_string(in.directSunLux.size()) + " values, not hours × sensors = " +
                 std::to_string(rows) + " × " + std::to_string(sensors) + " (ASE and the blinds need the direct sun)"};

  // Occupied rows: the interval [hour − 1, hour) within [first, last).
  std::vector<std::size_t> occupied;
  for (std::size_t h = 0; h < rows; ++h) {
    const DaylightHourInfo& t = in.hours[h];
    if (t.month < 1 || t.month > 12 || t.day < 1 || t.day > daysInMonth(t.month) || t.hour < 1 || t.hour > 24)
      return Error{"daylight metrics: row " + std::to_string(h + 1) + " is month " + std::to_string(t.month) + ", day " + std::to_string(t.day) +
                   ", hour " + std::to_string(t.hour) + " (months 1–12, days of the month, hours 1–24 ending at that clock hour)"};
    if (t.hour - 1 >= options.firstOccupiedHour && t.hour <= options.lastOccupiedHour) occupied.push_back(h);
  }
  if (occupied.empty())
    return Error{"daylight metrics: no row lies in the occupied hours " + number(options.firstOccupiedHour) + " to " + number(options.lastOccupiedHour)};
  const std::size_t hours = occupied.size();

  DaylightMetrics out;
  out.occupiedHours = static_cast<int>(hours);
  std::vector<double> daCount(sensors, 0), cdaSum(sensors, 0), fellShort(sensors, 0), useful(sensors, 0), exceeded(sensors, 0), sum(sensors, 0),
      sunlit(sensors, 0), sdaCount(sensors, 0);
  std::vector<float> bySensor(sensors * hours);  // sensor-major, each sensor's occupied hours (blinds applied), for the percentiles
  for (std::size_t k = 0; k < hours; ++k) {
    const std::size_t h = occupied[k];
    const float* total = in.totalLux.data() + h * sensors;
    const float* sun = in.directSunLux.data() + h * sensors;
    std::size_t sunlitSensors = 0;
    for (std::size_t s = 0; s < sensors; ++s) {
      if (!(std::isfinite(total[s]) && total[s] >= 0 && std::isfinite(sun[s]) && sun[s] >= 0))
        return Error{"daylight metrics: row " + std::to_string(h + 1) + ", sensor " + std::to_string(s + 1) + ": illuminance " + number(total[s]) +
                     " lx, direct sun " + number(sun[s]) + " lx; both must be finite and ≥ 0"};
      if (sun[s] >= options.aseLux) {
        ++sunlitSensors;
        sunlit[s] += 1;
      }
    }
    const bool closed = options.blinds && moreThan(static_cast<double>(sunlitSensors), options.blindsSensorShare * static_cast<double>(sensors));
    out.blindsClosedHours += closed;
    for (std::size_t s = 0; s < sensors; ++s) {
      // Closed: the sun stopped, the rest through the blinds (total ≥ sun in theory; a matrix's rounding clamped).
      const double e = closed ? std::max(0.0, static_cast<double>(total[s]) - sun[s]) * options.blindsTransmittance : total[s];
      daCount[s] += e >= options.daLux;
      cdaSum[s] += std::min(1.0, e / options.daLux);
      sdaCount[s] += e >= options.sdaLux;
      fellShort[s] += e < options.udiLowerLux;
      useful[s] += e >= options.udiLowerLux && e <= options.udiUpperLux;
      exceeded[s] += e > options.udiUpperLux;
      sum[s] += e;
      bySensor[s * hours + k] = static_cast<float>(e);
    }
  }

  const double n = static_cast<double>(hours);
  out.sensors.resize(sensors);
  std::size_t sdaPasses = 0, aseExceeded = 0;
  std::vector<float> sorted(hours);
  for (std::size_t s = 0; s < sensors; ++s) {
    SensorDaylight& d = out.sensors[s];
    d.daylightAutonomy = 100 * daCount[s] / n;
    d.continuousDaylightAutonomy = 100 * cdaSum[s] / n;
    d.udiFellShort = 100 * fellShort[s] / n;
    d.udiUseful = 100 * useful[s] / n;
    d.udiExceeded = 100 * exceeded[s] / n;
    d.meanLux = sum[s] / n;
    d.sunlitHours = sunlit[s];
    d.sdaPass = atLeast(sdaCount[s], options.sdaTimeFraction * n);
    d.aseExceeded = moreThan(sunlit[s], options.aseHours);
    sdaPasses += d.sdaPass;
    aseExceeded += d.aseExceeded;
    if (!options.percentiles.empty()) {
      std::copy(bySensor.begin() + static_cast<std::ptrdiff_t>(s * hours), bySensor.begin() + static_cast<std::ptrdiff_t>((s + 1) * hours), sorted.begin());
      std::sort(sorted.begin(), sorted.end());
      for (double p : options.percentiles) d.percentileLux.push_back(percentileOfSorted(sorted, p));
    }
    out.meanDaylightAutonomy += d.daylightAutonomy;
    out.meanContinuousDaylightAutonomy += d.continuousDaylightAutonomy;
    out.meanUdiFellShort += d.udiFellShort;
    out.meanUdiUseful += d.udiUseful;
    out.meanUdiExceeded += d.udiExceeded;
    out.meanLux += d.meanLux;
  }
  const double m = static_cast<double>(sensors);
  // 100·count/m: an exact quotient, so that 11 of 20 is 55 exactly, not a hair below.
  out.spatialDaylightAutonomy = 100.0 * static_cast<double>(sdaPasses) / m;
  out.annualSunlightExposure = 100.0 * static_cast<double>(aseExceeded) / m;
  out.meanDaylightAutonomy /= m;
  out.meanContinuousDaylightAutonomy /= m;
  out.meanUdiFellShort /= m;
  out.meanUdiUseful /= m;
  out.meanUdiExceeded /= m;
  out.meanLux /= m;
  out.lm83SdaNominallyAccepted = out.spatialDaylightAutonomy >= 55;
  out.lm83SdaPreferred = out.spatialDaylightAutonomy >= 75;
  out.lm83AseLikelyDiscomfort = out.annualSunlightExposure > 10;
  const double one = 1;
  out.leed = *leedV41DaylightPoints({&out.spatialDaylightAutonomy, 1}, {&out.annualSunlightExposure, 1}, {&one, 1});
  return out;
}

std::vector<std::string> daylightCsvColumns(const DaylightMetricsOptions& o) {
  std::vector<std::string> columns{"DA_" + number(o.daLux) + "lx_pct",
                                   "cDA_" + number(o.daLux) + "lx_pct",
                                   "UDI_below_" + number(o.udiLowerLux) + "lx_pct",
                                   "UDI_" + number(o.udiLowerLux) + "-" + number(o.udiUpperLux) + "lx_pct",
                                   "UDI_above_" + number(o.udiUpperLux) + "lx_pct",
                                   "E_mean_lx"};
  for (double p : o.percentiles) columns.push_back("E_p" + number(p) + "_lx");
  columns.push_back("sun_hours_" + number(o.aseLux) + "lx_h");
  columns.push_back("sDA_" + number(o.sdaLux) + "lx_" + number(100 * o.sdaTimeFraction) + "pct_pass");
  columns.push_back("ASE_" + number(o.aseLux) + "lx_" + number(o.aseHours) + "h_exceeded");
  return columns;
}

Status writeDaylightCsv(const std::string& path, const PointsTable& table, const DaylightMetrics& metrics, const DaylightMetricsOptions& options) {
  if (table.rows.size() != metrics.sensors.size())
    return Error{"writeDaylightCsv: " + std::to_string(table.rows.size()) + " points but " + std::to_string(metrics.sensors.size()) + " sensors"};
  const std::vector<std::string> columns = daylightCsvColumns(options);
  std::vector<double> values;
  values.reserve(columns.size() * metrics.sensors.size());
  for (const SensorDaylight& d : metrics.sensors) {
    if (d.percentileLux.size() != options.percentiles.size())
      return Error{"writeDaylightCsv: the metrics were computed with other percentiles than the options name"};
    values.insert(values.end(), {d.daylightAutonomy, d.continuousDaylightAutonomy, d.udiFellShort, d.udiUseful, d.udiExceeded, d.meanLux});
    values.insert(values.end(), d.percentileLux.begin(), d.percentileLux.end());
    values.insert(values.end(), {d.sunlitHours, d.sdaPass ? 1.0 : 0.0, d.aseExceeded ? 1.0 : 0.0});
  }
  return writePointsCsvColumns(path, table, columns, values);
}

Status writeDaylightCsv(const std::string& path, const CalculationGrid& grid, const FileFrame& frame, const DaylightMetrics& metrics,
                        const DaylightMetricsOptions& options) {
  return writeDaylightCsv(path, gridTable(grid, frame), metrics, options);
}

std::vector<double> daylightMetricValues(const DaylightMetrics& metrics, DaylightMetric metric) {
  std::vector<double> values;
  values.reserve(metrics.sensors.size());
  for (const SensorDaylight& d : metrics.sensors) switch (metric) {
      case DaylightMetric::DaylightAutonomy: values.push_back(d.daylightAutonomy); break;
      case DaylightMetric::ContinuousDaylightAutonomy: values.push_back(d.continuousDaylightAutonomy); break;
      case DaylightMetric::UdiFellShort: values.push_back(d.udiFellShort); break;
      case DaylightMetric::UdiUseful: values.push_back(d.udiUseful); break;
      case DaylightMetric::UdiExceeded: values.push_back(d.udiExceeded); break;
      case DaylightMetric::SunlitHours: values.push_back(d.sunlitHours); break;
    }
  return values;
}

namespace {

std::string metricTitle(DaylightMetric metric, const DaylightMetricsOptions& o) {
  switch (metric) {
    case DaylightMetric::DaylightAutonomy: return "Daylight autonomy DA" + number(o.daLux) + " lx (% of occupied hours)";
    case DaylightMetric::ContinuousDaylightAutonomy: return "Continuous daylight autonomy cDA" + number(o.daLux) + " lx (% of occupied hours)";
    case DaylightMetric::UdiFellShort: return "UDI fell short, E < " + number(o.udiLowerLux) + " lx (% of occupied hours)";
    case DaylightMetric::UdiUseful: return "UDI useful, " + number(o.udiLowerLux) + "-" + number(o.udiUpperLux) + " lx (% of occupied hours)";
    case DaylightMetric::UdiExceeded: return "UDI exceeded, E > " + number(o.udiUpperLux) + " lx (% of occupied hours)";
    case DaylightMetric::SunlitHours: return "Direct sun >= " + number(o.aseLux) + " lx, blinds open (occupied hours)";
  }
  return {};
}

std::string metricSymbol(DaylightMetric metric) {
  switch (metric) {
    case DaylightMetric::DaylightAutonomy: return "DA";
    case DaylightMetric::ContinuousDaylightAutonomy: return "cDA";
    case DaylightMetric::UdiFellShort:
    case DaylightMetric::UdiUseful:
    case DaylightMetric::UdiExceeded: return "UDI";
    case DaylightMetric::SunlitHours: return "sun hours ";
  }
  return {};
}

std::string passFail(bool pass) { return pass ? "PASS" : "FAIL"; }

}  // namespace

FalseColourImage daylightPlan(const CalculationGrid& grid, const DaylightMetrics& metrics, DaylightMetric metric, const DaylightMetricsOptions& options,
                              const FalseColourOptions& plan) {
  FalseColourOptions o = plan;
  o.title = grid.name + ": " + metricTitle(metric, options);
  o.figureSymbol = metricSymbol(metric);
  o.uniformityFigures = false;
  const std::vector<double> values = daylightMetricValues(metrics, metric);
  if (metric == DaylightMetric::SunlitHours) {
    o.unit = "h";
    double most = options.aseHours;
    for (double v : values) most = std::max(most, v);
    const std::vector<double> guide = roundLevels(std::max(most, 1.0), 6);
    const double step = guide.empty() ? 1 : guide.front();
    o.scaleMaximum = std::max(step, std::ceil(most / step - 1e-9) * step);
    if (o.scaleMaximum <= options.aseHours) o.scaleMaximum += step;  // the ASE line inside the scale, not at its top
    o.isoluxLevels = roundLevels(o.scaleMaximum, 6);
    // The ASE limit among the levels (its line is the ASE boundary), replacing a level too near it.
    std::erase_if(o.isoluxLevels, [&](double l) { return std::fabs(l - options.aseHours) < 0.3 * step; });
    if (options.aseHours > 0 && options.aseHours < o.scaleMaximum) o.isoluxLevels.push_back(options.aseHours);
    std::sort(o.isoluxLevels.begin(), o.isoluxLevels.end());
  } else {
    o.unit = "%";
    o.scaleMaximum = 100;
    o.isoluxLevels = {25, 50, 75};
  }
  return falseColourImage(grid, values, o);
}

ReportPage daylightReportPage(const DaylightMetrics& metrics, const CalculationGrid& grid, const DaylightMetricsOptions& o,
                              const FalseColourOptions& plan, const std::string& csvFile) {
  ReportPage page{"Annual daylight: " + grid.name, "daylight-" + gridFileStem(grid.name), {}};
  const std::string sda = "sDA" + number(o.sdaLux) + "/" + number(100 * o.sdaTimeFraction) + "%";
  const std::string ase = "ASE" + number(o.aseLux) + "," + number(o.aseHours) + "h";
  page.blocks.push_back(reportParagraph(
      std::to_string(metrics.sensors.size()) + " sensors, " + std::to_string(metrics.occupiedHours) + " occupied hours" +
      (o.blinds ? ", the blinds closed in " + std::to_string(metrics.blindsClosedHours) + " of them" : ", no blinds") + "." +
      (csvFile.empty() ? "" : " The per-sensor values: " + csvFile + ", one row per sensor.") +
      " Each sensor stands for an equal share of the area; spatial figures are percentages of the sensors."));
  const bool lm83Thresholds = o.sdaLux == 300 && o.sdaTimeFraction == 0.5 && o.aseLux == 1000 && o.aseHours == 250 && o.firstOccupiedHour == 8 &&
                              o.lastOccupiedHour == 18;
  ReportTable spatial{"Spatial metrics", {"metric", "value", "criterion", "result", "source"}, {}, "daylight-spatial"};
  spatial.rows = {
      {sda + " (% of sensors)", reportFixed(metrics.spatialDaylightAutonomy, 1), "≥ 55 % nominally accepted", passFail(metrics.lm83SdaNominallyAccepted), "IES LM-83-12"},
      {sda, reportFixed(metrics.spatialDaylightAutonomy, 1), "≥ 75 % preferred", passFail(metrics.lm83SdaPreferred), "IES LM-83-12"},
      {ase + " (% of sensors)", reportFixed(metrics.annualSunlightExposure, 1), "≤ 10 % (above: likely visual discomfort)",
       passFail(!metrics.lm83AseLikelyDiscomfort), "IES LM-83-12"},
      {"LEED points, sDA (the grid as one space)", std::to_string(metrics.leed.points) + " of 3",
       "average sDA ≥ 40/55/75 % → 1/2/3; every space ≥ 55 % → +1 up to 3", metrics.leed.points > 0 ? "PASS" : "FAIL", "LEED v4.1 BD+C EQ Daylight, option 1"},
      {"LEED, ASE", reportFixed(metrics.annualSunlightExposure, 1), "> 10 %: document how the space addresses glare",
       metrics.leed.glareStrategyRequired ? "glare strategy required" : "none required", "LEED v4.1 (v4 required ≤ 10 %)"},
      {"mean DA" + number(o.daLux) + " lx (%)", reportFixed(metrics.meanDaylightAutonomy, 1), "", "", "Reinhart 2006"},
      {"mean cDA" + number(o.daLux) + " lx (%)", reportFixed(metrics.meanContinuousDaylightAutonomy, 1), "", "", "Rogers 2006"},
      {"mean UDI fell short, < " + number(o.udiLowerLux) + " lx (%)", reportFixed(metrics.meanUdiFellShort, 1), "", "", "Nabil & Mardaljevic 2005"},
      {"mean UDI useful, " + number(o.udiLowerLux) + "–" + number(o.udiUpperLux) + " lx (%)", reportFixed(metrics.meanUdiUseful, 1), "", "",
       "Nabil & Mardaljevic 2005"},
      {"mean UDI exceeded, > " + number(o.udiUpperLux) + " lx (%)", reportFixed(metrics.meanUdiExceeded, 1), "", "", "Nabil & Mardaljevic 2005"},
      {"mean illuminance, occupied hours (lx)", reportFixed(metrics.meanLux, 0), "", "", ""}};
  page.blocks.push_back(reportTableBlock(std::move(spatial)));
  if (!lm83Thresholds)
    page.blocks.push_back(reportParagraph("The thresholds or hours differ from LM-83's (300 lx, 50 %, 1000 lx, 250 h, 8 am–6 pm): the criteria above "
                                          "are LM-83's and LEED's, applied to these figures for comparison only."));
  if (!o.blinds)
    page.blocks.push_back(reportParagraph("LM-83 and LEED ask for sDA with operable blinds; this one was computed without (the blinds option is off)."));

  ReportTable used{"Options", {"option", "value"}, {}, "daylight-options"};
  used.rows = {{"occupied hours (local standard time)", number(o.firstOccupiedHour) + ":00–" + number(o.lastOccupiedHour) +
                                                            ":00, every day (EPW hour h = the hour ending at h:00)"},
               {"occupied hours counted", std::to_string(metrics.occupiedHours)},
               {"sDA threshold", number(o.sdaLux) + " lx in ≥ " + number(100 * o.sdaTimeFraction) + " % of the occupied hours"},
               {"ASE threshold", "direct sun ≥ " + number(o.aseLux) + " lx in > " + number(o.aseHours) + " occupied hours, blinds open"},
               {"DA / cDA threshold", number(o.daLux) + " lx"},
               {"UDI bands", "< " + number(o.udiLowerLux) + " lx, " + number(o.udiLowerLux) + "–" + number(o.udiUpperLux) + " lx (both included), > " +
                                 number(o.udiUpperLux) + " lx"},
               {"blinds", o.blinds ? "closed in an hour where more than " + number(100 * o.blindsSensorShare) + " % of the sensors see direct sun ≥ " +
                                         number(o.aseLux) + " lx; then E = (E − E_sun) × " + number(o.blindsTransmittance)
                                   : "none"},
               {"blinds closed (occupied hours)", std::to_string(metrics.blindsClosedHours)}};
  std::string percentiles;
  for (double p : o.percentiles) percentiles += (percentiles.empty() ? "" : ", ") + number(p);
  used.rows.push_back({"percentiles of E (linear between order statistics)", percentiles.empty() ? "none" : percentiles});
  page.blocks.push_back(reportTableBlock(std::move(used)));
  if (o.blinds)
    page.blocks.push_back(reportParagraph("Blinds: a simplification of LM-83 §2.2.6 — one window group for the whole grid, the closed state not simulated "
                                          "but taken as the sky's and interreflected light times the blinds' transmittance " +
                                          number(o.blindsTransmittance) + " (DAYSIM's simple dynamic shading: 25 % of the diffuse light, no direct sun)."));

  for (DaylightMetric metric : {DaylightMetric::DaylightAutonomy, DaylightMetric::ContinuousDaylightAutonomy, DaylightMetric::UdiUseful,
                                DaylightMetric::UdiFellShort, DaylightMetric::UdiExceeded, DaylightMetric::SunlitHours}) {
    page.blocks.push_back(reportHeading(metricTitle(metric, o)));
    page.blocks.push_back(reportImageBlock(daylightPlan(grid, metrics, metric, o, plan), grid.name + ": " + metricTitle(metric, o)));
  }
  return page;
}

}  // namespace lambert
