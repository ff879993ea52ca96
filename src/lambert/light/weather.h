#pragma once
// Hourly weather for climate-based daylighting: a place and a year of hours of solar irradiance
// and illuminance, as an EnergyPlus weather (EPW) file gives them (load/epw.h reads one). Plain
// data; every quantity's unit is in its name or beside it.
//
// Time: an EPW hour h (1–24) is the hour ENDING at h:00 local standard time (no daylight saving),
// so its values are the hour's means (illuminance) or integrals over it (irradiation in Wh/m², the
// same number as a mean irradiance in W/m²). The sun is placed at the middle of the hour, h − 0.5.
// The year is a fixed non-leap one (kWeatherYear): typical-year files mix months of different years,
// and annual metrics count 365 days (IES LM-83-12's sDA and ASE: 8760 hours); the reader drops 29
// February's rows (load/epw.h).
#include <string>
#include <vector>

#include "lambert/light/sun.h"

namespace lambert {

// 2005: not a leap year, and within the years the PSA sun algorithm was fitted to (1999–2015).
inline constexpr int kWeatherYear = 2005;

struct WeatherLocation {
  std::string city, region, country, source, station;  // station: the WMO number, as text
  double latitudeDegrees = 0;   // north positive
  double longitudeDegrees = 0;  // east positive
  double timeZoneHours = 0;     // standard time's offset from UTC, east positive
  double elevationMetres = 0;
};

struct WeatherHour {
  int month = 1, day = 1, hour = 1;  // hour 1–24: the hour ENDING at that clock time (local standard time)
  double dryBulbCelsius = 0, dewPointCelsius = 0;
  double directNormalIrradiance = 0, diffuseHorizontalIrradiance = 0, globalHorizontalIrradiance = 0;     // W/m²
  double directNormalIlluminance = 0, diffuseHorizontalIlluminance = 0, globalHorizontalIlluminance = 0;  // lux
  int line = 0;  // the file's line it came from (1-based), for messages; 0 when made in code

  // 1 (1 January) to 365 in kWeatherYear.
  int dayOfYear() const;
  // Hours since 1 January 00:00 at the hour's middle: 0.5 for (1, 1, 1), 8759.5 for (12, 31, 24).
  double hourOfYear() const { return (dayOfYear() - 1) * 24.0 + hour - 0.5; }
};

struct WeatherData {
  WeatherLocation location;
  std::vector<WeatherHour> hours;  // in the file's order, 29 February left out
  std::string path;                // where it was read from ("" when made in code)
};

// Day of the year 1–365 of a date in kWeatherYear (no 29 February).
int dayOfYear(int month, int day);

// The sun at the middle of the hour (clock time hour − 0.5, local standard time, kWeatherYear) by the
// PSA algorithm (light/sun.h), without refraction (the geometric sun, as Radiance's gendaymtx places
// it): refraction lifts a sun on the horizon by about 0.5°, which would move twilight's boundary.
SunPosition weatherSunPosition(const WeatherLocation& location, const WeatherHour& hour);

}  // namespace lambert
