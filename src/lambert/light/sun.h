#pragma once
// The sun's position in the sky from a place and a local time, by the PSA algorithm (Blanco-Muriel,
// Alarcón-Padilla, López-Moratalla and Lara-Coira, "Computing the solar vector", Solar Energy 70(5),
// 2001, pp. 431–441): accurate to 0.5 arcminute (0.0083°) in the years 1999–2015 for which it was
// fitted, and slowly drifting outside them (about 0.01° a decade). Includes the parallax of the
// Earth's radius; atmospheric refraction is an optional correction (SPA's: Reda and Andreas, NREL
// TP-560-34302, 2008, eq. 42, after Bennett 1982).
#include <string>

#include "lambert/core/error.h"
#include "lambert/core/vec3.h"

namespace lambert {

// A civil date and clock time at a place, and the place's offset from UTC in hours (east
// positive: Central European Time is +1, Mountain Standard Time −7).
struct LocalTime {
  int year = 2000, month = 1, day = 1;  // Gregorian calendar
  int hour = 12, minute = 0;
  double second = 0;
  double timeZoneHours = 0;
};

// The atmosphere bending the sun's light (the sun looks higher than it is). SPA's example: 820
// mbar, 11 °C. A sun below the refraction's range (elevation under −0.83°) is not corrected.
struct Refraction {
  bool apply = true;
  double pressureMillibar = 1010;
  double temperatureCelsius = 10;
};

struct SunPosition {
  double zenithDegrees = 0;   // angle from the zenith; 90 − elevation
  double azimuthDegrees = 0;  // from north, clockwise seen from above (east = 90°), in [0, 360)
  double elevationDegrees() const { return 90 - zenithDegrees; }
};

// The sun's topocentric position at latitude (north positive) and longitude (east positive), in
// degrees, at local time `time`.
SunPosition sunPosition(double latitudeDegrees, double longitudeDegrees, const LocalTime& time,
                        const Refraction& refraction = {});

// "YYYY-MM-DD" and "HH:MM" or "HH:MM:SS" into a LocalTime (time zone left at 0); an error names
// what is wrong.
Result<LocalTime> parseLocalTime(const std::string& date, const std::string& clock);

// The direction toward a point of the sky at this azimuth (from north, clockwise seen from above)
// and elevation, in a y-up scene whose horizontal `north` direction is given (east = north × up).
Vec3 skyDirection(double azimuthDegrees, double elevationDegrees, const Vec3& north);

}  // namespace lambert
