#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/rng.h"
#include "lambert/formfactor/kernels.h"

namespace lambert {
namespace {

// Differential element at the origin (normal +z) to a parallel a×b rectangle at height c with a
// corner above it (Howell's catalogue, B-3).
double cornerRectangle(double a, double b, double c) {
  double A = a / c, B = b / c;
  double sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
  return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * kPi);
}

std::vector<Vec3> regularPolygonFacingDown(double equalAreaRadius, double height, int sides) {
  // Circumradius giving the polygon the disk's area.
  double r = equalAreaRadius * std::sqrt(2 * kPi / (sides * std::sin(2 * kPi / sides)));
  std::vector<Vec3> polygon;
  for (int k = 0; k < sides; ++k) {
    double phi = -2 * kPi * k / sides;  // clockwise seen from above: counter-clockwise from below
    polygon.push_back({r * std::cos(phi), r * std::sin(phi), height});
  }
  return polygon;
}

TEST(KernelTest, PointToRectangleMatchesHowell) {
  for (auto [a, b, c] : {std::array<double, 3>{1, 1, 1}, {2, 0.5, 1}, {0.1, 3, 0.7}, {5, 5, 0.01}}) {
    std::vector<Vec3> rect{{0, 0, c}, {0, b, c}, {a, b, c}, {a, 0, c}};
    double f = pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, rect, {0, 0, -1});
    EXPECT_NEAR(f, cornerRectangle(a, b, c), 1e-12) << a << " " << b << " " << c;
  }
}

TEST(KernelTest, PointToCoaxialDisk) {
  for (auto [radius, height] : {std::pair{1.0, 1.0}, {1.0, 2.0}, {3.0, 0.5}}) {
    auto disk = regularPolygonFacingDown(radius, height, 512);
    double f = pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, disk, {0, 0, -1});
    EXPECT_NEAR(f, radius * radius / (height * height + radius * radius), 2e-5);
  }
}

TEST(KernelTest, BackFacingAndBelowHorizonGiveZero) {
  std::vector<Vec3> up{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};  // normal +z: faces away
  EXPECT_EQ(pointToPolygonFormFactor({0.5, 0.5, 0}, {0, 0, 1}, up, {0, 0, 1}), 0);
  std::vector<Vec3> down{{0, 0, -1}, {0, 1, -1}, {1, 1, -1}, {1, 0, -1}};  // below x's horizon
  EXPECT_EQ(pointToPolygonFormFactor({0.5, 0.5, 0}, {0, 0, 1}, down, {0, 0, 1}), 0);
}

// A point in a polygon's own plane sees none of it: the back twin of a two-sided face, a
// duplicate of the face and a face lying on it are all in that plane, where the rounding of
// rotated coordinates puts the point a hair in front of the plane or behind it at random. Counted
// as in front, the contour integral from inside the polygon is the whole hemisphere (F = 1).
// Lifted by a thousandth of its size, the point sees nearly all of a polygon facing it.
TEST(KernelTest, APointInThePolygonsPlaneSeesNoneOfIt) {
  // A unit square turned about an oblique axis, so that no coordinate is exact.
  const Vec3 axis = normalize(Vec3{0.3, 0.7, 0.2});
  const double angle = 0.7;
  const auto turn = [&](Vec3 p) {  // Rodrigues' rotation
    return p * std::cos(angle) + cross(axis, p) * std::sin(angle) + axis * (dot(axis, p) * (1 - std::cos(angle)));
  };
  std::vector<Vec3> square;
  for (Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}) square.push_back(turn(p + Vec3{0.1, 0.2, 0.3}));
  const Vec3 n = turn({0, 0, 1});
  Pcg32 rng(7, 1);
  int nearlyAll = 0;
  for (int k = 0; k < 2000; ++k) {
    const double u = 0.05 + 0.9 * rng.nextDouble(), v = 0.05 + 0.9 * rng.nextDouble();
    const Vec3 x = lerp(lerp(square[0], square[1], u), lerp(square[3], square[2], u), v);
    // The back twin's point (normal −n) and a duplicate's or a face-on-face point (normal ±n).
    for (const Vec3& xNormal : {n * -1.0, n}) {
      ASSERT_EQ(pointToPolygonFormFactor(x, xNormal, square, n), 0) << "point " << k;
      std::vector<Vec3> reversed(square.rbegin(), square.rend());
      ASSERT_EQ(pointToPolygonFormFactor(x, xNormal, reversed, n * -1.0), 0) << "point " << k;
    }
    nearlyAll += pointToPolygonFormFactor(x + n * 1e-3, n * -1.0, square, n) > 0.99;
  }
  EXPECT_GT(nearlyAll, 1900);
}

// A polygon cut by the tangent plane contributes only its upper part: a unit wall standing on the
// receiver's plane equals the perpendicular-rectangle formula whether or not it extends below.
TEST(KernelTest, HorizonClippingKeepsTheUpperPart) {
  std::vector<Vec3> wall{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}};         // x = 1, facing −x
  std::vector<Vec3> tallWall{{1, 0, -1}, {1, 1, -1}, {1, 1, 1}, {1, 0, 1}};  // the same, reaching below
  Vec3 x{0, 0, 0}, n{0, 0, 1}, wallNormal{-1, 0, 0};
  double f = pointToPolygonFormFactor(x, n, wall, wallNormal);
  EXPECT_GT(f, 0);
  EXPECT_NEAR(pointToPolygonFormFactor(x, n, tallWall, wallNormal), f, 1e-12);
  // Howell B-4 (element to a perpendicular rectangle, corner on the common line): a=1 (height), b=1, c=1.
  double X = 1, Y = 1;  // X = a/b (height/width), Y = c/b (distance/width)
  double expected = (std::atan(1 / Y) - Y / std::sqrt(X * X + Y * Y) * std::atan(1 / std::sqrt(X * X + Y * Y))) / (2 * kPi);
  EXPECT_NEAR(f, expected, 1e-12);
}

// Approaching a patch's edge the analytic factor stays finite and tends to the half-space value;
// the point-to-point kernel grows without bound.
TEST(KernelTest, AdjacentPatchesStayFinite) {
  std::vector<Vec3> wall{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};  // x = 0, facing +x
  Vec3 n{0, 0, 1}, wallNormal{1, 0, 0};
  double previous = 0;
  for (double d : {1e-1, 1e-3, 1e-6, 1e-9}) {
    double f = pointToPolygonFormFactor({d, 0.5, 0}, n, wall, wallNormal);
    EXPECT_TRUE(std::isfinite(f));
    EXPECT_GE(f, previous);
    EXPECT_LE(f, 0.5 + 1e-12);
    previous = f;
  }
  // At the foot of a wall, the wall fills the half of the hemisphere on its side: F → 1/2.
  EXPECT_NEAR(previous, 0.5, 1e-6);
  EXPECT_GT(pointToPointKernel({1e-6, 0.5, 1e-6}, n, {0, 0.5, 2e-6}, wallNormal), 1e10);
}

// The corner weights against the kernel integrated directly: a midpoint rule over cells graded
// toward the point's foot on the source's plane, with each corner's weight linear over the fan
// triangles (0, 1, 2) and (0, 2, 3), as a face is drawn. Points: 0.01 above the source's edge in
// the plane perpendicular to it (a room's corner vertex, the case the near field is for), 10⁻⁵
// above it (a vertex site nudged off its face), over the source's middle tilted 30°, and off to
// one side facing it obliquely. Each weight within 0.2% of the whole factor, their sum the
// contour integral's factor to 10⁻⁹ (a different formula: the boundary integrals' check).
TEST(KernelTest, CornerFormFactorsMatchTheKernelIntegratedAgainstEachCornersWeight) {
  // Cell boundaries on [lo, hi], `finest` wide at `focus` and growing 8% a cell away from it.
  const auto graded = [](double lo, double hi, double focus, double finest) {
    std::vector<double> side = {0};
    for (double h = finest; side.back() < 2; h *= 1.08) side.push_back(side.back() + h);
    std::vector<double> edges;
    for (auto it = side.rbegin(); it != side.rend(); ++it)
      if (focus - *it > lo) edges.push_back(focus - *it);
    edges.insert(edges.begin(), lo);
    for (double d : side)
      if (d > 0 && focus + d < hi) edges.push_back(focus + d);
    edges.push_back(hi);
    return edges;
  };
  const Vec3 sourceNormal{0, 0, 1};
  const double s = std::sqrt(0.75);
  const struct {
    Vec3 x, normal;
  } points[] = {{{0.3, 0, 0.01}, {0, 1, 0}}, {{0.3, 0, 1e-5}, {0, 1, 0}}, {{0.4, 0.6, 0.3}, {0.5, 0, -s}}, {{1.5, 0.2, 0.4}, {-s, 0, -0.5}}};
  for (const auto& [x, xNormal] : points) {
    const double finest = std::fmax(1e-6, 0.1 * x.z);
    const std::vector<double> xs = graded(0, 1, std::clamp(x.x, 0.0, 1.0), finest), ys = graded(0, 1, std::clamp(x.y, 0.0, 1.0), finest);
    for (const bool quad : {true, false}) {
      const std::vector<Vec3> polygon = quad ? std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}
                                             : std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
      std::array<double, 4> direct{0, 0, 0, 0};
      for (std::size_t i = 0; i + 1 < xs.size(); ++i)
        for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
          // A triangle's cell across its hypotenuse through a 32 × 32 grid of its own.
          const bool straddles = !quad && xs[i] + ys[j] < 1 && xs[i + 1] + ys[j + 1] > 1;
          const int split = straddles ? 32 : 1;
          const double du = (xs[i + 1] - xs[i]) / split, dv = (ys[j + 1] - ys[j]) / split;
          for (int a = 0; a < split; ++a)
            for (int b = 0; b < split; ++b) {
              const double u = xs[i] + (a + 0.5) * du, v = ys[j] + (b + 0.5) * dv;
              if (!quad && u + v > 1) continue;
              const double k = pointToPointKernel(x, xNormal, {u, v, 0}, sourceNormal) * du * dv;
              // Barycentric in (0,0)-(1,0)-(1,1) below the quad's diagonal, (0,0)-(1,1)-(0,1) above it.
              const std::array<double, 4> phi = !quad  ? std::array<double, 4>{1 - u - v, u, v, 0}
                                                 : v <= u ? std::array<double, 4>{1 - u, u - v, v, 0}
                                                          : std::array<double, 4>{1 - v, 0, u, v - u};
              for (int c = 0; c < 4; ++c) direct[c] += k * phi[c];
            }
        }
      const std::array<double, 4> w = cornerFormFactors(x, xNormal, polygon, sourceNormal);
      const double factor = pointToPolygonFormFactor(x, xNormal, polygon, sourceNormal);
      ASSERT_GT(factor, 0.01);
      EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], factor, 1e-9 * factor);
      for (std::size_t c = 0; c < polygon.size(); ++c)
        EXPECT_NEAR(w[c], direct[c], 2e-3 * factor) << (quad ? "quad" : "triangle") << " corner " << c << " at " << x.x << ',' << x.y << ',' << x.z;
      if (!quad) {
        EXPECT_EQ(w[3], 0.0);
      }
    }
  }
  // The point beside the near edge sees its strip at nearly half its hemisphere: corners 0 and 1
  // carry most of it, and they are what a uniform split by area (¼ each) would get wrong.
  const std::array<double, 4> w = cornerFormFactors(points[0].x, points[0].normal, std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, sourceNormal);
  EXPECT_GT(w[0] + w[1], 0.8 * (w[0] + w[1] + w[2] + w[3]));
}

// The quadrature where it is used against the contour integral: random quads and triangles,
// points in random directions at 10 to 1,000 times their bounding radius, random normals; each
// within 0.13% (measured worst 0.13% for triangles at the 10× threshold). Closer, or straddling
// the point's horizon, it is the contour integral itself.
TEST(KernelTest, FarPolygonsByQuadrature) {
  Pcg32 rng(7, 1);
  const auto uniform = [&] { return 2 * rng.nextDouble() - 1; };
  double worst = 0;
  int used = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const bool quad = trial % 2 == 0;
    const std::vector<Vec3> polygon = quad ? std::vector<Vec3>{{-0.5, -0.3, 0}, {0.5 + 0.2 * uniform(), -0.3, 0}, {0.5, 0.4 + 0.2 * uniform(), 0}, {-0.5 + 0.2 * uniform(), 0.4, 0}}
                                           : std::vector<Vec3>{{-0.5, -0.3, 0}, {0.6 * uniform() + 0.5, -0.3, 0}, {0.3 * uniform(), 0.6, 0}};
    Vec3 centre;
    for (const Vec3& p : polygon) centre += p;
    centre = centre / static_cast<double>(polygon.size());
    double radius = 0;
    for (const Vec3& p : polygon) radius = std::fmax(radius, length(p - centre));
    const Vec3 direction = normalize(Vec3{uniform(), uniform(), std::fabs(uniform()) + 0.05});
    const Vec3 x = centre + direction * (radius * std::pow(10.0, 1.0 + 2.0 * rng.nextDouble()));
    const Vec3 n = normalize(Vec3{uniform(), uniform(), uniform()});
    const double exact = pointToPolygonFormFactor(x, n, polygon, {0, 0, 1});
    const double fast = pointToPolygonFormFactorFast(x, n, polygon, {0, 0, 1});
    if (!(exact > 0)) {
      EXPECT_EQ(fast, exact);
      continue;
    }
    ++used;
    worst = std::fmax(worst, std::fabs(fast - exact) / exact);
  }
  EXPECT_GT(used, 5000);
  EXPECT_LT(worst, 1.4e-3);
  EXPECT_GT(worst, 1e-6);  // the quadrature was used, not the contour integral everywhere
  // Close by, or straddling the horizon: exact.
  const std::vector<Vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(pointToPolygonFormFactorFast({0.5, 0.5, 2}, {0, 0, -1}, square, {0, 0, 1}), pointToPolygonFormFactor({0.5, 0.5, 2}, {0, 0, -1}, square, {0, 0, 1}));
  EXPECT_EQ(pointToPolygonFormFactorFast({0.5, 0.5, 20}, {1, 0, 0}, square, {0, 0, 1}),
            pointToPolygonFormFactor({0.5, 0.5, 20}, {1, 0, 0}, square, {0, 0, 1}));
}

TEST(KernelTest, TriangleSamplingIsUniformAndInside) {
  std::array<Vec3, 3> tri{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 1, 0}};
  Pcg32 rng(3, 4);
  Vec3 mean;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    Vec3 p = sampleTriangle(tri, rng.nextDouble(), rng.nextDouble());
    ASSERT_GE(p.x, -1e-12);
    ASSERT_GE(p.y, -1e-12);
    ASSERT_LE(p.x / 2 + p.y, 1 + 1e-12);
    mean += p / n;
  }
  EXPECT_NEAR(mean.x, 2.0 / 3, 3e-3);  // the centroid
  EXPECT_NEAR(mean.y, 1.0 / 3, 3e-3);
}

TEST(KernelTest, IncenterIsEquidistantFromTheEdges) {
  std::array<Vec3, 3> tri{Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{0, 3, 0}};
  Vec3 c = incenter(tri);
  EXPECT_NEAR(c.x, 1, 1e-12);  // r = (a + b − c)/2 = 1 for the 3-4-5 triangle
  EXPECT_NEAR(c.y, 1, 1e-12);
}

}  // namespace
}  // namespace lambert
