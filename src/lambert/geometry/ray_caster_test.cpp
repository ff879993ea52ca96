#include <gtest/gtest.h>

#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/geometry/coverage.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

// Random rays through the Cornell box: Embree and the brute-force loop agree on every answer.
TEST(RayCasterTest, EmbreeAgreesWithBruteForce) {
  Mesh mesh = subdivideScene(cornellBox(), 120);
  auto embree = makeEmbreeRayCaster(mesh);
  auto brute = makeBruteForceRayCaster(mesh);
  Pcg32 rng(7, 0);
  int hits = 0, occludedCount = 0;
  const int kRays = 2000;
  std::vector<Ray> rays;
  for (int k = 0; k < kRays; ++k) {
    Vec3 origin{50 + 450 * rng.nextDouble(), 20 + 500 * rng.nextDouble(), 20 + 520 * rng.nextDouble()};
    Vec3 direction{rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, rng.nextDouble() - 0.5};
    Ray ray{origin, direction, 0, 400 * rng.nextDouble() + 1};
    rays.push_back(ray);
    auto a = embree->intersect(ray);
    auto b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << k;
    if (a) {
      ++hits;
      EXPECT_NEAR(a->t, b->t, 1e-4 * b->t);
      EXPECT_EQ(a->frontFace, b->frontFace);
    }
    bool occluded = embree->occluded(ray);
    EXPECT_EQ(occluded, brute->occluded(ray));
    EXPECT_EQ(occluded, a.has_value());
    occludedCount += occluded;
  }
  // Both outcomes are exercised.
  EXPECT_GT(hits, kRays / 10);
  EXPECT_LT(hits, kRays * 9 / 10);

  std::unique_ptr<bool[]> batch(new bool[rays.size()]);
  embree->occluded(rays, std::span<bool>(batch.get(), rays.size()));
  int batchOccluded = 0;
  for (std::size_t k = 0; k < rays.size(); ++k) batchOccluded += batch[k];
  EXPECT_EQ(batchOccluded, occludedCount);
  // The batch intersection gives each ray the brute-force loop's nearest hit.
  std::vector<std::optional<RayHit>> batchHits(rays.size());
  embree->intersect(rays, batchHits);
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const std::optional<RayHit> b = brute->intersect(rays[k]);
    ASSERT_EQ(batchHits[k].has_value(), b.has_value()) << "ray " << k;
    if (!b) continue;
    EXPECT_NEAR(batchHits[k]->t, b->t, 1e-4 * b->t);
    EXPECT_EQ(batchHits[k]->frontFace, b->frontFace);
    EXPECT_EQ(mesh.patches[batchHits[k]->patch].surface, mesh.patches[b->patch].surface);
  }
  EXPECT_EQ(embree->raysCast(), 4u * kRays);
  // Rays cast from many threads are all counted (each thread counts in its own slot).
  parallelFor(0, rays.size(), [&](std::size_t k) { (void)embree->occluded(rays[k]); }, 1);
  EXPECT_EQ(embree->raysCast(), 5u * kRays);
}

TEST(RayCasterTest, HitReportsPatchAndSide) {
  Scene scene = cornellBox();
  Mesh mesh = subdivideScene(scene, 1000);
  auto caster = makeEmbreeRayCaster(mesh);
  // Straight down from the room's middle onto the floor, away from the blocks.
  auto hit = caster->intersect(Ray{{450, 300, 450}, {0, -1, 0}, 0, INFINITY});
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 300, 1e-3);
  EXPECT_EQ(scene.surfaces[mesh.patches[hit->patch].surface].name, "floor");
  EXPECT_TRUE(hit->frontFace);
  // From above the ceiling, the ceiling's back is what is hit first.
  auto back = caster->intersect(Ray{{100, 600, 100}, {0, -1, 0}, 0, INFINITY});
  ASSERT_TRUE(back.has_value());
  EXPECT_FALSE(back->frontFace);
  EXPECT_FALSE(caster->occluded(Ray{{450, 300, 450}, {0, -1, 0}, 0, 299}));
}

// Measuring some patches' open fractions gives each of them what measuring all gives (a patch's
// points depend on its corners and index only) and leaves the others as they were: the Cornell
// box's floor runs under its blocks, so some patches are partly covered.
TEST(RayCasterTest, OpenFractionsOfChosenPatchesMatchMeasuringAll) {
  Mesh all = subdivideScene(cornellBox(), 40);
  auto caster = makeEmbreeRayCaster(all);
  measureOpenFractions(all, *caster);
  Mesh some = all;
  std::vector<std::uint8_t> measure(some.numPatches(), 0);
  int partly = 0;
  for (std::size_t i = 0; i < some.numPatches(); ++i) {
    some.patches[i].openFraction = -1;  // not a fraction: must stay where not measured
    measure[i] = i % 3 == 0;
    partly += all.patches[i].openFraction > 0 && all.patches[i].openFraction < 1;
  }
  EXPECT_GT(partly, 0);
  measureOpenFractions(some, *caster, measure);
  for (std::size_t i = 0; i < some.numPatches(); ++i)
    EXPECT_EQ(some.patches[i].openFraction, measure[i] ? all.patches[i].openFraction : -1.0) << "patch " << i;
}

}  // namespace
}  // namespace lambert
