#include "lambert/design/calculation_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "lambert/design/false_colour.h"
#include "lambert/design/lighting.h"
#include "lambert/scene/builtin.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

// p = 0.2·5^log10(d) is 0.2·d^log10(5): checked in that second form, and at its round values.
TEST(CalculationGridTest, En12464SpacingFollowsItsFormula) {
  EXPECT_NEAR(en12464GridSpacing(1, 1), 0.2, 1e-12);
  EXPECT_NEAR(en12464GridSpacing(10, 6), 1.0, 1e-12);
  EXPECT_NEAR(en12464GridSpacing(100, 60), 5.0, 1e-12);
  for (double d : {2.5, 4.0, 7.3, 31.0}) EXPECT_NEAR(en12464GridSpacing(d, 0.6 * d), 0.2 * std::pow(d, std::log10(5.0)), 1e-12) << d;
  // An area at least twice as long as wide: its shorter side decides.
  EXPECT_NEAR(en12464GridSpacing(20, 4), en12464GridSpacing(4, 4), 1e-12);
  EXPECT_NEAR(en12464GridSpacing(1e6, 1e5), 10.0, 1e-12);  // at most 10 m
}

// A 6 m × 4 m × 3 m room in millimetres: d = 6 m (6 < 2 × 4), p = 0.2·6^0.699 = 0.700 m,
// n = round(6/0.700) = 9 cells of 0.667 m, the 4 m side round(4/0.667) = 6 cells.
TEST(CalculationGridTest, WorkPlaneIsTheStandardsLatticeAtItsHeight) {
  Scene scene = testing::closedCube(1);
  for (Surface& s : scene.surfaces)
    for (Vec3& v : s.vertices) v = {v.x * 6000 - 100, v.y * 3000 + 50, v.z * 4000};
  scene.metresPerUnit = 0.001;
  WorkPlaneSpec spec;
  spec.heightMetres = 0.75;
  Result<CalculationGrid> grid = workPlaneGrid(scene, spec);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  const double p = 0.2 * std::pow(6.0, std::log10(5.0));
  const int nu = static_cast<int>(std::lround(6 / p));
  const int nv = static_cast<int>(std::lround(4 / (6.0 / nu)));
  EXPECT_EQ(grid->nu, nu);
  EXPECT_EQ(grid->nv, nv);
  EXPECT_EQ(nu, 9);
  EXPECT_EQ(nv, 6);
  ASSERT_EQ(grid->points.size(), static_cast<std::size_t>(nu * nv));
  for (const CalculationPoint& point : grid->points) {
    EXPECT_NEAR(point.position.y, 50 + 750, 1e-9);
    EXPECT_EQ(point.normal.y, 1.0);
    EXPECT_GT(point.position.x, -100);
    EXPECT_LT(point.position.x, 5900);
  }
  // The first point is half a cell in from the corner; the last half a cell from the far one.
  EXPECT_NEAR(grid->points.front().position.x, -100 + 6000.0 / nu / 2, 1e-9);
  EXPECT_NEAR(grid->points.back().position.z, 4000 - 4000.0 / nv / 2, 1e-9);
  // A given spacing and a margin.
  spec.spacingMetres = 0.5;
  spec.marginMetres = 0.5;
  grid = workPlaneGrid(scene, spec);
  ASSERT_TRUE(grid.ok());
  EXPECT_EQ(grid->nu, 10);
  EXPECT_EQ(grid->nv, 6);
  EXPECT_NEAR(grid->points.front().position.x, -100 + 500 + 250, 1e-9);
  // Above the ceiling: refused, saying the room's height.
  spec.heightMetres = 3.5;
  grid = workPlaneGrid(scene, spec);
  ASSERT_FALSE(grid.ok());
  EXPECT_NE(grid.error().message.find("3.0"), std::string::npos) << grid.error().message;
}

TEST(CalculationGridTest, SurfaceGridLiesOnTheChosenFaces) {
  const Scene scene = cornellBox();
  SurfaceGridSpec spec;
  spec.surface = "floor";
  Result<CalculationGrid> grid = surfaceGrid(scene, spec);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  // The floor is about 0.55 m square: p = 0.2·0.556^0.699 = 0.13 m, so 4 × 4 cells.
  EXPECT_EQ(grid->nu * grid->nv, 16);
  EXPECT_EQ(grid->points.size(), 16u);
  for (const CalculationPoint& p : grid->points) {
    EXPECT_NEAR(p.normal.y, 1, 1e-3);
    EXPECT_NEAR(p.position.y, 0, 1e-6);
  }
  spec.surface = "no such surface";
  grid = surfaceGrid(scene, spec);
  ASSERT_FALSE(grid.ok());
  EXPECT_NE(grid.error().message.find("\"floor\""), std::string::npos) << grid.error().message;
  // A triangle: cells whose centres fall outside it are left out.
  Scene triangle = testing::sceneOf({{"tri", {{0, 0, 0}, {0, 0, 4}, {4, 0, 0}}, 0, {}}});
  spec.surface = "tri";
  spec.spacingMetres = 0.5;
  grid = surfaceGrid(triangle, spec);
  ASSERT_TRUE(grid.ok());
  EXPECT_EQ(grid->nu * grid->nv, 64);
  // Of 8 × 8 cells, those whose centre is inside x + z < 4: 28 (i + j ≤ 6 with centres at k + ½ / 2).
  EXPECT_EQ(grid->points.size(), 28u);
}

TEST(CalculationGridTest, StatisticsAreTheStandardsFigures) {
  const std::vector<double> lux{300, 500, 400, 600};
  const GridStatistics s = gridStatistics(lux);
  EXPECT_EQ(s.points, 4u);
  EXPECT_DOUBLE_EQ(s.average, 450);
  EXPECT_DOUBLE_EQ(s.minimum, 300);
  EXPECT_DOUBLE_EQ(s.maximum, 600);
  EXPECT_DOUBLE_EQ(s.uniformity, 300.0 / 450);
  EXPECT_DOUBLE_EQ(s.minOverMax, 0.5);
}

TEST(FalseColourTest, RoundLevelsAreOneTwoFiveSteps) {
  EXPECT_EQ(roundLevels(1000), (std::vector<double>{200, 400, 600, 800}));
  EXPECT_EQ(roundLevels(55, 6), (std::vector<double>{10, 20, 30, 40, 50}));
  EXPECT_EQ(roundLevels(3.2, 6), (std::vector<double>{1, 2, 3}));
}

// A field rising linearly along u from 0 to 1000 lx: the 500 lx isolux line is the column where
// the bilinear field crosses 500, half way across the plane, and the colours run blue to red.
TEST(FalseColourTest, IsoluxLineSitsWhereTheFieldCrossesItsLevel) {
  CalculationGrid grid;
  grid.name = "ramp";
  grid.nu = 11;
  grid.nv = 5;
  grid.spacingU = grid.spacingV = 1;
  grid.axisU = {1, 0, 0};
  grid.axisV = {0, 0, 1};
  std::vector<double> lux;
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      grid.pointOfCell.push_back(static_cast<int>(grid.points.size()));
      grid.points.push_back({{i + 0.5, 0, j + 0.5}, {0, 1, 0}});
      lux.push_back(100.0 * i);
    }
  FalseColourOptions options;
  options.planePixels = 440;  // 40 pixels per cell
  options.isoluxLevels = {500};
  options.scaleMaximum = 1000;
  const FalseColourImage image = falseColourImage(grid, lux, options);
  ASSERT_GT(image.width, 440);
  ASSERT_EQ(image.rgb.size(), static_cast<std::size_t>(image.width) * image.height * 3);
  ASSERT_EQ(image.planeWidth, 440);
  // A row of the plane clear of the isolux line's label (written half way along the line).
  const int row = image.planeTop + 30, left = image.planeLeft;
  auto pixel = [&](int x) { return &image.rgb[(static_cast<std::size_t>(row) * image.width + x) * 3]; };
  std::vector<int> black;
  for (int x = left; x < left + 440; ++x)
    if (pixel(x)[0] == 0 && pixel(x)[1] == 0 && pixel(x)[2] == 0) black.push_back(x - left);
  ASSERT_EQ(black.size(), 1u);
  // 500 lx lies at cell 5's centre: u = 5.5 cells = 220 pixels.
  EXPECT_NEAR(black[0], 220, 1);
  // Blue at the left (150 lx), red at the right.
  EXPECT_GT(pixel(left + 80)[2], pixel(left + 80)[0]);
  EXPECT_GT(pixel(left + 430)[0], pixel(left + 430)[2]);
}

// The value a plan pixel shows: the Turbo colour nearest it, as a fraction of the scale (−1 for
// a colour Turbo does not hold: text, lines, the background).
double turboValue(const std::uint8_t* rgb) {
  static std::vector<std::array<std::uint8_t, 3>> table;
  if (table.empty())
    for (int k = 0; k <= 1000; ++k) table.push_back(turboColour(k / 1000.0));
  int best = -1, bestDistance = 1 << 30;
  for (int k = 0; k <= 1000; ++k) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d += (table[k][c] - rgb[c]) * (table[k][c] - rgb[c]);
    if (d < bestDistance) bestDistance = d, best = k;
  }
  return bestDistance <= 12 ? best / 1000.0 : -1;
}

// A plan as lambert's convention draws it (x east to the right, north −z up the page): one lamp
// at x = 1.5, z = 1.0 m over a 6 m × 4 m room, near its north-west corner, peaks in the plan's
// top-left, a quarter of the way across and down, where its symbol is; the same room's west wall
// is drawn from inside the room with the scene's up at the top. The values are the lamp's exact
// direct light, I·h/r³.
TEST(CalculationGridTest, PlansAreDrawnNorthUpWithTheLuminairesWhereTheyHang) {
  Scene scene = testing::closedCube(1);
  for (Surface& s : scene.surfaces)
    for (Vec3& v : s.vertices) v = {v.x * 6, v.y * 3, v.z * 4};
  WorkPlaneSpec spec;
  spec.heightMetres = 0.8;
  spec.spacingMetres = 0.1;
  Result<CalculationGrid> grid = workPlaneGrid(scene, spec);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  Light lamp;
  lamp.kind = LightKind::Point;
  lamp.position = {1.5, 2.8, 1.0};
  lamp.intensity = Rgb::gray(1);
  std::vector<double> lux;
  for (const CalculationPoint& p : grid->points) {
    const Vec3 d = lamp.position - p.position;
    lux.push_back(683 * d.y / std::pow(length(d), 3));
  }
  const FalseColourImage image = falseColourImage(*grid, lux, planOptions(scene, std::span<const Light>(&lamp, 1)));
  // The brightest colour on the plane, away from the lamp's symbol (a ring of 7 pixels).
  double best = -1;
  int bestX = 0, bestY = 0;
  for (int y = 0; y < image.planeHeight; ++y)
    for (int x = 0; x < image.planeWidth; ++x) {
      const double t = turboValue(&image.rgb[(static_cast<std::size_t>(image.planeTop + y) * image.width + image.planeLeft + x) * 3]);
      if (t > best) best = t, bestX = x, bestY = y;
    }
  const double across = (bestX + 0.5) / image.planeWidth, down = (bestY + 0.5) / image.planeHeight;
  std::printf("peak at %.3f across, %.3f down the plan (the lamp: 0.25, 0.25)\n", across, down);
  EXPECT_NEAR(across, 0.25, 0.03);
  EXPECT_NEAR(down, 0.25, 0.03);
  // The symbol: its ring's pixels black, 7 pixels round the point under the lamp.
  const auto [cx, cy] = image.pixelOf(lamp.position);
  EXPECT_NEAR((cx - image.planeLeft) / image.planeWidth, 0.25, 0.01);
  EXPECT_NEAR((cy - image.planeTop) / image.planeHeight, 0.25, 0.01);
  int ringBlack = 0;
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * kPi * k / 16;
    const int x = static_cast<int>(std::floor(cx + 7 * std::cos(a))), y = static_cast<int>(std::floor(cy + 7 * std::sin(a)));
    const std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
    ringBlack += p[0] < 60 && p[1] < 60 && p[2] < 60;
  }
  EXPECT_GE(ringBlack, 12);

  // The west wall (x = 0), seen from inside the room: its values rising with height show red at
  // the top; its page runs north to south as a viewer facing west sees it (south, +z, on the left).
  SurfaceGridSpec wall;
  wall.surface = "x0";
  wall.spacingMetres = 0.1;
  Result<CalculationGrid> west = surfaceGrid(scene, wall);
  ASSERT_TRUE(west.ok()) << west.error().message;
  std::vector<double> rising;
  for (const CalculationPoint& p : west->points) rising.push_back(100 * p.position.y + 10 * p.position.z);
  const FalseColourImage side = falseColourImage(*west, rising);
  auto valueAt = [&](double across, double down) {
    const int x = side.planeLeft + static_cast<int>(across * side.planeWidth), y = side.planeTop + static_cast<int>(down * side.planeHeight);
    return turboValue(&side.rgb[(static_cast<std::size_t>(y) * side.width + x) * 3]);
  };
  EXPECT_GT(valueAt(0.5, 0.1), valueAt(0.5, 0.9)) << "up is up";
  EXPECT_GT(valueAt(0.1, 0.5), valueAt(0.9, 0.5)) << "facing west, south (+z) is on the left";
}

}  // namespace
}  // namespace lambert
