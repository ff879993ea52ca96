// Adaptive texel sampling (bake/adaptive_texels.h) against light fields known in closed form:
// what it interpolates must be what the field is there, and it must gather little where the
// field is smooth.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "lambert/bake/adaptive_texels.h"

namespace lambert {
namespace {

constexpr int kSize = 128;

// A chart of w × h texels at (x0, y0) of atlas 0, every texel on `surface` facing `normal`; the
// texel's point is its (x, y) in the atlas, so that a field can be written over the atlas.
void addChart(LightmapTexels& texels, int x0, int y0, int w, int h, std::uint32_t surface, Vec3 normal) {
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x) {
      SurfacePoint p;
      p.point = {static_cast<double>(x), static_cast<double>(y), 0};
      p.normal = normal;
      p.surface = surface;
      texels.points.push_back(p);
      texels.atlas.push_back(0);
      texels.texel.push_back(static_cast<std::uint32_t>(y * kSize + x));
    }
}

struct Sampled {
  std::vector<Rgb> values;
  AdaptiveTexelStats stats;
  std::size_t asked = 0;  // texels the gather was asked for, counted there
};

// Samples `field` (of the texel's point and surface) adaptively.
Sampled sample(const LightmapTexels& texels, const std::function<double(const SurfacePoint&)>& field, const AdaptiveTexelOptions& options) {
  Sampled out;
  std::vector<std::uint8_t> seen(texels.points.size(), 0);
  const TexelGather gather = [&](std::span<const std::uint32_t> asked) -> Result<std::vector<Rgb>> {
    std::vector<Rgb> values;
    for (std::uint32_t t : asked) {
      EXPECT_FALSE(seen[t]) << "texel " << t << " gathered twice";
      seen[t] = 1;
      const double v = field(texels.points[t]);
      values.push_back({v, 0.5 * v, 0.25 * v});
    }
    out.asked += asked.size();
    return values;
  };
  Result<std::vector<Rgb>> values = adaptiveTexelValues(texels, kSize, 1, gather, options, &out.stats);
  EXPECT_TRUE(values) << values.error().message;
  if (values) out.values = std::move(*values);
  return out;
}

double worstError(const LightmapTexels& texels, const Sampled& sampled, const std::function<double(const SurfacePoint&)>& field) {
  double worst = 0;
  for (std::size_t t = 0; t < texels.points.size(); ++t) worst = std::fmax(worst, std::fabs(sampled.values[t].r - field(texels.points[t])));
  return worst;
}

TEST(AdaptiveTexelsTest, AnAffineFieldIsInterpolatedExactlyFromALatticeAndItsCentres) {
  LightmapTexels texels;
  addChart(texels, 0, 0, 97, 65, 0, {0, 0, 1});  // 96 × 64 texels of cells, one texel beyond
  const auto field = [](const SurfacePoint& p) { return 2.0 + 0.03 * p.point.x - 0.02 * p.point.y; };
  const Sampled sampled = sample(texels, field, {});
  EXPECT_LT(worstError(texels, sampled, field), 1e-12);
  // The lattice of every 8th texel (13 × 9), the 12 × 8 cells' centres and their edges'
  // midpoints (12 × 9 across, 13 × 8 down): 425 of 6,305.
  EXPECT_EQ(sampled.stats.gathered, 13u * 9u + 12u * 8u + 12u * 9u + 13u * 8u);
  EXPECT_EQ(sampled.asked, sampled.stats.gathered);
  EXPECT_EQ(sampled.stats.gathered + sampled.stats.interpolated, texels.points.size());
}

TEST(AdaptiveTexelsTest, AStepInTheLightIsGatheredTexelByTexelAlongItsEdge) {
  // A shadow's edge, slanted across the chart: a line through a cell always has corners on both
  // sides of it, so every cell it crosses is refined down to its texels.
  LightmapTexels texels;
  addChart(texels, 3, 5, 117, 115, 0, {0, 0, 1});  // off the lattice: its first cells lack corners
  const auto field = [](const SurfacePoint& p) { return 0.3 * p.point.x + 0.7 * p.point.y > 41.3 ? 1.0 : 0.2; };
  const Sampled sampled = sample(texels, field, {});
  EXPECT_LT(worstError(texels, sampled, field), 1e-12);
  EXPECT_LT(sampled.stats.gathered, texels.points.size() / 4);
}

TEST(AdaptiveTexelsTest, ABumpBetweenTheCornersIsFoundAtTheCentre) {
  // A contact shadow of a small object (a Gaussian dip two texels wide) in the middle of a
  // coarsest cell, where all four corners see the same light: the centre sees the dip.
  LightmapTexels texels;
  addChart(texels, 0, 0, 33, 33, 0, {0, 0, 1});
  const auto field = [](const SurfacePoint& p) {
    const double dx = p.point.x - 12, dy = p.point.y - 20;
    return 1.0 - 0.5 * std::exp(-(dx * dx + dy * dy) / 8);
  };
  const AdaptiveTexelOptions options;
  const Sampled sampled = sample(texels, field, options);
  EXPECT_LT(worstError(texels, sampled, field), options.tolerance) << "the dip at (12, 20) interpolated away";
  EXPECT_LT(sampled.stats.gathered, texels.points.size() / 2);
}

TEST(AdaptiveTexelsTest, ASaddleIsFoundAtTheEdgesMidpoints) {
  // Light rising along x and falling along y about a cell's centre (8 + 4, 16 + 4): its four
  // corners and its centre all see 1, the midpoints of its edges do not.
  LightmapTexels texels;
  addChart(texels, 0, 0, 33, 33, 0, {0, 0, 1});
  const auto field = [](const SurfacePoint& p) {
    const double dx = p.point.x - 12, dy = p.point.y - 20;
    return 1.0 + 0.02 * (dx * dx - dy * dy) * std::exp(-(dx * dx + dy * dy) / 32);
  };
  const AdaptiveTexelOptions options;
  const Sampled sampled = sample(texels, field, options);
  EXPECT_LT(worstError(texels, sampled, field), options.tolerance);
}

TEST(AdaptiveTexelsTest, EachSurfaceAndPlaneIsInterpolatedFromItsOwnTexels) {
  // Two charts side by side in the atlas with no gap, and a fold: one surface bent along x = 48,
  // its two planes lit alike at the fold but sloping differently. No texel may take another
  // surface's or plane's light.
  LightmapTexels texels;
  addChart(texels, 0, 0, 30, 40, 0, {0, 0, 1});
  addChart(texels, 30, 0, 18, 40, 1, {0, 0, 1});
  addChart(texels, 48, 0, 40, 40, 1, {0, 1, 0});
  const auto field = [](const SurfacePoint& p) {
    if (p.surface == 0) return 5.0;
    return p.normal.z > 0 ? 1.0 + 0.002 * (p.point.x - 48) : 1.0 - 0.004 * (p.point.x - 48);
  };
  const Sampled sampled = sample(texels, field, {});
  EXPECT_LT(worstError(texels, sampled, field), 1e-12);
  EXPECT_LT(sampled.stats.gathered, texels.points.size() / 3);
}

TEST(AdaptiveTexelsTest, ACoarsestStepOfOneGathersEveryTexelAndOthersAreRefused) {
  LightmapTexels texels;
  addChart(texels, 3, 5, 20, 10, 0, {0, 0, 1});
  const auto field = [](const SurfacePoint& p) { return p.point.x; };
  AdaptiveTexelOptions every;
  every.coarsestStep = 1;
  const Sampled sampled = sample(texels, field, every);
  EXPECT_EQ(sampled.stats.gathered, texels.points.size());
  EXPECT_EQ(worstError(texels, sampled, field), 0.0);
  AdaptiveTexelOptions three;
  three.coarsestStep = 3;
  const TexelGather never = [](std::span<const std::uint32_t>) -> Result<std::vector<Rgb>> { return std::vector<Rgb>{}; };
  EXPECT_FALSE(adaptiveTexelValues(texels, kSize, 1, never, three));
}

}  // namespace
}  // namespace lambert
