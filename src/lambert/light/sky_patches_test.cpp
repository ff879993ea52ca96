#include "lambert/light/sky_patches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "lambert/light/sun.h"

namespace lambert {
namespace {

constexpr double kDeg = kPi / 180;

// Tregenza's sky has 145 patches, Reinhart's MF:n 144 n² + 1; their solid angles add up to the
// hemisphere's 2π, each is the closed form Δaz (sin alt_hi − sin alt_lo), and each patch's centre
// falls in the patch.
TEST(SkyPatchesTest, CountsSolidAnglesAndCentresOfTregenzaAndReinhart) {
  for (int mf : {1, 2, 4}) {
    Result<SkyPatches> sky = SkyPatches::reinhart(mf);
    ASSERT_TRUE(sky);
    EXPECT_EQ(sky->count(), 144 * mf * mf + 1) << "MF:" << mf;
    double total = 0;
    for (int p = 0; p < sky->count(); ++p) {
      total += sky->solidAngle(p);
      EXPECT_EQ(sky->patchOf(sky->centre(p)), p) << "MF:" << mf << " patch " << p;
    }
    EXPECT_NEAR(total, 2 * kPi, 1e-12) << "MF:" << mf;
  }
  // Tregenza's published layout: rings 12° high, starting at the horizon, with 30, 30, 24, 24, 18,
  // 12 and 6 patches, the cap from 84° up; the first patch of each ring centred on north.
  const SkyPatches tregenza = *SkyPatches::reinhart(1);
  const int firstOfRing[] = {0, 30, 60, 84, 108, 126, 138, 144};
  for (int ring = 0; ring < 7; ++ring) {
    const SkyPatches::Bounds b = tregenza.bounds(firstOfRing[ring]);
    EXPECT_NEAR(b.altitudeLo, 12.0 * ring, 1e-12);
    EXPECT_NEAR(b.altitudeHi, 12.0 * (ring + 1), 1e-12);
    EXPECT_NEAR(b.azimuthLo + b.azimuthHi, 0, 1e-12);
    EXPECT_NEAR(b.azimuthHi - b.azimuthLo, 360.0 / (firstOfRing[ring + 1] - firstOfRing[ring]), 1e-12);
  }
  EXPECT_NEAR(tregenza.bounds(144).altitudeLo, 84, 1e-12);
  // Patch 1 is east of north (clockwise seen from above), patch 29 west of it.
  EXPECT_EQ(tregenza.patchOf(skyDirection(12, 6, {0, 0, -1})), 1);
  EXPECT_EQ(tregenza.patchOf(skyDirection(-12, 6, {0, 0, -1})), 29);
  EXPECT_EQ(tregenza.patchOf({0, -1, 0}), -1);
  // MF:2's rings are 90/14.5 = 6.2069° high.
  EXPECT_NEAR(SkyPatches::reinhart(2)->bounds(0).altitudeHi, 90 / 14.5, 1e-12);
  EXPECT_FALSE(SkyPatches::reinhart(0));
}

// On an open horizontal point, a patch's coefficient is ∫_p cos Z dω = Δaz (sin² alt_hi − sin² alt_lo)/2
// exactly; the binned estimate, from 65,536 directions (about 450 a patch), agrees patch by patch
// within its sampling error (a cell across a patch's border counts in the patch of its sample:
// 5.8% at worst), and their sum is the uniform sky's π. Over a sky whose luminance varies smoothly
// these errors cancel between neighbours (MeanLuminancesReproduce… below).
TEST(SkyPatchesTest, PatchCoefficientsOfAnOpenPointAreTheClosedForm) {
  const SkyPatches sky = *SkyPatches::reinhart(1);
  std::vector<double> coefficient(static_cast<std::size_t>(sky.count()));
  auto open = [](std::span<const Vec3>, std::span<bool> seen) { std::fill(seen.begin(), seen.end(), true); };
  skyPatchIlluminance(sky, {0, 1, 0}, 65536, open, SkyEdges::Cells, coefficient);
  double sum = 0, worst = 0;
  for (int p = 0; p < sky.count(); ++p) {
    const SkyPatches::Bounds b = sky.bounds(p);
    const double exact = (b.azimuthHi - b.azimuthLo) * kDeg *
                         (std::pow(std::sin(b.altitudeHi * kDeg), 2) - std::pow(std::sin(b.altitudeLo * kDeg), 2)) / 2;
    worst = std::max(worst, std::fabs(coefficient[p] / exact - 1));
    sum += coefficient[p];
  }
  EXPECT_LT(worst, 0.07);
  EXPECT_NEAR(sum, kPi, 1e-9);
  // Half the sky hidden (a wall to the south: every direction with z > 0): the patches south of
  // east–west get nothing, those north of it their whole share.
  auto northOnly = [](std::span<const Vec3> directions, std::span<bool> seen) {
    for (std::size_t i = 0; i < directions.size(); ++i) seen[i] = directions[i].z < 0;
  };
  std::vector<double> half(coefficient.size());
  skyPatchIlluminance(sky, {0, 1, 0}, 65536, northOnly, SkyEdges::Cells, half);
  EXPECT_EQ(half[15], 0.0);  // due south, lowest ring
  EXPECT_NEAR(half[0], coefficient[0], 1e-12);
  double halfSum = 0;
  for (double e : half) halfSum += e;
  EXPECT_NEAR(halfSum, kPi / 2, 0.01 * kPi / 2);
}

// The patches' mean luminances weighted by the open point's coefficients give the sky's
// horizontal illuminance (SkyModel's own Simpson quadrature): within 1% for the overcast and a
// clear sky on Tregenza's patches, closer on finer ones.
TEST(SkyPatchesTest, MeanLuminancesReproduceTheHorizontalIlluminance) {
  for (int type : {1, 12}) {
    const SkyModel model = SkyModel::cieStandard(type, 135, 35, 1000).value();
    double previous = 1;
    for (int mf : {1, 2, 4}) {
      const SkyPatches sky = *SkyPatches::reinhart(mf);
      double e = 0;
      for (int p = 0; p < sky.count(); ++p) {
        const SkyPatches::Bounds b = sky.bounds(p);
        const double cosWeighted = (b.azimuthHi - b.azimuthLo) * kDeg *
                                   (std::pow(std::sin(b.altitudeHi * kDeg), 2) - std::pow(std::sin(b.altitudeLo * kDeg), 2)) / 2;
        e += cosWeighted * sky.meanLuminance(model, p);
      }
      const double error = std::fabs(e / model.horizontalIlluminance() - 1);
      EXPECT_LT(error, 0.01) << "type " << type << " MF:" << mf;
      EXPECT_LE(error, previous * 1.01) << "type " << type << " MF:" << mf;
      previous = error;
    }
  }
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

// The interpolation reproduces a function linear in altitude and in azimuth (within a ring's
// span) exactly from its values at the patch centres, and every direction's weights add up to 1.
TEST(SkyPatchesTest, InterpolationIsLinearBetweenCentres) {
  const SkyPatches sky = *SkyPatches::reinhart(4);
  auto altitudeOf = [&](int p) { return sky.patchOf(sky.centre(p)) == p ? std::asin(sky.centre(p).y) * 180 / kPi : -1; };
  for (double altitude : {1.0, 5.5, 20.3, 45.0, 71.7, 86.0, 89.5})
    for (double azimuth : {0.0, 33.3, 181.2, 359.0}) {
      const SkyPatches::Interpolation w = sky.interpolation(skyDirection(azimuth, altitude, {0, 0, -1}));
      double sum = 0, value = 0;
      for (int k = 0; k < 4; ++k)
        if (w.patch[k] >= 0) sum += w.weight[k], value += w.weight[k] * altitudeOf(w.patch[k]);
      EXPECT_NEAR(sum, 1, 1e-12) << altitude << " " << azimuth;
      // Altitude itself is linear: reproduced wherever the direction lies between ring centres.
      if (altitude > 90 / 28.5 / 2) EXPECT_NEAR(value, altitude, 1e-9) << altitude << " " << azimuth;
    }
  EXPECT_EQ(sky.interpolation({0, -1, 0}).patch[0], -1);
}

}  // namespace
}  // namespace lambert
