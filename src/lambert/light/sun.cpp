#include "lambert/light/sun.h"

#include <cmath>
#include <cstdio>

#include "lambert/core/rgb.h"

namespace lambert {
namespace {

constexpr double kRadians = kPi / 180;
constexpr double kTwoPi = 2 * kPi;

// Refraction Δe in degrees that lifts a true elevation e (degrees) in an atmosphere at pressure
// P and temperature T: SPA eq. 42 (Reda and Andreas 2008), Bennett's formula scaled by P and T.
double refractionDegrees(double elevationDegrees, const Refraction& r) {
  if (!r.apply || elevationDegrees < -0.83) return 0;
  return (r.pressureMillibar / 1010) * (283 / (273 + r.temperatureCelsius)) * 1.02 /
         (60 * std::tan((elevationDegrees + 10.3 / (elevationDegrees + 5.11)) * kRadians));
}

}  // namespace

SunPosition sunPosition(double latitudeDegrees, double longitudeDegrees, const LocalTime& time, const Refraction& refraction) {
  // Blanco-Muriel et al. 2001, section 3, step by step (their variable names in comments).
  // Universal time in hours; it may leave [0, 24): the day number and the hour only enter
  // through their sum (the Julian date) and the sidereal time, which is periodic in 24 h.
  const double decimalHours = time.hour + (time.minute + time.second / 60.0) / 60.0 - time.timeZoneHours;
  // The Julian day number by integer arithmetic (Fliegel and van Flandern 1968), as the paper.
  const long aux1 = (time.month - 14) / 12;
  const long aux2 = (1461L * (time.year + 4800 + aux1)) / 4 + (367L * (time.month - 2 - 12 * aux1)) / 12 -
                    (3L * ((time.year + 4900 + aux1) / 100)) / 4 + time.day - 32075;
  const double julianDate = static_cast<double>(aux2) - 0.5 + decimalHours / 24.0;
  const double n = julianDate - 2451545.0;  // days since J2000.0 (2000-01-01 12:00 UT)

  // Ecliptic coordinates (radians).
  const double omega = 2.1429 - 0.0010394594 * n;
  const double meanLongitude = 4.8950630 + 0.017202791698 * n;
  const double meanAnomaly = 6.2400600 + 0.0172019699 * n;
  const double eclipticLongitude = meanLongitude + 0.03341607 * std::sin(meanAnomaly) +
                                   0.00034894 * std::sin(2 * meanAnomaly) - 0.0001134 - 0.0000203 * std::sin(omega);
  const double eclipticObliquity = 0.4090928 - 6.2140e-9 * n + 0.0000396 * std::cos(omega);

  // Celestial coordinates: right ascension and declination.
  const double sinEclipticLongitude = std::sin(eclipticLongitude);
  double rightAscension = std::atan2(std::cos(eclipticObliquity) * sinEclipticLongitude, std::cos(eclipticLongitude));
  if (rightAscension < 0) rightAscension += kTwoPi;
  const double declination = std::asin(std::sin(eclipticObliquity) * sinEclipticLongitude);

  // Local coordinates: hour angle, zenith and azimuth.
  const double greenwichMeanSiderealTime = 6.6974243242 + 0.0657098283 * n + decimalHours;
  const double localMeanSiderealTime = (greenwichMeanSiderealTime * 15 + longitudeDegrees) * kRadians;
  const double hourAngle = localMeanSiderealTime - rightAscension;
  const double latitude = latitudeDegrees * kRadians;
  const double cosLatitude = std::cos(latitude), sinLatitude = std::sin(latitude);
  const double cosHourAngle = std::cos(hourAngle);
  double zenith = std::acos(std::fmin(1.0, std::fmax(-1.0, cosLatitude * cosHourAngle * std::cos(declination) +
                                                             std::sin(declination) * sinLatitude)));
  double azimuth = std::atan2(-std::sin(hourAngle), std::tan(declination) * cosLatitude - sinLatitude * cosHourAngle);
  if (azimuth < 0) azimuth += kTwoPi;
  // Parallax: seen from the surface rather than the centre, the sun is lower by
  // (Earth's mean radius / astronomical unit) sin(zenith).
  constexpr double kEarthMeanRadiusKm = 6371.01, kAstronomicalUnitKm = 149597890;
  zenith += (kEarthMeanRadiusKm / kAstronomicalUnitKm) * std::sin(zenith);

  SunPosition sun;
  sun.azimuthDegrees = azimuth / kRadians;
  sun.zenithDegrees = zenith / kRadians;
  sun.zenithDegrees -= refractionDegrees(sun.elevationDegrees(), refraction);
  return sun;
}

Result<LocalTime> parseLocalTime(const std::string& date, const std::string& clock) {
  LocalTime t;
  char tail = 0;
  if (std::sscanf(date.c_str(), "%d-%d-%d%c", &t.year, &t.month, &t.day, &tail) != 3)
    return Error{"date \"" + date + "\" is not YYYY-MM-DD"};
  static const int kDaysInMonth[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (t.month < 1 || t.month > 12) return Error{"date \"" + date + "\": month must be 1 to 12"};
  const bool leap = (t.year % 4 == 0 && t.year % 100 != 0) || t.year % 400 == 0;
  const int days = t.month == 2 && !leap ? 28 : kDaysInMonth[t.month - 1];
  if (t.day < 1 || t.day > days) return Error{"date \"" + date + "\": day must be 1 to " + std::to_string(days)};
  if (t.year < 1 || t.year > 9999) return Error{"date \"" + date + "\": year must be 1 to 9999"};
  double second = 0;
  const int fields = std::sscanf(clock.c_str(), "%d:%d:%lf%c", &t.hour, &t.minute, &second, &tail);
  if (fields != 2 && fields != 3) return Error{"time \"" + clock + "\" is not HH:MM or HH:MM:SS"};
  if (t.hour < 0 || t.hour > 24 || t.minute < 0 || t.minute > 59 || !(second >= 0 && second < 61))
    return Error{"time \"" + clock + "\" is out of range (hours 0–24, minutes 0–59, seconds 0–60)"};
  t.second = second;
  return t;
}

Vec3 skyDirection(double azimuthDegrees, double elevationDegrees, const Vec3& north) {
  const Vec3 up{0, 1, 0};
  const Vec3 n = normalize(north - up * dot(north, up));
  const Vec3 east = cross(n, up);
  const double a = azimuthDegrees * kRadians, e = elevationDegrees * kRadians;
  return normalize((n * std::cos(a) + east * std::sin(a)) * std::cos(e) + up * std::sin(e));
}

}  // namespace lambert
