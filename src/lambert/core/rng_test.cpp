#include "lambert/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace lambert {
namespace {

TEST(RngTest, StreamsAreReproducibleAndDistinct) {
  Pcg32 a(7, 3), b(7, 3), otherStream(7, 4), otherSeed(8, 3);
  int sameStream = 0, sameSeed = 0;
  for (int k = 0; k < 1000; ++k) {
    std::uint32_t x = a.nextUint();
    EXPECT_EQ(x, b.nextUint());
    sameStream += x == otherStream.nextUint();
    sameSeed += x == otherSeed.nextUint();
  }
  EXPECT_LT(sameStream, 3);
  EXPECT_LT(sameSeed, 3);
}

// Neighbouring streams (patch ids 0, 1, 2 …) must not be correlated: the mean of products of
// centred uniforms from streams k and k + 1 is zero within its standard error.
TEST(RngTest, NeighbouringStreamsAreUncorrelated) {
  const int n = 20000;
  for (std::uint64_t stream = 0; stream < 4; ++stream) {
    Pcg32 first(1, stream), second(1, stream + 1);
    double sum = 0;
    for (int k = 0; k < n; ++k) sum += (first.nextDouble() - 0.5) * (second.nextDouble() - 0.5);
    const double standardError = (1.0 / 12) / std::sqrt(n);
    EXPECT_LT(std::fabs(sum / n), 5 * standardError) << "streams " << stream << ", " << stream + 1;
  }
}

TEST(RngTest, UniformInTheUnitIntervalAndBelowABound) {
  Pcg32 rng(42, 0);
  const int n = 60000, bins = 6;
  double sum = 0;
  std::vector<int> count(bins, 0);
  for (int k = 0; k < n; ++k) {
    double u = rng.nextDouble();
    ASSERT_GE(u, 0);
    ASSERT_LT(u, 1);
    sum += u;
    std::uint32_t b = rng.nextBelow(bins);
    ASSERT_LT(b, static_cast<std::uint32_t>(bins));
    ++count[b];
  }
  EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  // χ² with 5 degrees of freedom: above 20.5 with probability 0.1%.
  double chi2 = 0;
  for (int c : count) chi2 += (c - n / double(bins)) * (c - n / double(bins)) / (n / double(bins));
  EXPECT_LT(chi2, 20.5);
}

}  // namespace
}  // namespace lambert
