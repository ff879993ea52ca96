// The EPW reader on the committed test week (values read back exactly), on damaged copies of it
// (repairs and refusals, each with its place), on a leap year, and where LAMBERT_CORPUS is set on
// three real files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/light/perez_sky.h"
#include "lambert/load/epw.h"

namespace lambert {
namespace {

const std::string kWeek = std::string(LAMBERT_SOURCE_DIR) + "/tests/weather/boulder-week.epw";

std::string weekText() {
  Result<std::string> text = readWholeFile(kWeek);
  EXPECT_TRUE(text);
  return text ? *text : std::string();
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines, const std::string& end = "\n") {
  std::string out;
  for (const std::string& line : lines) out += line + end;
  return out;
}

// Field k (1-based) of a CSV line replaced.
std::string withField(const std::string& line, int k, const std::string& value) {
  std::vector<std::string> f;
  std::stringstream in(line);
  for (std::string s; std::getline(in, s, ',');) f.push_back(s);
  f[k - 1] = value;
  std::string out;
  for (std::size_t i = 0; i < f.size(); ++i) out += (i ? "," : "") + f[i];
  return out;
}

TEST(EpwTest, ReadsTheTestWeekExactly) {
  WarningCapture warnings;
  Result<WeatherData> weather = readEpw(kWeek);
  ASSERT_TRUE(weather) << weather.error().message;
  EXPECT_TRUE(warnings.messages().empty());
  EXPECT_EQ(weather->path, kWeek);
  const WeatherLocation& l = weather->location;
  EXPECT_EQ(l.city, "Boulder Test");
  EXPECT_EQ(l.region, "CO");
  EXPECT_EQ(l.country, "USA");
  EXPECT_EQ(l.source, "lambert synthetic");
  EXPECT_EQ(l.station, "724699");
  EXPECT_EQ(l.latitudeDegrees, 40.02);
  EXPECT_EQ(l.longitudeDegrees, -105.25);
  EXPECT_EQ(l.timeZoneHours, -7);
  EXPECT_EQ(l.elevationMetres, 1650);
  ASSERT_EQ(weather->hours.size(), 7u * 24);
  // Line 20: 2005,6,19,12,0,…,24.4,6.0,…,975,943,78,94605,89585,9360,…
  const WeatherHour& noon = weather->hours[11];
  EXPECT_EQ(noon.line, 20);
  EXPECT_EQ(noon.month, 6);
  EXPECT_EQ(noon.day, 19);
  EXPECT_EQ(noon.hour, 12);
  EXPECT_EQ(noon.dayOfYear(), 170);
  EXPECT_EQ(noon.hourOfYear(), 169 * 24 + 11.5);
  EXPECT_EQ(noon.dryBulbCelsius, 24.4);
  EXPECT_EQ(noon.dewPointCelsius, 6.0);
  EXPECT_EQ(noon.globalHorizontalIrradiance, 975);
  EXPECT_EQ(noon.directNormalIrradiance, 943);
  EXPECT_EQ(noon.diffuseHorizontalIrradiance, 78);
  EXPECT_EQ(noon.globalHorizontalIlluminance, 94605);
  EXPECT_EQ(noon.directNormalIlluminance, 89585);
  EXPECT_EQ(noon.diffuseHorizontalIlluminance, 9360);
  // Line 40: 6/20 hour 8, overcast: 175,0,175,21000,0,21000.
  const WeatherHour& overcast = weather->hours[31];
  EXPECT_EQ(overcast.line, 40);
  EXPECT_EQ(overcast.day, 20);
  EXPECT_EQ(overcast.hour, 8);
  EXPECT_EQ(overcast.directNormalIrradiance, 0);
  EXPECT_EQ(overcast.diffuseHorizontalIlluminance, 21000);
  EXPECT_EQ(weather->hours.back().line, 176);
  EXPECT_EQ(weather->hours.back().day, 25);
  EXPECT_EQ(weather->hours.back().hour, 24);
}

// The sun at the hour's middle: 19 June 2005 11:30 MST at Boulder, by the PSA algorithm without
// refraction. Its elevation is the one the textbook formula of tests/weather/make_test_epw.py gives
// to within the formula's accuracy (about 0.1°): cos Z = 0.9650 there.
TEST(EpwTest, TheHoursSunIsAtItsMiddle) {
  Result<WeatherData> weather = readEpw(kWeek);
  ASSERT_TRUE(weather);
  const SunPosition sun = weatherSunPosition(weather->location, weather->hours[11]);
  EXPECT_NEAR(std::cos(sun.zenithDegrees * kPi / 180), (975.0 - 78) / 943, 0.002);  // the file's global = direct·cos Z + diffuse, rounded
  EXPECT_GT(sun.azimuthDegrees, 90);
  EXPECT_LT(sun.azimuthDegrees, 180);  // before solar noon (12:01 MST there)
}

TEST(EpwTest, ReadsCrlfAByteOrderMarkTrailingCommasAndQuotes) {
  const WeatherData plain = *readEpwText(weekText(), "week");
  std::vector<std::string> lines = splitLines(weekText());
  lines[0] = "LOCATION,\"Boulder Test\",CO,USA,\"lambert synthetic\",724699,40.02,-105.25,-7.0,1650.0,Csb";
  for (std::size_t i = 8; i < lines.size(); ++i) lines[i] += ",,";
  lines.push_back("");
  WarningCapture warnings;
  Result<WeatherData> read = readEpwText("\xEF\xBB\xBF" + joinLines(lines, "\r\n"), "week");
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_TRUE(warnings.messages().empty());
  EXPECT_EQ(read->location.city, "Boulder Test");
  ASSERT_EQ(read->hours.size(), plain.hours.size());
  for (std::size_t i = 0; i < plain.hours.size(); ++i) {
    EXPECT_EQ(read->hours[i].globalHorizontalIlluminance, plain.hours[i].globalHorizontalIlluminance);
    EXPECT_EQ(read->hours[i].diffuseHorizontalIrradiance, plain.hours[i].diffuseHorizontalIrradiance);
  }
}

TEST(EpwTest, RepairsMissingAndNegativeValuesWithAWarning) {
  std::vector<std::string> lines = splitLines(weekText());
  // Line 20 (6/19 noon): diffuse radiation missing; line 21: diffuse illuminance missing and global
  // radiation negative... line 22: the dew point missing; line 41: every illuminance missing.
  lines[19] = withField(lines[19], 16, "9999");
  lines[20] = withField(withField(lines[20], 19, "999999"), 15, "-3");
  lines[21] = withField(lines[21], 8, "99.9");
  lines[40] = withField(withField(withField(lines[40], 17, "999999"), 18, "999999"), 19, "");
  WarningCapture warnings;
  Result<WeatherData> read = readEpwText(joinLines(lines), "damaged.epw");
  ASSERT_TRUE(read) << read.error().message;
  const WeatherData plain = *readEpwText(weekText(), "week");
  // Diffuse from global − direct·cos Z at the hour's sun: 975 − 943 cos Z ≈ 78 (the file rounded it).
  const WeatherHour& h20 = read->hours[11];
  const double cosZ = std::sin(weatherSunPosition(read->location, h20).elevationDegrees() * kPi / 180);
  EXPECT_NEAR(h20.diffuseHorizontalIrradiance, 975 - 943 * cosZ, 1e-9);
  EXPECT_NEAR(h20.diffuseHorizontalIrradiance, 78, 2);
  // Negative direct → 0, and the missing diffuse illuminance from the diffuse radiation: an
  // efficacy of a clear sky, 110–160 lm/W.
  const WeatherHour& h21 = read->hours[12];
  EXPECT_EQ(h21.directNormalIrradiance, 0);
  EXPECT_GT(h21.diffuseHorizontalIlluminance / h21.diffuseHorizontalIrradiance, 110);
  EXPECT_LT(h21.diffuseHorizontalIlluminance / h21.diffuseHorizontalIrradiance, 160);
  EXPECT_EQ(read->hours[13].dewPointCelsius, plain.hours[12].dewPointCelsius);
  // Line 41 (6/20 hour 9, overcast: 206 W/m² diffuse, no sun): all three from the radiation; global =
  // diffuse, the direct being 0.
  const WeatherHour& h41 = read->hours[32];
  EXPECT_EQ(h41.directNormalIlluminance, 0);
  EXPECT_GT(h41.diffuseHorizontalIlluminance, 206 * 90);
  EXPECT_LT(h41.diffuseHorizontalIlluminance, 206 * 140);
  EXPECT_EQ(h41.globalHorizontalIlluminance, h41.diffuseHorizontalIlluminance);
  EXPECT_EQ(warnings.count("damaged.epw:20: a missing radiation"), 1) << ::testing::PrintToString(warnings.messages());
  EXPECT_EQ(warnings.count("damaged.epw:21: negative radiation set to 0 (1 row: line 21)"), 1);
  EXPECT_EQ(warnings.count("damaged.epw:21: a missing (≥ 999900), negative or zero illuminance"), 1);
  EXPECT_EQ(warnings.count("(2 rows: lines 21, 41)"), 1);
  EXPECT_EQ(warnings.count("damaged.epw:22: a missing dry bulb or dew point"), 1);
}

// Errors name the file and line, what is wrong and what to do.
TEST(EpwTest, RefusesWhatItCannotRead) {
  const std::vector<std::string> lines = splitLines(weekText());
  auto refused = [&](std::vector<std::string> changed, const std::string& part) {
    Result<WeatherData> read = readEpwText(joinLines(changed), "bad.epw");
    ASSERT_FALSE(read) << part;
    EXPECT_NE(read.error().message.find(part), std::string::npos) << read.error().message;
  };
  {
    std::vector<std::string> l = lines;
    l.erase(l.begin());
    refused(l, "bad.epw:1: not an EPW weather file: its first line must be LOCATION");
  }
  {
    std::vector<std::string> l = lines;
    l[0] = withField(l[0], 7, "forty");
    refused(l, "bad.epw:1: the latitude (degrees, north positive) \"forty\" is not a number within [-90, 90]");
    l[0] = withField(lines[0], 8, "-205.25");
    refused(l, "bad.epw:1: the longitude");
  }
  {
    std::vector<std::string> l = lines;
    l.erase(l.begin() + 50);  // line 51, 6/20 hour 19
    refused(l, "bad.epw:51: the row is 6/20 hour 20 where 6/20 hour 19 belongs (after line 50's 6/20 hour 18)");
  }
  {
    std::vector<std::string> l = lines;
    l.resize(100);
    refused(l, "bad.epw:100: the data ends at 6/22 hour 20, before its period's end, 6/25 hour 24 (DATA PERIODS, line 8): 92 rows of the 168");
  }
  {
    std::vector<std::string> l = lines;
    l[7] = "DATA PERIODS,1,4,Data,Wednesday, 6/19, 6/25";
    refused(l, "bad.epw:8: DATA PERIODS gives \"4\" records an hour");
  }
  {
    std::vector<std::string> l = lines;
    l[7] = "COMMENTS 3,none";
    refused(l, "no DATA PERIODS line");
  }
  {
    std::vector<std::string> l = lines;
    l[30] = l[30].substr(0, 40);
    refused(l, "bad.epw:31: the row has");
  }
  {
    std::vector<std::string> l = lines;
    l[30] = withField(l[30], 16, "lots");
    refused(l, "bad.epw:31: field 16 (\"lots\") is not a number");
  }
  {
    std::vector<std::string> l = lines;
    l.push_back(withField(l.back(), 3, "26"));
    refused(l, "bad.epw:177: a row after the data period's end");
  }
  EXPECT_FALSE(readEpw("/nonexistent/weather.epw"));
}

// A full year, leap or not: 8760 hours either way, 29 February left out with a warning; one hour
// short is refused.
TEST(EpwTest, ReadsAFullYearAndALeapYear) {
  const std::vector<std::string> week = splitLines(weekText());
  auto year = [&](bool leap, int drop) {
    std::vector<std::string> l(week.begin(), week.begin() + 7);
    l.push_back("DATA PERIODS,1,1,Data,Sunday, 1/ 1,12/31");
    static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    for (int m = 1; m <= 12; ++m)
      for (int d = 1; d <= kDays[m - 1] + (leap && m == 2); ++d)
        for (int h = 1; h <= 24; ++h) {
          std::string row = withField(withField(withField(week[8], 2, std::to_string(m)), 3, std::to_string(d)), 4, std::to_string(h));
          if (static_cast<int>(l.size()) != drop) l.push_back(row);
        }
    return joinLines(l);
  };
  {
    WarningCapture warnings;
    Result<WeatherData> plain = readEpwText(year(false, -1), "year.epw");
    ASSERT_TRUE(plain) << plain.error().message;
    EXPECT_EQ(plain->hours.size(), 8760u);
    EXPECT_TRUE(warnings.messages().empty());
  }
  {
    WarningCapture warnings;
    Result<WeatherData> leap = readEpwText(year(true, -1), "leap.epw");
    ASSERT_TRUE(leap) << leap.error().message;
    EXPECT_EQ(leap->hours.size(), 8760u);
    EXPECT_EQ(leap->hours[59 * 24].month, 3);  // 1 March follows 28 February
    EXPECT_EQ(leap->hours[59 * 24].line, 8 + 60 * 24 + 1);
    EXPECT_EQ(warnings.count("leap.epw:1425: 29 February left out"), 1) << ::testing::PrintToString(warnings.messages());
  }
  Result<WeatherData> short1 = readEpwText(year(false, 8 + 8759), "short.epw");
  ASSERT_FALSE(short1);
  EXPECT_NE(short1.error().message.find("short.epw:8767: the data ends at 12/31 hour 23"), std::string::npos) << short1.error().message;
  EXPECT_NE(short1.error().message.find("8759 rows of the 8760 (8784 with 29 February)"), std::string::npos) << short1.error().message;
}

// The fetched files (scripts/fetch-corpus.py; skipped without LAMBERT_CORPUS). Mannheim's and Los
// Angeles's give a direct normal illuminance of 0 beside a positive direct irradiance at low suns
// (their converters' efficacy clamped to 0): repaired, one warning each; Los Angeles's is a leap
// year (2024), 29 February left out.
TEST(EpwTest, ReadsTheCorpusWeatherFiles) {
  const char* corpus = std::getenv("LAMBERT_CORPUS");
  if (!corpus) GTEST_SKIP() << "set LAMBERT_CORPUS to scripts/fetch-corpus.py's folder";
  struct Expected {
    const char* file;
    double latitude, longitude, timeZone;
    std::size_t warnings;
  };
  for (const Expected& e : {Expected{"ladybug-weather/tests/assets/epw/mannheim.epw", 49.52, 8.55, 1, 1},
                            Expected{"ladybug-weather/tests/assets/epw/long_beach_2021.epw", 33.812, -118.146, -8, 0},
                            Expected{"ladybug-weather/tests/assets/epw/los_angeles_no_leap_field.epw", 34.212, -118.491, -8, 2}}) {
    const std::string path = std::string(corpus) + "/" + e.file;
    if (!std::filesystem::exists(path)) {
      ADD_FAILURE() << path << " is missing: run scripts/fetch-corpus.py";
      continue;
    }
    WarningCapture warnings;
    Result<WeatherData> weather = readEpw(path);
    ASSERT_TRUE(weather) << weather.error().message;
    for (const std::string& m : warnings.messages()) std::printf("%s\n", m.c_str());
    EXPECT_EQ(weather->location.latitudeDegrees, e.latitude);
    EXPECT_EQ(weather->location.longitudeDegrees, e.longitude);
    EXPECT_EQ(weather->location.timeZoneHours, e.timeZone);
    EXPECT_EQ(weather->hours.size(), 8760u);
    EXPECT_EQ(warnings.messages().size(), e.warnings);
    double annualGlobal = 0;  // kWh/m²
    for (const WeatherHour& h : weather->hours) annualGlobal += h.globalHorizontalIrradiance / 1000;
    std::printf("%s: %.0f kWh/m² a year on the horizontal\n", e.file, annualGlobal);
    EXPECT_GT(annualGlobal, 900);   // Mannheim about 1100, southern California about 1800
    EXPECT_LT(annualGlobal, 2200);
  }
}

}  // namespace
}  // namespace lambert
