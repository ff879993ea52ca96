#include "lambert/design/daylight_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>

#include "lambert/core/text.h"

namespace lambert {
namespace {

constexpr double kPiHere = 3.14159265358979323846;

// `days` days of 24 rows (EPW hours 1..24), from 1 January; total(day, hour, sensor) and sun(...) in lux.
using Field = std::function<double(int day, int hour, std::size_t sensor)>;
AnnualIlluminance year(int days, std::size_t sensors, const Field& total, const Field& sun = [](int, int, std::size_t) { return 0.0; }) {
  static const int lengths[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  AnnualIlluminance a;
  a.sensors = sensors;
  int month = 1, dayOfMonth = 1;
  for (int d = 0; d < days; ++d) {
    for (int h = 1; h <= 24; ++h) {
      a.hours.push_back({month, dayOfMonth, h});
      for (std::size_t s = 0; s < sensors; ++s) {
        a.totalLux.push_back(static_cast<float>(total(d, h, s)));
        a.directSunLux.push_back(static_cast<float>(sun(d, h, s)));
      }
    }
    if (++dayOfMonth > lengths[month - 1]) dayOfMonth = 1, ++month;
  }
  return a;
}

TEST(DaylightMetricsTest, OccupiedHoursFollowTheEpwHourEndingConvention) {
  // Four sensors, each lit (500 lx) in one hour only: hour 8 (7–8 am), 9 (8–9), 18 (5–6 pm), 19 (6–7 pm).
  const int litHour[] = {8, 9, 18, 19};
  const AnnualIlluminance a = year(1, 4, [&](int, int h, std::size_t s) { return h == litHour[s] ? 500.0 : 0.0; });
  Result<DaylightMetrics> m = daylightMetrics(a);
  ASSERT_TRUE(m.ok()) << m.error().message;
  // Occupied: hours 9..18, the intervals [8, 9) … [17, 18): 10 of them.
  EXPECT_EQ(m->occupiedHours, 10);
  EXPECT_EQ(m->sensors[0].daylightAutonomy, 0);   // 7–8 am: not occupied
  EXPECT_EQ(m->sensors[1].daylightAutonomy, 10);  // 8–9 am: 1 of 10
  EXPECT_EQ(m->sensors[2].daylightAutonomy, 10);  // 5–6 pm: 1 of 10
  EXPECT_EQ(m->sensors[3].daylightAutonomy, 0);   // 6–7 pm: not occupied
  // From 8:30: hour 9's interval [8, 9) starts before it; hours 10..18 remain, 9 of them.
  DaylightMetricsOptions late;
  late.firstOccupiedHour = 8.5;
  Result<DaylightMetrics> l = daylightMetrics(a, late);
  ASSERT_TRUE(l.ok());
  EXPECT_EQ(l->occupiedHours, 9);
  EXPECT_EQ(l->sensors[1].daylightAutonomy, 0);
  EXPECT_NEAR(l->sensors[2].daylightAutonomy, 100.0 / 9, 1e-12);
}

TEST(DaylightMetricsTest, DaCdaUdiMeanAndPercentilesOfOneDayByHand) {
  // One day; the occupied hours 9..18 of sensor 0 take these values, sensor 1 the same with 300 → 290.
  // Unoccupied hours get 5000 lx, which must count nowhere.
  const double day0[] = {50, 100, 150, 300, 299, 2000, 2001, 600, 0, 1000};
  const AnnualIlluminance a = year(1, 2, [&](int, int h, std::size_t s) {
    if (h < 9 || h > 18) return 5000.0;
    const double v = day0[h - 9];
    return s == 1 && v == 300 ? 290.0 : v;
  });
  Result<DaylightMetrics> m = daylightMetrics(a);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->occupiedHours, 10);
  const SensorDaylight& d = m->sensors[0];
  // DA300: E ≥ 300 in 300, 2000, 2001, 600, 1000: 5 of 10.
  EXPECT_DOUBLE_EQ(d.daylightAutonomy, 50);
  // cDA: 5 full hours + (50 + 100 + 150 + 299 + 0)/300 = 5 + 599/300, over 10 hours.
  EXPECT_NEAR(d.continuousDaylightAutonomy, 100 * (5 + 599.0 / 300) / 10, 1e-9);
  // UDI: fell short (< 100): 50, 0 → 20 %; useful (100 ≤ E ≤ 2000): 100, 150, 300, 299, 2000, 600,
  // 1000 → 70 %; exceeded (> 2000): 2001 → 10 %.
  EXPECT_DOUBLE_EQ(d.udiFellShort, 20);
  EXPECT_DOUBLE_EQ(d.udiUseful, 70);
  EXPECT_DOUBLE_EQ(d.udiExceeded, 10);
  // Mean: 6500 / 10.
  EXPECT_DOUBLE_EQ(d.meanLux, 650);
  // Percentiles, linear between order statistics at rank p/100·(n − 1): sorted 0, 50, 100, 150, 299,
  // 300, 600, 1000, 2000, 2001. p10: rank 0.9 → 0 + 0.9·50 = 45; p50: rank 4.5 → 299.5;
  // p90: rank 8.1 → 2000 + 0.1·1 = 2000.1.
  ASSERT_EQ(d.percentileLux.size(), 3u);
  EXPECT_NEAR(d.percentileLux[0], 45, 1e-9);
  EXPECT_NEAR(d.percentileLux[1], 299.5, 1e-9);
  EXPECT_NEAR(d.percentileLux[2], 2000.1, 1e-9);
  // sDA300/50%: sensor 0 meets 300 lx in exactly 50 % of the hours (passes: "at least"); sensor 1 in 40 %.
  EXPECT_TRUE(d.sdaPass);
  EXPECT_DOUBLE_EQ(m->sensors[1].daylightAutonomy, 40);
  EXPECT_FALSE(m->sensors[1].sdaPass);
  EXPECT_DOUBLE_EQ(m->spatialDaylightAutonomy, 50);
  EXPECT_FALSE(m->lm83SdaNominallyAccepted);
  EXPECT_EQ(m->leed.points, 1);  // 50 % ≥ 40 %; the one space is below 55 %: no extra point
  // Area means: DA (50 + 40)/2; UDI useful: sensor 1 has 290 in the band as well: 70 %.
  EXPECT_DOUBLE_EQ(m->meanDaylightAutonomy, 45);
  EXPECT_DOUBLE_EQ(m->meanUdiUseful, 70);
  // Other UDI limits: 300–1000 lx useful (both ends in) → 300, 600, 1000 → 30 % for sensor 0.
  DaylightMetricsOptions band;
  band.udiLowerLux = 300, band.udiUpperLux = 1000;
  Result<DaylightMetrics> b = daylightMetrics(a, band);
  ASSERT_TRUE(b.ok());
  EXPECT_DOUBLE_EQ(b->sensors[0].udiUseful, 30);
  EXPECT_DOUBLE_EQ(b->sensors[0].udiFellShort, 50);  // 50, 100, 150, 299, 0
  EXPECT_DOUBLE_EQ(b->sensors[0].udiExceeded, 20);   // 2000, 2001
}

TEST(DaylightMetricsTest, AseCountsMoreThan250SunlitOccupiedHours) {
  // 26 days: 260 occupied hours. Occupied hour k (0-based, in order) of sensor 0 has direct sun
  // 1500 lx for k < 250, of sensor 1 for k < 251, of sensor 2 exactly 1000 lx for k < 251 (direct sun
  // is "1000 lx or more"), sensor 3 999 lx always. Sensor 0 also gets 5000 lx of sun at 6–7 am
  // every day (not occupied: must not count).
  int k = 0;
  std::vector<int> occupiedIndex(26 * 24, -1);
  for (int day = 0; day < 26; ++day)
    for (int h = 9; h <= 18; ++h) occupiedIndex[day * 24 + h - 1] = k++;
  auto sun = [&](int day, int h, std::size_t s) {
    const int i = occupiedIndex[day * 24 + h - 1];
    if (i < 0) return s == 0 && h == 7 ? 5000.0 : 0.0;
    switch (s) {
      case 0: return i < 250 ? 1500.0 : 0.0;
      case 1: return i < 251 ? 1500.0 : 0.0;
      case 2: return i < 251 ? 1000.0 : 0.0;
      default: return 999.0;
    }
  };
  const AnnualIlluminance a = year(26, 4, [&](int d, int h, std::size_t s) { return sun(d, h, s) + 100; }, sun);
  Result<DaylightMetrics> m = daylightMetrics(a);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->occupiedHours, 260);
  EXPECT_EQ(m->sensors[0].sunlitHours, 250);
  EXPECT_FALSE(m->sensors[0].aseExceeded);  // 250 is not more than 250
  EXPECT_EQ(m->sensors[1].sunlitHours, 251);
  EXPECT_TRUE(m->sensors[1].aseExceeded);
  EXPECT_EQ(m->sensors[2].sunlitHours, 251);
  EXPECT_TRUE(m->sensors[2].aseExceeded);
  EXPECT_EQ(m->sensors[3].sunlitHours, 0);
  EXPECT_DOUBLE_EQ(m->annualSunlightExposure, 50);  // 2 of 4
  EXPECT_TRUE(m->lm83AseLikelyDiscomfort);
  EXPECT_TRUE(m->leed.glareStrategyRequired);
  // The blinds never touch ASE (it is taken with them retracted).
  DaylightMetricsOptions blinds;
  blinds.blinds = true;
  Result<DaylightMetrics> b = daylightMetrics(a, blinds);
  ASSERT_TRUE(b.ok());
  EXPECT_DOUBLE_EQ(b->annualSunlightExposure, 50);
  // Occupied hours k < 250: sensors 0, 1, 2 sunlit (3 of 4 > 2 %), closed; k = 250: sensors 1, 2,
  // closed; k ≥ 251: none (sensor 3's 999 lx is not direct sun), open. 251 hours closed.
  EXPECT_EQ(b->blindsClosedHours, 251);
}

TEST(DaylightMetricsTest, BlindsCloseWhenMoreThanTwoPercentOfSensorsSeeDirectSun) {
  // 100 sensors, one day. Hour 10 (9–10 am): sensors 0, 1, 2 get 1500 lx of direct sun (1800 lx in
  // all): 3 of 100 > 2 % → blinds closed. Hour 11: sensors 0 and 1 the same: 2 of 100, not more than
  // 2 % → open. Otherwise every sensor 400 lx, no sun.
  auto sun = [](int, int h, std::size_t s) { return (h == 10 && s < 3) || (h == 11 && s < 2) ? 1500.0 : 0.0; };
  const AnnualIlluminance a = year(1, 100, [&](int d, int h, std::size_t s) { return sun(d, h, s) > 0 ? 1800.0 : 400.0; }, sun);
  DaylightMetricsOptions o;
  o.blinds = true;
  o.blindsTransmittance = 0.25;
  Result<DaylightMetrics> m = daylightMetrics(a, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->blindsClosedHours, 1);
  // Sensor 50: 9 hours at 400, hour 10 at 400 × 0.25 = 100 (in the useful band: 100 ≤ E).
  const SensorDaylight& plain = m->sensors[50];
  EXPECT_DOUBLE_EQ(plain.daylightAutonomy, 90);
  EXPECT_NEAR(plain.continuousDaylightAutonomy, 100 * (9 + 100.0 / 300) / 10, 1e-9);
  EXPECT_DOUBLE_EQ(plain.udiUseful, 100);
  EXPECT_DOUBLE_EQ(plain.meanLux, (9 * 400 + 100) / 10.0);
  // Sensor 0: hour 10 at (1800 − 1500) × 0.25 = 75 (fell short), hour 11 open at 1800, 8 hours at 400.
  const SensorDaylight& lit = m->sensors[0];
  EXPECT_DOUBLE_EQ(lit.daylightAutonomy, 90);
  EXPECT_NEAR(lit.continuousDaylightAutonomy, 100 * (9 + 75.0 / 300) / 10, 1e-9);
  EXPECT_DOUBLE_EQ(lit.udiFellShort, 10);
  EXPECT_DOUBLE_EQ(lit.meanLux, (75 + 1800 + 8 * 400) / 10.0);
  EXPECT_EQ(lit.sunlitHours, 2);
  // The transmittance is used: 0.5 gives sensor 50 200 lx in hour 10.
  o.blindsTransmittance = 0.5;
  Result<DaylightMetrics> half = daylightMetrics(a, o);
  ASSERT_TRUE(half.ok());
  EXPECT_DOUBLE_EQ(half->sensors[50].meanLux, (9 * 400 + 200) / 10.0);
  // Without blinds: sensor 50 always 400 lx; sensor 0 1800 lx in hours 10 and 11.
  Result<DaylightMetrics> open = daylightMetrics(a);
  ASSERT_TRUE(open.ok());
  EXPECT_EQ(open->blindsClosedHours, 0);
  EXPECT_DOUBLE_EQ(open->sensors[50].daylightAutonomy, 100);
  EXPECT_DOUBLE_EQ(open->sensors[0].meanLux, (2 * 1800 + 8 * 400) / 10.0);
  // A share whose product rounds below its whole number (0.29 × 100 = 28.999999999999996): 29 of 100
  // sunlit is not more than 29 %.
  auto sun29 = [](int, int h, std::size_t s) { return h == 10 && s < 29 ? 1500.0 : 0.0; };
  const AnnualIlluminance b = year(1, 100, [&](int d, int h, std::size_t s) { return sun29(d, h, s) + 400; }, sun29);
  o.blindsSensorShare = 0.29;
  Result<DaylightMetrics> m29 = daylightMetrics(b, o);
  ASSERT_TRUE(m29.ok());
  EXPECT_EQ(m29->blindsClosedHours, 0);
}

TEST(DaylightMetricsTest, SyntheticYearOfSineDaysHasTheClosedFormFractions) {
  // 365 days × 24 h; sensor s: E = A_s · max(0, sin(π(t − 6)/12)), t = h − ½ the middle of the hour
  // ending at h. Occupied hours h = 9..18: t − 6 = 2.5 … 11.5, angles 37.5°, 52.5°, …, 172.5° (step 15°),
  // all in (0°, 180°). E ≥ 300 lx ⇔ sin θ ≥ 300/A:
  //  A = 300: sin θ ≥ 1: never (sin 82.5° < 1)                           → DA 0 %
  //  A = 400: sin θ ≥ 0.75 ⇔ 48.6° ≤ θ ≤ 131.4°: 52.5 … 127.5, 6 hours  → DA 60 %
  //  A = 500: sin θ ≥ 0.6 ⇔ 36.9° ≤ θ ≤ 143.1°: 37.5 … 142.5, 8 hours   → DA 80 %
  //  A = 1000: sin θ ≥ 0.3 ⇔ 17.5° ≤ θ ≤ 162.5°: 37.5 … 157.5, 9 hours  → DA 90 %
  //  A = 2500: sin θ ≥ 0.12 ⇔ 6.9° ≤ θ ≤ 173.1°: all 10                 → DA 100 %;
  //            E > 2000 ⇔ sin θ > 0.8 ⇔ 53.1° < θ < 126.9°: 67.5 … 112.5, 4 hours → UDI exceeded 40 %.
  // sDA300/50%: 4 of 5 sensors (all but A = 300) → 80 %: LM-83 "preferred"; LEED 3 points.
  // Mean over the occupied hours: A/10 · Σ_{k=0}^{9} sin(37.5° + 15°k) = A/10 · sin(75°)·sin(105°)/sin(7.5°).
  const double amplitude[] = {300, 400, 500, 1000, 2500};
  const AnnualIlluminance a = year(365, 5, [&](int, int h, std::size_t s) {
    return amplitude[s] * std::max(0.0, std::sin(kPiHere * (h - 0.5 - 6) / 12));
  });
  ASSERT_EQ(a.hours.size(), 8760u);
  EXPECT_EQ(a.hours.back().month, 12);
  EXPECT_EQ(a.hours.back().day, 31);
  Result<DaylightMetrics> m = daylightMetrics(a);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->occupiedHours, 3650);
  const double da[] = {0, 60, 80, 90, 100};
  for (std::size_t s = 0; s < 5; ++s) EXPECT_NEAR(m->sensors[s].daylightAutonomy, da[s], 1e-9) << "A = " << amplitude[s];
  EXPECT_NEAR(m->sensors[4].udiExceeded, 40, 1e-9);
  EXPECT_NEAR(m->spatialDaylightAutonomy, 80, 1e-12);
  EXPECT_TRUE(m->lm83SdaNominallyAccepted);
  EXPECT_TRUE(m->lm83SdaPreferred);
  EXPECT_EQ(m->leed.points, 3);
  const double sineSum = std::sin(75 * kPiHere / 180) * std::sin(105 * kPiHere / 180) / std::sin(7.5 * kPiHere / 180);
  EXPECT_NEAR(sineSum, 7.148, 1e-3);
  for (std::size_t s = 0; s < 5; ++s) EXPECT_NEAR(m->sensors[s].meanLux, amplitude[s] * sineSum / 10, 1e-6 * amplitude[s]);
  // The median of A·sin θ over the ten angles, every day alike: sorted, sin 172.5°, 157.5°, then the
  // pairs 37.5°/142.5°, 52.5°/127.5°, 67.5°/112.5°, 82.5°/97.5°; the 5th and 6th smallest (ranks 4
  // and 5 of 0..9, the median's rank 4.5) are the pair sin 52.5° = sin 127.5°: A · 0.79335.
  EXPECT_NEAR(m->sensors[2].percentileLux[1], 500 * std::sin(52.5 * kPiHere / 180), 1e-3);
  EXPECT_EQ(m->annualSunlightExposure, 0);
}

TEST(DaylightMetricsTest, LeedV41PointsFromTheAreaWeightedAverageAndEverySpace) {
  auto points = [](std::vector<double> sda, std::vector<double> area, std::vector<double> ase = {}) {
    if (ase.empty()) ase.assign(sda.size(), 0);
    Result<LeedDaylightPoints> p = leedV41DaylightPoints(sda, ase, area);
    EXPECT_TRUE(p.ok());
    return *p;
  };
  EXPECT_EQ(points({39.9}, {1}).points, 0);
  EXPECT_EQ(points({45}, {1}).points, 1);
  EXPECT_EQ(points({60, 50}, {1, 1}).points, 2);  // average 55: 2; one space below 55: no extra
  EXPECT_EQ(points({60, 56}, {1, 1}).points, 3);  // average 58: 2, + 1 as every space ≥ 55
  EXPECT_EQ(points({80, 76}, {1, 1}).points, 3);  // 3 already: no fourth
  // Area-weighted: (3·80 + 1·20)/4 = 65 → 2 points (unweighted, 50 → 1).
  const LeedDaylightPoints w = points({80, 20}, {3, 1});
  EXPECT_DOUBLE_EQ(w.averageSda, 65);
  EXPECT_EQ(w.averagePoints, 2);
  EXPECT_EQ(w.points, 2);
  EXPECT_FALSE(points({50}, {1}, {10}).glareStrategyRequired);  // 10 % is not more than 10 %
  EXPECT_TRUE(points({50, 50}, {1, 1}, {10, 10.5}).glareStrategyRequired);
  EXPECT_FALSE(leedV41DaylightPoints(std::vector<double>{50}, std::vector<double>{}, std::vector<double>{1}).ok());
}

TEST(DaylightMetricsTest, RefusesInconsistentDataAndBadOptionsByName) {
  AnnualIlluminance a = year(1, 2, [](int, int, std::size_t) { return 100.0; });
  auto refusal = [](const AnnualIlluminance& x, const DaylightMetricsOptions& o = {}) {
    Result<DaylightMetrics> m = daylightMetrics(x, o);
    return m.ok() ? std::string("accepted") : m.error().message;
  };
  AnnualIlluminance shortTotal = a;
  shortTotal.totalLux.pop_back();
  EXPECT_NE(refusal(shortTotal).find("totalLux"), std::string::npos);
  AnnualIlluminance noSun = a;
  noSun.directSunLux.clear();
  EXPECT_NE(refusal(noSun).find("directSunLux"), std::string::npos);
  AnnualIlluminance badHour = a;
  badHour.hours[5].hour = 25;
  EXPECT_NE(refusal(badHour).find("row 6"), std::string::npos);
  AnnualIlluminance negative = a;
  negative.totalLux[2 * 12 + 1] = -1;  // row 13 (hour 13, occupied), sensor 2
  EXPECT_NE(refusal(negative).find("row 13, sensor 2"), std::string::npos);
  DaylightMetricsOptions o;
  o.sdaTimeFraction = 1.5;
  EXPECT_NE(refusal(a, o).find("sdaTimeFraction"), std::string::npos);
  o = {};
  o.udiLowerLux = 3000;
  EXPECT_NE(refusal(a, o).find("udiLowerLux"), std::string::npos);
  o = {};
  o.blindsTransmittance = -0.1;
  EXPECT_NE(refusal(a, o).find("blindsTransmittance"), std::string::npos);
  o = {};
  o.percentiles = {101};
  EXPECT_NE(refusal(a, o).find("percentile"), std::string::npos);
  o = {};
  o.firstOccupiedHour = 20, o.lastOccupiedHour = 18;
  EXPECT_NE(refusal(a, o).find("occupied hours"), std::string::npos);
  AnnualIlluminance night = a;
  night.hours.resize(6), night.totalLux.resize(12), night.directSunLux.resize(12);  // hours 1..6 only
  EXPECT_NE(refusal(night).find("no row lies in the occupied hours"), std::string::npos);
}

// A 2 × 1 grid of two points, for the file and the page.
CalculationGrid twoPointGrid() {
  CalculationGrid g;
  g.name = "desk";
  g.origin = {0, 0.8, 0};
  g.axisU = {1, 0, 0}, g.axisV = {0, 0, 1};
  g.spacingU = g.spacingV = 1;
  g.nu = 2, g.nv = 1;
  g.pointOfCell = {0, 1};
  g.points = {{{0.5, 0.8, 0.5}, {0, 1, 0}}, {{1.5, 0.8, 0.5}, {0, 1, 0}}};
  return g;
}

TEST(DaylightMetricsTest, CsvHasOneRowPerSensorWithNamedColumnsAndUnits) {
  const double day0[] = {50, 100, 150, 300, 299, 2000, 2001, 600, 0, 1000};
  const AnnualIlluminance a = year(1, 2, [&](int, int h, std::size_t s) { return h < 9 || h > 18 ? 0.0 : s == 0 ? day0[h - 9] : 400.0; });
  DaylightMetricsOptions o;
  o.percentiles = {50};
  Result<DaylightMetrics> m = daylightMetrics(a, o);
  ASSERT_TRUE(m.ok());
  const std::string path = (std::filesystem::temp_directory_path() / "lambert-daylight-metrics.csv").string();
  ASSERT_TRUE(writeDaylightCsv(path, twoPointGrid(), FileFrame{}, *m, o).ok());
  Result<std::string> text = readWholeFile(path);
  ASSERT_TRUE(text.ok());
  // Sensor 0 as worked out in DaCdaUdiMeanAndPercentilesOfOneDayByHand (cDA 69.9667 %); sensor 1
  // 400 lx throughout.
  EXPECT_EQ(*text,
            "x,y,z,nx,ny,nz,DA_300lx_pct,cDA_300lx_pct,UDI_below_100lx_pct,UDI_100-2000lx_pct,UDI_above_2000lx_pct,E_mean_lx,E_p50_lx,"
            "sun_hours_1000lx_h,sDA_300lx_50pct_pass,ASE_1000lx_250h_exceeded\n"
            "0.5,0.8,0.5,0,1,0,50,69.9667,20,70,10,650,299.5,0,1,0\n"
            "1.5,0.8,0.5,0,1,0,100,100,0,100,0,400,400,0,1,0\n");
  PointsTable three;
  three.header = {"x", "y", "z"};
  three.rows = {{"0", "0", "0"}};
  EXPECT_FALSE(writeDaylightCsv(path, three, *m, o).ok());  // 1 point, 2 sensors
}

TEST(DaylightMetricsTest, ReportPageTabulatesCriteriaOptionsAndPlans) {
  const AnnualIlluminance a = year(1, 2, [](int, int h, std::size_t s) { return h >= 9 && h <= 18 ? (s == 0 ? 500.0 : 100.0) : 0.0; });
  DaylightMetricsOptions o;
  o.blinds = true;
  Result<DaylightMetrics> m = daylightMetrics(a, o);
  ASSERT_TRUE(m.ok());
  ASSERT_DOUBLE_EQ(m->spatialDaylightAutonomy, 50);
  const CalculationGrid grid = twoPointGrid();
  const ReportPage page = daylightReportPage(*m, grid, o, {}, "desk-daylight.csv");
  const ReportTable* spatial = nullptr;
  const ReportTable* options = nullptr;
  int images = 0;
  for (const ReportBlock& b : page.blocks) {
    if (b.kind == ReportBlock::Kind::Table && b.table.id == "daylight-spatial") spatial = &b.table;
    if (b.kind == ReportBlock::Kind::Table && b.table.id == "daylight-options") options = &b.table;
    if (b.kind == ReportBlock::Kind::Image) {
      ++images;
      EXPECT_EQ(b.image.rgb.size(), static_cast<std::size_t>(b.image.width) * b.image.height * 3);
    }
  }
  ASSERT_TRUE(spatial && options);
  EXPECT_EQ(images, 6);
  // sDA 50 %: below 55 and 75 (FAIL twice); ASE 0 % (PASS); LEED 1 point (≥ 40 %).
  EXPECT_EQ(spatial->rows[0][1], "50.0");
  EXPECT_EQ(spatial->rows[0][3], "FAIL");
  EXPECT_EQ(spatial->rows[1][3], "FAIL");
  EXPECT_EQ(spatial->rows[2][3], "PASS");
  EXPECT_EQ(spatial->rows[3][1], "1 of 3");
  bool blindsRow = false;
  for (const auto& row : options->rows) blindsRow |= row[0] == "blinds" && row[1].find("2 %") != std::string::npos && row[1].find("0.25") != std::string::npos;
  EXPECT_TRUE(blindsRow);
  Result<std::string> html = reportHtml({"daylight", "", {page}});
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("desk-daylight.csv"), std::string::npos);
  // The DA plan: sensor 0 at 100 %, sensor 1 at 0 %, on a 0–100 % scale, lines at 25/50/75.
  const FalseColourImage plan = daylightPlan(grid, *m, DaylightMetric::DaylightAutonomy, o);
  EXPECT_EQ(plan.scaleMaximum, 100);
  EXPECT_EQ(plan.isoluxLevels, (std::vector<double>{25, 50, 75}));
  // Sunlit hours: none, so the scale runs past the ASE limit, 250 h (round levels of 50 h: to 300),
  // with a line at 250.
  const FalseColourImage sun = daylightPlan(grid, *m, DaylightMetric::SunlitHours, o);
  EXPECT_EQ(sun.scaleMaximum, 300);
  EXPECT_EQ(sun.isoluxLevels, (std::vector<double>{50, 100, 150, 200, 250}));
}

}  // namespace
}  // namespace lambert
