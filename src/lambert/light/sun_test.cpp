#include <gtest/gtest.h>

#include <cmath>

#include "lambert/core/rgb.h"
#include "lambert/light/sun.h"

namespace lambert {
namespace {

// The PSA algorithm's stated accuracy (Blanco-Muriel et al. 2001): 0.5 arcminute.
constexpr double kHalfArcminute = 0.5 / 60;

// NREL's Solar Position Algorithm report (Reda and Andreas, NREL/TP-560-34302, 2008, table A4.1)
// works this example: Golden, Colorado, 2003-10-17 12:30:30 local (UTC−7), 820 mbar, 11 °C →
// topocentric zenith 50.11162° (refraction included) and azimuth 194.34024°. SPA is accurate to
// 0.0003°, so the difference is PSA's own error.
TEST(SunTest, MatchesNrelSpaWorkedExample) {
  LocalTime t{2003, 10, 17, 12, 30, 30, -7};
  Refraction atmosphere{true, 820, 11};
  SunPosition sun = sunPosition(39.742476, -105.1786, t, atmosphere);
  EXPECT_NEAR(sun.zenithDegrees, 50.11162, kHalfArcminute);
  EXPECT_NEAR(sun.azimuthDegrees, 194.34024, kHalfArcminute);
}

// The same instant in two time zones is the same sun.
TEST(SunTest, TimeZoneShiftsTheClockNotTheSun) {
  SunPosition golden = sunPosition(39.742476, -105.1786, {2003, 10, 17, 12, 30, 30, -7});
  SunPosition utc = sunPosition(39.742476, -105.1786, {2003, 10, 17, 19, 30, 30, 0});
  SunPosition tokyo = sunPosition(39.742476, -105.1786, {2003, 10, 18, 4, 30, 30, 9});
  EXPECT_NEAR(golden.zenithDegrees, utc.zenithDegrees, 1e-9);
  EXPECT_NEAR(golden.azimuthDegrees, tokyo.azimuthDegrees, 1e-9);
}

// At the March 2020 equinox (2020-03-20 03:50 UTC, the almanac's instant) the declination is zero,
// so where it is solar noon the sun stands at elevation 90° − |latitude|, due south in the north
// and due north in the south. Solar noon falls at longitude 15°·(12 h − UT − EoT) with the
// equation of time EoT = −7.45 min that day (almanac); an error of a minute in it moves the
// elevation by under 1e-5° (the elevation is stationary at noon), so the closed form holds to the
// algorithm's accuracy.
TEST(SunTest, EquinoxNoonElevationIsNinetyMinusLatitude) {
  const double ut = 3 + 50.0 / 60, equationOfTimeHours = -7.45 / 60;
  const double noonLongitude = 15 * (12 - ut - equationOfTimeHours);
  for (double latitude : {40.0, 51.5, -35.0, 10.0}) {
    SunPosition sun = sunPosition(latitude, noonLongitude, {2020, 3, 20, 3, 50, 0, 0}, {false});
    EXPECT_NEAR(sun.elevationDegrees(), 90 - std::fabs(latitude), kHalfArcminute + 1e-3) << latitude;
    const double expectedAzimuth = latitude > 0 ? 180 : 0;
    EXPECT_NEAR(std::remainder(sun.azimuthDegrees - expectedAzimuth, 360), 0, 0.3) << latitude;
  }
}

// At the June 2020 solstice (2020-06-20 21:43 UTC; EoT −1.45 min; obliquity 23.4367°) the noon
// sun stands at 90° − latitude + 23.4367°. (Not overhead on the tropic: there the zenith angle is
// first order in the hour angle, and the almanac's equation of time is good to a few seconds only.)
TEST(SunTest, SolsticeNoonElevationAddsTheObliquity) {
  const double ut = 21 + 43.0 / 60, equationOfTimeHours = -1.45 / 60, obliquity = 23.4367;
  const double noonLongitude = 15 * (12 - ut - equationOfTimeHours);
  for (double latitude : {51.5, 30.0, 60.0}) {
    SunPosition sun = sunPosition(latitude, noonLongitude, {2020, 6, 20, 21, 43, 0, 0}, {false});
    EXPECT_NEAR(sun.elevationDegrees(), 90 - latitude + obliquity, kHalfArcminute + 1e-3) << latitude;
  }
}

// Refraction lifts a low sun by about half a degree (Bennett: 34′ at the horizon) and a high one
// by almost nothing.
TEST(SunTest, RefractionLiftsALowSun) {
  LocalTime evening{2003, 10, 17, 17, 0, 0, -7};
  SunPosition bent = sunPosition(39.742476, -105.1786, evening), straight = sunPosition(39.742476, -105.1786, evening, {false});
  ASSERT_GT(straight.elevationDegrees(), 0);
  ASSERT_LT(straight.elevationDegrees(), 5);
  EXPECT_GT(bent.elevationDegrees() - straight.elevationDegrees(), 0.15);
  EXPECT_LT(bent.elevationDegrees() - straight.elevationDegrees(), 0.6);
}

TEST(SunTest, ParsesDatesAndTimesAndRefusesNonsense) {
  Result<LocalTime> t = parseLocalTime("2024-02-29", "07:05");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->year, 2024);
  EXPECT_EQ(t->month, 2);
  EXPECT_EQ(t->day, 29);
  EXPECT_EQ(t->hour, 7);
  EXPECT_EQ(t->minute, 5);
  EXPECT_TRUE(parseLocalTime("2024-01-01", "12:30:15.5"));
  EXPECT_FALSE(parseLocalTime("2023-02-29", "12:00"));
  EXPECT_FALSE(parseLocalTime("2023-13-01", "12:00"));
  EXPECT_FALSE(parseLocalTime("17/10/2003", "12:00"));
  EXPECT_FALSE(parseLocalTime("2003-10-17", "12h30"));
  EXPECT_FALSE(parseLocalTime("2003-10-17", "25:00"));
}

// Azimuth from north clockwise seen from above, north −z and up +y: east is +x.
TEST(SunTest, SkyDirectionFollowsCompassConvention) {
  const Vec3 north{0, 0, -1};
  auto near = [](Vec3 a, Vec3 b) { return length(a - b) < 1e-12; };
  EXPECT_TRUE(near(skyDirection(0, 0, north), {0, 0, -1}));
  EXPECT_TRUE(near(skyDirection(90, 0, north), {1, 0, 0}));
  EXPECT_TRUE(near(skyDirection(180, 0, north), {0, 0, 1}));
  EXPECT_TRUE(near(skyDirection(270, 0, north), {-1, 0, 0}));
  EXPECT_TRUE(near(skyDirection(123, 90, north), {0, 1, 0}));
  const double s = std::sqrt(0.5);
  EXPECT_TRUE(near(skyDirection(90, 45, {1, 0, 0}), {0, s, s}));  // north +x: east is +z
}

}  // namespace
}  // namespace lambert
