#include "lambert/load/epw.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/light/perez_sky.h"

namespace lambert {
namespace {

constexpr double kRadians = kPi / 180;
constexpr int kDaysInMonth[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
constexpr double kDefaultDewPointCelsius = 11;  // gendaymtx's, for a file whose first dew points are missing

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t')) --e;
  return std::string(s.substr(b, e - b));
}

// One CSV line's fields, each trimmed; a field in double quotes may hold commas ("" is a quote).
std::vector<std::string> splitCsv(std::string_view line) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(trim(field));
      field.clear();
    } else {
      field += c;
    }
  }
  fields.push_back(trim(field));
  return fields;
}

std::optional<double> number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  const char* begin = s.data() + (s[0] == '+' ? 1 : 0);
  double value = 0;
  const auto [end, ec] = std::from_chars(begin, s.data() + s.size(), value);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<int> integer(const std::string& s) {
  const std::optional<double> x = number(s);
  if (!x || *x != std::floor(*x) || std::fabs(*x) > 1e6) return std::nullopt;
  return static_cast<int>(*x);
}

// "m/d" (spaces allowed: " 1/ 1") or a day of the year 1–365.
bool monthDay(const std::string& s, int& month, int& day) {
  const std::size_t slash = s.find('/');
  if (slash == std::string::npos) {
    const std::optional<int> n = integer(s);
    if (!n || *n < 1 || *n > 365) return false;
    month = 1;
    day = *n;
    while (day > kDaysInMonth[month - 1]) day -= kDaysInMonth[month++ - 1];
    return true;
  }
  const std::optional<int> m = integer(trim(s.substr(0, slash))), d = integer(trim(s.substr(slash + 1)));
  if (!m || !d || *m < 1 || *m > 12 || *d < 1 || *d > kDaysInMonth[*m - 1]) return false;
  month = *m;
  day = *d;
  return true;
}

struct Stamp {
  int month = 1, day = 1, hour = 1;
  bool operator==(const Stamp&) const = default;
};

std::string describe(const Stamp& s) {
  return std::to_string(s.month) + "/" + std::to_string(s.day) + " hour " + std::to_string(s.hour);
}

// The hour after `s`; 28 February is followed by 29 February when `leap`. 31 December wraps.
Stamp next(Stamp s, bool leap) {
  if (++s.hour <= 24) return s;
  s.hour = 1;
  const int days = s.month == 2 && (leap || s.day == 29) ? 29 : kDaysInMonth[s.month - 1];
  if (++s.day <= days) return s;
  s.day = 1;
  if (++s.month > 12) s.month = 1;
  return s;
}

// One kind of repair: how many rows, and the first few lines.
struct Repair {
  explicit Repair(std::string w) : what(std::move(w)) {}
  std::string what;  // "<what was wrong>: <what was done>"
  int rows = 0;
  std::vector<int> lines;
  void add(int line) {
    ++rows;
    if (lines.size() < 4) lines.push_back(line);
  }
  void report(const std::string& name) const {
    if (rows == 0) return;
    std::string where;
    for (std::size_t i = 0; i < lines.size(); ++i) where += (i ? ", " : "") + std::to_string(lines[i]);
    if (rows > static_cast<int>(lines.size())) where += ", …";
    warning(name + ":" + std::to_string(lines[0]) + ": " + what + " (" + std::to_string(rows) + " row" + (rows == 1 ? "" : "s") +
            ": line" + (rows == 1 ? " " : "s ") + where + ")");
  }
};

}  // namespace

Result<WeatherData> readEpw(const std::string& path) {
  Result<std::string> text = readWholeFile(path);
  if (!text) return Error{text.error().message};
  return readEpwText(*text, path);
}

Result<WeatherData> readEpwText(const std::string& input, const std::string& name) {
  std::string_view text = input;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<std::string_view> lines;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    at = end + 1;
  }
  auto at = [&](std::size_t index) { return name + ":" + std::to_string(index + 1) + ": "; };

  WeatherData out;
  out.path = name;
  // LOCATION,city,region,country,source,WMO,latitude,longitude,time zone,elevation
  const std::vector<std::string> location = lines.empty() ? std::vector<std::string>{} : splitCsv(lines[0]);
  std::string first = location.empty() ? "" : location[0];
  for (char& c : first) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (first != "LOCATION")
    return Error{at(0) + "not an EPW weather file: its first line must be LOCATION,city,region,country,source,WMO,latitude,longitude,"
                         "time zone,elevation (found \"" + std::string(lines.empty() ? "" : lines[0].substr(0, 40)) + "\")"};
  if (location.size() < 10)
    return Error{at(0) + "the LOCATION line has " + std::to_string(location.size()) +
                 " fields, not the 10 of LOCATION,city,region,country,source,WMO,latitude,longitude,time zone,elevation: complete it"};
  out.location.city = location[1];
  out.location.region = location[2];
  out.location.country = location[3];
  out.location.source = location[4];
  out.location.station = location[5];
  struct Angle {
    const char* what;
    int field;
    double low, high;
    double* into;
  };
  for (const Angle& a : {Angle{"latitude (degrees, north positive)", 7, -90, 90, &out.location.latitudeDegrees},
                         Angle{"longitude (degrees, east positive)", 8, -180, 180, &out.location.longitudeDegrees},
                         Angle{"time zone (hours from UTC, east positive)", 9, -12, 14, &out.location.timeZoneHours}}) {
    const std::optional<double> x = number(location[a.field - 1]);
    if (!x || *x < a.low || *x > a.high)
      return Error{at(0) + "the " + a.what + " \"" + location[a.field - 1] + "\" is not a number within [" + std::to_string(static_cast<int>(a.low)) +
                   ", " + std::to_string(static_cast<int>(a.high)) + "]: correct the LOCATION line's field " + std::to_string(a.field)};
    *a.into = *x;
  }
  if (const std::optional<double> elevation = number(location[9]))
    out.location.elevationMetres = *elevation;
  else
    warning(at(0) + "the elevation \"" + location[9] + "\" is not a number: taken as 0 m");

  // DATA PERIODS,#periods,records per hour,name,start weekday,start day,end day: the last header line.
  std::size_t periods = lines.size();
  for (std::size_t i = 1; i < lines.size() && i < 32; ++i) {
    const std::vector<std::string> f = splitCsv(lines[i]);
    std::string key = f[0];
    for (char& c : key) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (key == "DATA PERIODS") {
      periods = i;
      break;
    }
    if (integer(f[0])) break;  // a data row: the header ended without one
  }
  if (periods == lines.size())
    return Error{at(std::min<std::size_t>(lines.size() - 1, 7)) +
                 "no DATA PERIODS line ends the header: add one (\"DATA PERIODS,1,1,Data,Sunday, 1/ 1,12/31\" for a year) before the first row"};
  const std::vector<std::string> period = splitCsv(lines[periods]);
  Stamp start, end;
  end.hour = 24;
  {
    const std::optional<int> count = period.size() > 1 ? integer(period[1]) : std::nullopt;
    const std::optional<int> perHour = period.size() > 2 ? integer(period[2]) : std::nullopt;
    if (!count || *count != 1)
      return Error{at(periods) + "DATA PERIODS gives " + (period.size() > 1 ? "\"" + period[1] + "\"" : std::string("no")) +
                   " data periods: lambert reads files of one period (split the file, one period each)"};
    if (!perHour || *perHour != 1)
      return Error{at(periods) + "DATA PERIODS gives " + (period.size() > 2 ? "\"" + period[2] + "\"" : std::string("no")) +
                   " records an hour: lambert reads hourly files (1 record an hour); average the sub-hourly records first"};
    if (period.size() < 7 || !monthDay(period[5], start.month, start.day) || !monthDay(period[6], end.month, end.day))
      return Error{at(periods) + "DATA PERIODS' start and end days (fields 6 and 7: \"" + (period.size() > 5 ? period[5] : "") + "\", \"" +
                   (period.size() > 6 ? period[6] : "") + "\") are not month/day dates: give them as \" 1/ 1\", \"12/31\""};
  }
  int periodDays = 0;
  for (Stamp s{start.month, start.day, 1};; s = next(s, false)) {
    if (s.hour == 1) ++periodDays;
    if (s == end || periodDays > 366) break;
  }

  Repair leap{"29 February left out (lambert's year has 365 days: light/weather.h)"};
  Repair negativeRadiation{"negative radiation set to 0"};
  Repair derivedRadiation{"a missing radiation (≥ 9999) made from the other two, global = direct·cos Z + diffuse"};
  Repair zeroRadiation{"two or three radiations missing (≥ 9999): the missing ones set to 0"};
  Repair illuminance{"a missing (≥ 999900), negative or zero illuminance beside positive radiation made from the radiation by "
                     "Perez et al. 1990's luminous efficacies"};
  Repair temperature{"a missing dry bulb or dew point (≥ 99.9 °C) taken from the hour before"};
  double lastDryBulb = 20, lastDewPoint = kDefaultDewPointCelsius;

  Stamp previous;
  bool started = false, ended = false;
  std::size_t lastRow = periods;
  for (std::size_t i = periods + 1; i < lines.size(); ++i) {
    if (lines[i].find_first_not_of(" \t,") == std::string_view::npos) continue;  // blank
    const std::vector<std::string> f = splitCsv(lines[i]);
    if (ended)
      return Error{at(i) + "a row after the data period's end (" + describe(end) + ", DATA PERIODS on line " + std::to_string(periods + 1) +
                   "): remove the extra rows, or correct the period's end day"};
    if (f.size() < 19)
      return Error{at(i) + "the row has " + std::to_string(f.size()) +
                   " fields; an EPW row has 35, and lambert needs the first 19 (through diffuse horizontal illuminance)"};
    const std::optional<int> month = integer(f[1]), day = integer(f[2]), hour = integer(f[3]);
    if (!month || !day || !hour || *month < 1 || *month > 12 || *day < 1 || *day > (*month == 2 ? 29 : kDaysInMonth[*month - 1]) || *hour < 1 ||
        *hour > 24)
      return Error{at(i) + "month, day and hour (fields 2–4: \"" + f[1] + "\", \"" + f[2] + "\", \"" + f[3] +
                   "\") are not a date and an hour 1–24 (the hour ending then)"};
    const Stamp stamp{*month, *day, *hour};
    const bool isLeapDay = stamp.month == 2 && stamp.day == 29;
    const Stamp expected = started ? next(previous, isLeapDay) : Stamp{start.month, start.day, 1};
    if (!(stamp == expected))
      return Error{at(i) + "the row is " + describe(stamp) + " where " + describe(expected) + " belongs" +
                   (started ? " (after line " + std::to_string(lastRow + 1) + "'s " + describe(previous) + ")"
                            : " (DATA PERIODS, line " + std::to_string(periods + 1) + ", starts there)") +
                   ": an hour is missing or repeated; the rows must run hour by hour through the data period"};
    started = true;
    previous = stamp;
    lastRow = i;
    ended = stamp == end;
    if (isLeapDay) {
      leap.add(static_cast<int>(i + 1));
      continue;
    }

    WeatherHour h;
    h.month = stamp.month;
    h.day = stamp.day;
    h.hour = stamp.hour;
    h.line = static_cast<int>(i + 1);
    // Fields 7, 8 (°C), 14–16 (Wh/m²), 17–19 (lux); empty counts as missing.
    double value[19] = {};
    bool missing[19] = {};
    for (int k : {6, 7, 13, 14, 15, 16, 17, 18}) {
      if (f[k].empty()) {
        missing[k] = true;
        continue;
      }
      const std::optional<double> x = number(f[k]);
      if (!x) return Error{at(i) + "field " + std::to_string(k + 1) + " (\"" + f[k] + "\") is not a number"};
      value[k] = *x;
      const double missingAt = k <= 7 ? 99.9 : k <= 15 ? 9999 : 999900;
      missing[k] = *x >= missingAt;
    }
    for (int k : {6, 7}) {
      double& last = k == 6 ? lastDryBulb : lastDewPoint;
      if (missing[k]) {
        temperature.add(h.line);
        value[k] = last;
      }
      last = value[k];
    }
    h.dryBulbCelsius = value[6];
    h.dewPointCelsius = value[7];

    std::optional<double> sinElevation;  // of the hour's sun, made when a repair needs it
    auto sunSine = [&] {
      if (!sinElevation) sinElevation = std::sin(weatherSunPosition(out.location, h).elevationDegrees() * kRadians);
      return *sinElevation;
    };
    // Radiation: 13 global, 14 direct normal, 15 diffuse.
    for (int k : {13, 14, 15})
      if (!missing[k] && value[k] < 0) {
        negativeRadiation.add(h.line);
        value[k] = 0;
      }
    const int missingRadiation = missing[13] + missing[14] + missing[15];
    if (missingRadiation == 1) {
      derivedRadiation.add(h.line);
      const double s = std::max(0.0, sunSine());
      if (missing[13]) value[13] = value[15] + value[14] * s;
      if (missing[15]) value[15] = std::max(0.0, value[13] - value[14] * s);
      if (missing[14]) value[14] = s > 0.05 ? std::max(0.0, (value[13] - value[15]) / s) : 0;  // below 3°, the sun's share is unknowable
    } else if (missingRadiation > 1) {
      zeroRadiation.add(h.line);
      for (int k : {13, 14, 15})
        if (missing[k]) value[k] = 0;
    }
    h.globalHorizontalIrradiance = value[13];
    h.directNormalIrradiance = value[14];
    h.diffuseHorizontalIrradiance = value[15];

    // Illuminance: 16 global, 17 direct normal, 18 diffuse, from 13–15 where it must be.
    const bool badIlluminance = [&] {
      for (int k : {16, 17, 18})
        if (missing[k] || value[k] < 0 || (value[k] == 0 && value[k - 3] > 0)) return true;
      return false;
    }();
    if (badIlluminance) {
      const double s = sunSine();
      const PerezCoefficients sky =
          h.diffuseHorizontalIrradiance > 0
              ? perezSkyCondition(h.diffuseHorizontalIrradiance, h.directNormalIrradiance, std::asin(s) / kRadians, h.dayOfYear())
              : perezCoefficients(11.9, 0.01, perezModelZenithRadians(std::asin(s) / kRadians));
      const double water = precipitableWaterCentimetres(h.dewPointCelsius);
      const double made[3] = {0, h.directNormalIrradiance * perezDirectEfficacy(sky, water),
                              h.diffuseHorizontalIrradiance * perezDiffuseEfficacy(sky, water)};
      bool repaired = false;
      for (int k : {17, 18})
        if (missing[k] || value[k] < 0 || (value[k] == 0 && made[k - 16] > 0)) {
          value[k] = std::max(0.0, made[k - 16]);
          repaired = true;
        }
      const double global = value[18] + value[17] * std::max(0.0, s);
      if (missing[16] || value[16] < 0 || (value[16] == 0 && global > 0)) {
        value[16] = global;
        repaired = true;
      }
      if (repaired) illuminance.add(h.line);
    }
    h.globalHorizontalIlluminance = value[16];
    h.directNormalIlluminance = value[17];
    h.diffuseHorizontalIlluminance = value[18];
    out.hours.push_back(h);
  }
  if (!started) return Error{at(periods) + "no data rows follow the header"};
  if (!ended) {
    const std::size_t rows = out.hours.size() + static_cast<std::size_t>(leap.rows);
    return Error{at(lastRow) + "the data ends at " + describe(previous) + ", before its period's end, " + describe(end) + " (DATA PERIODS, line " +
                 std::to_string(periods + 1) + "): " + std::to_string(rows) + " rows of the " + std::to_string(periodDays * 24) +
                 (leap.rows > 0 || periodDays == 365 ? " (" + std::to_string(periodDays * 24 + 24) + " with 29 February)" : std::string()) +
                 " it calls for; complete the rows, or correct the period's end day"};
  }
  for (const Repair* r : {&leap, &negativeRadiation, &derivedRadiation, &zeroRadiation, &illuminance, &temperature}) r->report(name);
  return out;
}

}  // namespace lambert
