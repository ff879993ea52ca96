#include "lambert/design/calculation_grid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lambert/design/false_colour.h"
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
  // The plane starts at x = 16 (the margin) below the title; a middle row of it.
  const int row = 2 * 12 * 2 + 16 + 100;
  auto pixel = [&](int x) { return &image.rgb[(static_cast<std::size_t>(row) * image.width + x) * 3]; };
  std::vector<int> black;
  for (int x = 16; x < 16 + 440; ++x)
    if (pixel(x)[0] == 0 && pixel(x)[1] == 0 && pixel(x)[2] == 0) black.push_back(x - 16);
  ASSERT_EQ(black.size(), 1u);
  // 500 lx lies at cell 5's centre: u = 5.5 cells = 220 pixels.
  EXPECT_NEAR(black[0], 220, 1);
  // Blue at the left (150 lx), red at the right.
  EXPECT_GT(pixel(16 + 80)[2], pixel(16 + 80)[0]);
  EXPECT_GT(pixel(16 + 430)[0], pixel(16 + 430)[2]);
}

}  // namespace
}  // namespace lambert
