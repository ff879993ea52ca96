// Lightmap updates after lights move (bake/lightmap_updates.h) against an independent bake: the
// full per-texel gather and direct light of bakeLightmaps over the same re-solved solution.
#include <gtest/gtest.h>

#include <cmath>

#include "lambert/bake/lightmap_updates.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/method/point_gather.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/scene/builtin.h"
#include "tests/support/engines.h"

namespace lambert {
namespace {

LightmapBakeOptions bakeOptions(int atlasSize) {
  LightmapBakeOptions options;
  options.uvs.atlasSize = atlasSize;
  options.showProgress = false;
  return options;
}

// Over the covered texels: the relative RMS of a against b (green channel, by b's mean) and the
// largest difference by b's mean.
struct Difference {
  double rms = 0, max = 0;
};
Difference difference(const std::vector<Image>& a, const std::vector<Image>& b, const BakedLightmaps& layout) {
  double sum2 = 0, sumB = 0, largest = 0;
  std::size_t n = 0;
  for (std::size_t atlas = 0; atlas < a.size(); ++atlas)
    for (std::size_t t = 0; t < a[atlas].pixels.size(); ++t) {
      if (!layout.covered[atlas][t]) continue;
      const double d = a[atlas].pixels[t].g - b[atlas].pixels[t].g;
      sum2 += d * d;
      sumB += b[atlas].pixels[t].g;
      largest = std::fmax(largest, std::fabs(d));
      ++n;
    }
  const double mean = sumB / static_cast<double>(n);
  return {std::sqrt(sum2 / static_cast<double>(n)) / mean, largest / mean};
}

// cornell-spots with its spots turned by `angle` radians about the vertical.
std::vector<Light> turned(const Scene& scene, double angle) {
  std::vector<Light> lights = scene.lights;
  for (Light& light : lights) {
    const Vec3 d = light.direction;
    light.direction = {d.x * std::cos(angle) + d.z * std::sin(angle), d.y, -d.x * std::sin(angle) + d.z * std::cos(angle)};
  }
  return lights;
}

class LightmapUpdateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = *builtinScene("cornell-spots");
    engine_ = testing::solved(scene_);
    ASSERT_TRUE(engine_);
    auto baked = bakeLightmaps(engine_->solution(), bakeOptions(128));
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    baked_ = std::move(*baked);
  }
  // Moves the spots, re-solves warm to convergence, and bakes afresh over the same atlas.
  std::vector<Image> moveAndBake(double angle) {
    engine_->setLights(turned(scene_, angle));
    EXPECT_TRUE(engine_->solve().ok());
    auto fresh = bakeLightmaps(engine_->solution(), baked_.uvs, bakeOptions(128));
    EXPECT_TRUE(fresh.ok());
    return fresh->irradiance;
  }
  Scene scene_;
  std::unique_ptr<Radiosity> engine_;
  BakedLightmaps baked_;
};

TEST_F(LightmapUpdateTest, AnUpdateBeforeAnyLightMovesGivesTheBake) {
  auto updater = LightmapUpdater::create(engine_->solution(), baked_);
  ASSERT_TRUE(updater.ok()) << updater.error().message;
  ASSERT_TRUE(updater->update(engine_->solution()).ok());
  const Difference d = difference(updater->lightmaps(), baked_.irradiance, baked_);
  EXPECT_LT(d.max, 1e-6);
  // Padding texels are filled as the bake fills them.
  for (std::size_t t = 0; t < baked_.irradiance[0].pixels.size(); ++t)
    EXPECT_NEAR(updater->lightmaps()[0].pixels[t].g, baked_.irradiance[0].pixels[t].g, 1e-6 * (1 + baked_.irradiance[0].pixels[t].g));
  EXPECT_EQ(updater->stats().directTexelsTraced, 0u);
}

TEST_F(LightmapUpdateTest, UpdatesFollowMovingSpotsAsAFreshBakeDoes) {
  auto updater = LightmapUpdater::create(engine_->solution(), baked_);
  ASSERT_TRUE(updater.ok()) << updater.error().message;
  auto everyTexel = LightmapUpdater::create(engine_->solution(), baked_, {.latticeStep = 1});
  ASSERT_TRUE(everyTexel.ok());
  // The lattice gathers at a fraction of the texels (in this small atlas, where every chart is a
  // few lattice cells wide, about half; in the 10⁵-face building's 1024² atlas, bench/).
  EXPECT_LT(updater->stats().gatherPoints, updater->stats().texels * 6 / 10);
  EXPECT_EQ(everyTexel->stats().gatherPoints, everyTexel->stats().texels);
  for (const double angle : {0.15, 0.5}) {
    const std::vector<Image> fresh = moveAndBake(angle);
    ASSERT_TRUE(updater->update(engine_->solution()).ok());
    ASSERT_TRUE(everyTexel->update(engine_->solution()).ok());
    const Difference stale = difference(baked_.irradiance, fresh, baked_);
    const Difference lattice = difference(updater->lightmaps(), fresh, baked_);
    const Difference exact = difference(everyTexel->lightmaps(), fresh, baked_);
    // The moved spots change the lightmap (the test's perturbation), and the updates follow:
    // the spots' direct light traced again, the indirect change from the weights.
    EXPECT_GT(stale.rms, 0.3) << angle;
    EXPECT_LT(exact.rms, 0.02) << angle;
    EXPECT_LT(lattice.rms, 0.02) << angle;
    EXPECT_LT(exact.max, 0.3) << angle;
    EXPECT_LT(lattice.max, 0.3) << angle;
    // Only the texels a spot can reach, before or after, were traced again.
    EXPECT_LT(updater->stats().directTexelsTraced, updater->stats().texels);
    EXPECT_GT(updater->stats().directTexelsTraced, 0u);
    std::printf("turned %.2f rad: stale %.3f, every texel rms %.4f max %.3f, lattice rms %.4f max %.3f, traced %zu of %zu\n", angle,
                stale.rms, exact.rms, exact.max, lattice.rms, lattice.max, updater->stats().directTexelsTraced, updater->stats().texels);
  }
}

// The recorded weights are the gather's own arithmetic: over the node means and the corner
// vertices' radiosity of the same solution they give the light the gather returned.
TEST_F(LightmapUpdateTest, GatherWeightsReproduceTheGatherTheyWereRecordedFrom) {
  const SolutionView& view = engine_->solution();
  const LightmapTexels texels = lightmapTexels(scene_, baked_.uvs);
  std::vector<SurfacePoint> points;
  for (std::size_t i = 0; i < texels.points.size(); i += 7) points.push_back(texels.points[i]);
  auto gathered = pointGather(view, points, PointGatherRequest::LightAndWeights);
  ASSERT_TRUE(gathered.ok()) << gathered.error().message;
  auto mean = nodeMeanRadiosity(view);
  ASSERT_TRUE(mean.ok());
  const std::vector<Rgb> corners = view.vertexValues(VertexQuantity::Radiosity);
  ASSERT_EQ(gathered->nodes.start.size(), points.size() + 1);
  double largest = 0, withCorners = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Rgb e;
    for (std::uint32_t k = gathered->nodes.start[i]; k < gathered->nodes.start[i + 1]; ++k) e += (*mean)[gathered->nodes.node[k]] * gathered->nodes.weight[k];
    for (std::uint32_t k = gathered->near.start[i]; k < gathered->near.start[i + 1]; ++k) e += corners[gathered->near.corner[k]] * gathered->near.weight[k];
    if (gathered->near.start[i + 1] > gathered->near.start[i]) ++withCorners;
    largest = std::fmax(largest, gathered->fromSurfaces[i].g);
    EXPECT_NEAR(std::fmax(0.0, e.g), gathered->fromSurfaces[i].g, 1e-5 * (1 + gathered->fromSurfaces[i].g)) << i;
  }
  EXPECT_GT(largest, 0);
  EXPECT_GT(withCorners, 0);  // the corner weights are exercised too
}

TEST_F(LightmapUpdateTest, TheFlatMethodIsRefused) {
  auto engine = testing::solved(scene_, testing::uniformOptions(200));
  ASSERT_TRUE(engine);
  auto updater = LightmapUpdater::create(engine->solution(), baked_);
  ASSERT_FALSE(updater.ok());
  EXPECT_NE(updater.error().message.find("hierarchical"), std::string::npos) << updater.error().message;
}

}  // namespace
}  // namespace lambert
