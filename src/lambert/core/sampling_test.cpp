// The sampling primitives the form factors and light injection stand on, checked directly
// (as pbrt-v4's util/sampling_test.cpp does): the (0,2)-sequence's net property, Owen-shuffled
// indices, and the equal-area warps.
#include "lambert/core/sampling.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

namespace lambert {
namespace {

// Whether points are one per elementary rectangle of every shape 2^k × 2^(m−k).
bool isZeroMTwoNet(const std::vector<UnitSquarePoint>& points, int m) {
  for (int k = 0; k <= m; ++k) {
    const std::uint32_t columns = 1u << k, rows = 1u << (m - k);
    std::vector<int> count(static_cast<std::size_t>(columns) * rows, 0);
    for (const UnitSquarePoint& p : points) {
      auto i = static_cast<std::uint32_t>(p.u * columns), j = static_cast<std::uint32_t>(p.v * rows);
      if (++count[j * columns + i] > 1) return false;
    }
  }
  return true;
}

TEST(SamplingTest, EveryPowerOfTwoPrefixOfTheScrambledSequenceIsANet) {
  for (std::uint32_t scramble : {0u, 0x9e3779b9u, 0xdeadbeefu}) {
    for (int m = 0; m <= 10; ++m) {
      std::vector<UnitSquarePoint> points;
      for (std::uint32_t k = 0; k < (1u << m); ++k) {
        points.push_back(scrambledZeroTwo(k, scramble, scramble * 2654435761u + 1));
        ASSERT_GE(points.back().u, 0);
        ASSERT_LT(points.back().u, 1);
        ASSERT_LT(points.back().v, 1);
      }
      EXPECT_TRUE(isZeroMTwoNet(points, m)) << "m = " << m << ", scramble " << scramble;
    }
  }
}

TEST(SamplingTest, PerAxisStratificationAloneIsNotANet) {
  // The check above can fail: a Latin-hypercube set (both axes stratified, paired along the
  // diagonal) is one point per row and column but piles up in the 2 × 2 blocks.
  std::vector<UnitSquarePoint> diagonal;
  for (int k = 0; k < 16; ++k) diagonal.push_back({(k + 0.5) / 16, (k + 0.5) / 16});
  EXPECT_FALSE(isZeroMTwoNet(diagonal, 4));
}

TEST(SamplingTest, ShuffledIndicesPermuteOneAlignedBlock) {
  for (std::uint32_t seed : {1u, 77u, 0x12345678u}) {
    for (int m = 1; m <= 12; ++m) {
      const std::uint32_t size = 1u << m;
      std::set<std::uint32_t> images;
      std::uint32_t block = shuffledIndex(0, seed) >> m;
      for (std::uint32_t k = 0; k < size; ++k) {
        std::uint32_t shuffled = shuffledIndex(k, seed);
        EXPECT_EQ(shuffled >> m, block) << "m = " << m;
        images.insert(shuffled & (size - 1));
      }
      EXPECT_EQ(images.size(), size) << "not a permutation, m = " << m;
    }
  }
  // … and different seeds give different permutations.
  int same = 0;
  for (std::uint32_t k = 0; k < 256; ++k) same += (shuffledIndex(k, 1) & 255) == (shuffledIndex(k, 2) & 255);
  EXPECT_LT(same, 32);
}

TEST(SamplingTest, ReverseBitsIsAnInvolution) {
  for (std::uint32_t v : {0u, 1u, 0x80000000u, 0x12345678u, 0xffffffffu}) EXPECT_EQ(reverseBits(reverseBits(v)), v);
  EXPECT_EQ(reverseBits(1u), 0x80000000u);
}

TEST(SamplingTest, PolygonWarpIsEqualArea) {
  // A quad made of a 1 × 1 and a 1 × 3 triangle: a quarter of the points land in the first.
  const std::vector<Vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-2, 1, 0}};
  const int n = 1 << 12;
  int inFirst = 0;
  Vec3 mean;
  for (int k = 0; k < n; ++k) {
    UnitSquarePoint p = scrambledZeroTwo(static_cast<std::uint32_t>(k), 0x5bd1e995u, 0x1b873593u);
    Vec3 x = sampleConvexPolygon(quad, p.u, p.v);
    inFirst += x.x >= x.y;  // below the diagonal from (0,0) to (1,1)
    mean += x / n;
  }
  EXPECT_NEAR(inFirst / static_cast<double>(n), 0.25, 0.01);
  // The area centroid of the quad: (1/2·(2/3, 1/3) + 3/2·(−1/3, 2/3)) / 2 = (−1/12, 7/12).
  EXPECT_NEAR(mean.x, -1.0 / 12, 5e-3);
  EXPECT_NEAR(mean.y, 7.0 / 12, 5e-3);
  EXPECT_NEAR(mean.z, 0, 1e-15);
}

}  // namespace
}  // namespace lambert
