#pragma once
// EnergyPlus weather (EPW) files: a place and its hours of solar irradiance and illuminance.
// Format: EnergyPlus "Auxiliary Programs", "Weather Converter Program", section "EnergyPlus
// Weather File (EPW) Data Dictionary" (doc/auxiliary-programs/src/weather-converter-program/
// energyplus-weather-file-epw-data-dictionary.tex in NREL/EnergyPlus). Eight header lines —
// LOCATION,city,state/province/region,country,source,WMO,latitude (N +),longitude (E +),time zone
// (h, E +),elevation (m); DESIGN CONDITIONS; TYPICAL/EXTREME PERIODS; GROUND TEMPERATURES;
// HOLIDAYS/DAYLIGHT SAVINGS; COMMENTS 1; COMMENTS 2; DATA PERIODS,#periods,records per
// hour,name,start weekday,start day,end day — then one comma-separated row an hour. Of a row's
// 35 fields (1-based) lambert reads 1 year (ignored: typical years mix years), 2 month, 3 day,
// 4 hour (1–24, the hour ENDING then, local standard time), 7 dry bulb and 8 dew point (°C, missing
// at ≥ 99.9), 14 global horizontal, 15 direct normal and 16 diffuse horizontal radiation (Wh/m²
// over the hour, i.e. a mean W/m², missing at ≥ 9999) and 17 global horizontal, 18 direct normal and
// 19 diffuse horizontal illuminance (lux, missing at ≥ 999900). Field 20 (zenith luminance) and the
// rest are not read.
//
// Read liberally, refused rarely. Repaired, each kind with one warning naming the file, the first
// line, how many rows and what was done:
//   - a missing or negative irradiance: negative → 0; a missing one from the other two
//     (global = direct·cos Z + diffuse, at the sun of the hour's middle), else 0;
//   - a missing or negative illuminance, or one of 0 where its irradiance is positive: from the
//     irradiance by Perez et al. 1990's luminous efficacies (light/perez_sky.h; global = diffuse +
//     direct·sin(elevation));
//   - a missing dew point or dry bulb: the previous hour's (11 °C, gendaymtx's default, before any);
//   - 29 February's rows (a leap year's 8784): left out, so that a full year is always 8760 hours
//     of a non-leap year (light/weather.h: annual metrics count 365 days); one warning.
// A UTF-8 byte-order mark, CRLF line ends, quoted header fields, trailing commas and blank lines
// are read. Refused (an Error naming file:line, what is wrong and how to proceed): no LOCATION
// first line; a latitude, longitude or time zone that is not a number in range; no DATA PERIODS
// line, or one with several periods or several records an hour; a row with fewer than 19 fields or
// an unreadable date, hour or value; a row out of sequence (a missing or repeated hour); data that
// ends before its period does (a full year: 8760 rows, 8784 with 29 February). Cost: one pass,
// about 1 µs a row.
#include <string>

#include "lambert/core/error.h"
#include "lambert/light/weather.h"

namespace lambert {

Result<WeatherData> readEpw(const std::string& path);
// The same from the file's text; `name` stands for its path in messages and in WeatherData::path.
Result<WeatherData> readEpwText(const std::string& text, const std::string& name);

}  // namespace lambert
