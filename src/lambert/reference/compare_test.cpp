#include <gtest/gtest.h>

#include <cmath>

#include "lambert/reference/compare.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

TEST(CompareTest, ErrorsOfAKnownDifference) {
  std::vector<Rgb> reference{{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {0, 0, 0}};
  std::vector<Rgb> value{{1.1, 1.1, 1.1}, {2, 2, 2}, {3, 3, 3}, {0.01, 0.01, 0.01}};
  RadianceError all = radianceError(value, reference);
  EXPECT_EQ(all.count, 12u);
  EXPECT_NEAR(all.meanReference, 1.5, 1e-12);
  EXPECT_NEAR(all.meanValue, (3 * 1.1 + 3 * 2 + 3 * 3 + 3 * 0.01) / 12, 1e-12);
  EXPECT_NEAR(all.rmse, std::sqrt((3 * 0.01 + 3 * 0.0001) / 12), 1e-12);
  EXPECT_NEAR(all.maxAbsolute, 0.1, 1e-12);
  EXPECT_NEAR(all.maxRelative, 0.1, 1e-12);  // the black element is too dark to divide by
  std::vector<char> mask{0, 1, 1, 1};
  RadianceError masked = radianceError(value, reference, mask);
  EXPECT_EQ(masked.count, 9u);
  EXPECT_NEAR(masked.maxAbsolute, 0.01, 1e-12);
  EXPECT_EQ(radianceError(reference, reference).rmse, 0);
}

TEST(CompareTest, MaskLeavesOutTheLightsRim) {
  Scene scene = cornellBox();
  std::vector<Vec3> points{{278, 548.8, 280},  // on the ceiling right above the light
                           {343 + 20, 548.8, 280},  // 20 mm beside its edge
                           {278, 548.8, 500},  // ceiling far from it
                           {278, 0, 280}};  // floor
  std::vector<char> keep = awayFromEmitters(scene, points, 40);
  EXPECT_EQ(keep, (std::vector<char>{0, 0, 1, 1}));
}

}  // namespace
}  // namespace lambert
