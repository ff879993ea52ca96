// Sampling a polygon by the solid angle it subtends (core/spherical_sampling.h), checked against
// sums over fine grids on the polygons (independent of Arvo's construction) and the octant.
#include "lambert/core/spherical_sampling.h"

#include <gtest/gtest.h>

#include <vector>

#include "lambert/core/sampling.h"

namespace lambert {
namespace {

// ∫ over the polygon of g(y) dA by the midpoint rule on an n × n grid of each fan triangle's
// barycentric cells (fine enough that the grid's error is far below the tolerances).
template <typename G>
double overPolygon(const std::vector<Vec3>& polygon, G g, int n = 400) {
  double sum = 0;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    const Vec3 a = polygon[0], b = polygon[k], c = polygon[k + 1];
    const double cellArea = 0.5 * length(cross(b - a, c - a)) / (n * n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        // the upright cell's centroid, then the inverted one's where it exists
        sum += g(a + (b - a) * ((i + 1.0 / 3) / n) + (c - a) * ((j + 1.0 / 3) / n)) * cellArea;
        if (i + j + 1 < n) sum += g(a + (b - a) * ((i + 2.0 / 3) / n) + (c - a) * ((j + 2.0 / 3) / n)) * cellArea;
      }
  }
  return sum;
}

TEST(SphericalSamplingTest, TheOctantIsAQuarterHemisphereAndItsDirectionsAreUniform) {
  const Vec3 X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
  EXPECT_NEAR(triangleSolidAngle(X, Y, Z), kPi / 2, 1e-12);
  // Uniform on the octant: the mean of z is ∫ cos θ dω / Ω = (π/4)/(π/2) and half lie where x > y.
  constexpr int kSamples = 1 << 14;
  double meanZ = 0;
  int xAboveY = 0;
  for (int i = 0; i < kSamples; ++i) {
    const auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(i), 0x1234567u, 0x89abcdefu);
    const Vec3 d = sampleSphericalTriangle(X, Y, Z, kPi / 2, u, v);
    ASSERT_NEAR(length(d), 1.0, 1e-9);
    ASSERT_GE(std::fmin(d.x, std::fmin(d.y, d.z)), -1e-9);
    meanZ += d.z / kSamples;
    xAboveY += d.x > d.y;
  }
  EXPECT_NEAR(meanZ, 0.5, 2e-3);
  EXPECT_NEAR(static_cast<double>(xAboveY) / kSamples, 0.5, 5e-3);
}

// A quad seen obliquely and close: its solid angle against Σ cos θ_y dA / r² over a grid, and
// the form factor Ω · mean(cos θ_x) / π against Σ cos θ_x cos θ_y dA / (π r²). With points
// uniform in area instead, the mean of cos θ_x would give neither.
TEST(SphericalSamplingTest, SolidAngleAndFormFactorOfACloseObliqueQuadMatchAGridSum) {
  const std::vector<Vec3> quad = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}};  // normal +z
  const Vec3 quadNormal{0, 0, 1};
  for (const auto& [x, xNormal] : {std::pair{Vec3{0.3, -0.2, 0.25}, normalize(Vec3{0.2, 1, -0.6})},
                                   std::pair{Vec3{1.9, 2.5, 0.05}, normalize(Vec3{-1, -0.3, -0.2})}}) {
    const double gridSolidAngle = overPolygon(quad, [&](const Vec3& y) {
      const Vec3 d = y - x;
      return dot(quadNormal, -d) / std::pow(lengthSquared(d), 1.5);
    });
    const double gridFactor = overPolygon(quad, [&](const Vec3& y) {
      const Vec3 d = y - x;
      const double r2 = lengthSquared(d);
      return std::fmax(0.0, dot(xNormal, d)) * dot(quadNormal, -d) / (kPi * r2 * r2);
    });
    constexpr int kSamples = 1 << 15;
    double meanCos = 0, solidAngle = 0;
    for (int i = 0; i < kSamples; ++i) {
      const auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(i), 0xa5a5a5u, 0x5a5a5a5u);
      const auto sample = sampleBySolidAngle(x, quad, u, v);
      ASSERT_TRUE(sample.has_value());
      ASSERT_NEAR(sample->point.z, 0.0, 1e-9);
      ASSERT_GE(sample->point.x, -1e-9);
      ASSERT_LE(sample->point.x, 2 + 1e-9);
      ASSERT_GE(sample->point.y, -1e-9);
      ASSERT_LE(sample->point.y, 3 + 1e-9);
      meanCos += std::fmax(0.0, dot(xNormal, sample->direction)) / kSamples;
      solidAngle = sample->solidAngle;
    }
    EXPECT_NEAR(solidAngle / gridSolidAngle, 1.0, 2e-3);
    EXPECT_NEAR(solidAngle * meanCos / kPi / gridFactor, 1.0, 5e-3);
  }
}

TEST(SphericalSamplingTest, APointInThePolygonsPlaneGetsNoSample) {
  const std::vector<Vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_FALSE(sampleBySolidAngle(Vec3{2, 2, 0}, triangle, 0.3, 0.7).has_value());
}

}  // namespace
}  // namespace lambert
