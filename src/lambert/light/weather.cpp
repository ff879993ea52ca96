#include "lambert/light/weather.h"

#include "lambert/core/error.h"

namespace lambert {

int dayOfYear(int month, int day) {
  static constexpr int kBefore[12] = {0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334};
  LAMBERT_CHECK(month >= 1 && month <= 12 && day >= 1 && day <= 31);
  return kBefore[month - 1] + day;
}

int WeatherHour::dayOfYear() const { return lambert::dayOfYear(month, day); }

SunPosition weatherSunPosition(const WeatherLocation& location, const WeatherHour& hour) {
  LocalTime time;
  time.year = kWeatherYear;
  time.month = hour.month;
  time.day = hour.day;
  time.hour = hour.hour - 1;  // hour − 0.5: (h − 1):30
  time.minute = 30;
  time.timeZoneHours = location.timeZoneHours;
  Refraction none;
  none.apply = false;
  return sunPosition(location.latitudeDegrees, location.longitudeDegrees, time, none);
}

}  // namespace lambert
