// Normal cones against brute force: every normal merged in lies inside the merged cone, and the
// facing test never says "no" where random pairs of points find a face that faces the other ball.
#include "lambert/geometry/normal_cone.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "lambert/core/rng.h"

namespace lambert {
namespace {

Vec3 randomUnit(Pcg32& rng) {
  const double z = 2 * rng.nextDouble() - 1, phi = 2 * kPi * rng.nextDouble(), s = std::sqrt(std::fmax(0.0, 1 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// A unit vector within `angle` of `axis` (uniform in its cap's area).
Vec3 withinCone(const Vec3& axis, double angle, Pcg32& rng) {
  Vec3 t, b;
  orthonormalBasis(axis, t, b);
  const double cosTheta = 1 - rng.nextDouble() * (1 - std::cos(angle)), phi = 2 * kPi * rng.nextDouble();
  const double sinTheta = std::sqrt(std::fmax(0.0, 1 - cosTheta * cosTheta));
  return normalize(axis * cosTheta + t * (sinTheta * std::cos(phi)) + b * (sinTheta * std::sin(phi)));
}

TEST(NormalConeTest, AMergedConeHoldsEveryNormalOfBoth) {
  Pcg32 rng(7, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<Vec3> normals;
    NormalCone cone;
    const int count = 1 + static_cast<int>(rng.nextDouble() * 12);
    const Vec3 around = randomUnit(rng);
    const double spread = rng.nextDouble() * kPi;
    for (int k = 0; k < count; ++k) {
      normals.push_back(withinCone(around, spread, rng));
      cone = mergeCones(cone, NormalCone::of(normals.back()));
    }
    ASSERT_FALSE(cone.empty());
    for (const Vec3& n : normals)
      if (!cone.whole()) {
        ASSERT_LE(angleBetween(cone.axis, n), cone.halfAngle + 1e-12) << trial;
      }
  }
  // Two normals 0.6 rad apart: the cone half way between them, 0.3 rad wide (the smallest).
  const NormalCone two = mergeCones(NormalCone::of({0, 0, 1}), NormalCone::of({std::sin(0.6), 0, std::cos(0.6)}));
  EXPECT_NEAR(two.halfAngle, 0.3, 1e-6);
  EXPECT_NEAR(angleBetween(two.axis, {std::sin(0.3), 0, std::cos(0.3)}), 0, 1e-6);
  // Opposite normals need every direction but are held; the empty cone merges to the other.
  const NormalCone opposite = mergeCones(NormalCone::of({0, 0, 1}), NormalCone::of({0, 0, -1}));
  EXPECT_GE(opposite.halfAngle, 0.5 * kPi);
  EXPECT_FALSE(coneMayFace(NormalCone{}, {0, 0, 0}, 1, {5, 0, 0}, 1));
}

TEST(NormalConeTest, NoFaceIsMissedThatFacesTheOtherBall) {
  Pcg32 rng(11, 3);
  int culled = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const NormalCone cone{randomUnit(rng), rng.nextDouble() * 0.8};
    const Vec3 from{0, 0, 0}, to = randomUnit(rng) * (0.5 + 4 * rng.nextDouble());
    const double fromRadius = 0.3 * rng.nextDouble(), toRadius = 0.3 * rng.nextDouble();
    const bool may = coneMayFace(cone, from, fromRadius, to, toRadius);
    culled += !may;
    if (may) continue;
    // Said "no": no face in the cone at a point of the first ball sees a point of the second in front.
    for (int k = 0; k < 400; ++k) {
      const Vec3 n = withinCone(cone.axis, cone.halfAngle, rng);
      const Vec3 y = from + randomUnit(rng) * (fromRadius * std::cbrt(rng.nextDouble()));
      const Vec3 x = to + randomUnit(rng) * (toRadius * std::cbrt(rng.nextDouble()));
      ASSERT_LE(dot(n, x - y), 1e-12) << trial;
    }
  }
  EXPECT_GT(culled, 500);  // the test is not vacuous: it says "no" often
  // A patch facing away from a ball behind it.
  EXPECT_FALSE(coneMayFace({{0, 0, 1}, 0.2}, {0, 0, 0}, 0.1, {0, 0, -3}, 0.5));
  EXPECT_TRUE(coneMayFace({{0, 0, 1}, 0.2}, {0, 0, 0}, 0.1, {0, 0, 3}, 0.5));
}

}  // namespace
}  // namespace lambert
