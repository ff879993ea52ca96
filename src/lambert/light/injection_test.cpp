#include "lambert/light/injection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "lambert/light/emission.h"
#include "lambert/light/sky.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

Light spotAt(Vec3 position, Vec3 direction, double coneDegrees) {
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = position;
  spot.direction = normalize(direction);
  spot.intensity = {2e5, 1.5e5, 1e5};
  spot.coneAngleDegrees = coneDegrees;
  spot.falloffDegrees = 0.2 * coneDegrees;
  return spot;
}

// The Cornell box meshed at one edge length, with its caster and the patches' albedo.
struct CornellPatches {
  Scene scene = cornellBox();
  Mesh mesh;
  std::unique_ptr<RayCaster> caster;
  std::vector<Rgb> albedo;
  explicit CornellPatches(double edge) : mesh(subdivideScene(scene, edge)), caster(makeEmbreeRayCaster(mesh)), albedo(patchAlbedo(scene, mesh)) {}
};

// What every light injects, each traced on every patch (patchIrradiance's full pass, no tree),
// summed in the lights' order.
std::vector<Rgb> tracedOnEveryPatch(const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& albedo,
                                    const std::vector<Light>& lights, double metresPerUnit, const DirectLightOptions& options) {
  std::vector<Rgb> total(mesh.numPatches());
  for (const Light& light : lights) {
    const std::vector<Rgb> injected = injectedRadiosity(mesh, albedo, patchIrradiance(mesh, caster, light, metresPerUnit, options));
    for (std::size_t i = 0; i < total.size(); ++i) total[i] += injected[i];
  }
  return total;
}

// A spot sweeping through the Cornell box (its blocks cast shadows) beside a fixed point light, a
// second spot that changes only some frames (narrow, then wide past 90°, then from inside a
// block's bounding sphere) and a directional light, updated incrementally frame after frame:
// every frame, every patch holds the very bits of tracing every light on every patch, and every
// patch whose total changed is among the patches the update names.
TEST(InjectionTest, AnIncrementalUpdateGivesTheBitsOfAFullTraceEveryFrame) {
  const CornellPatches box(40);
  const Scene& scene = box.scene;
  const Mesh& mesh = box.mesh;
  ASSERT_GT(mesh.numPatches(), 1000u);
  const RayCaster* caster = box.caster.get();
  const std::vector<Rgb>& albedo = box.albedo;
  const DirectLightOptions options{4, 3};
  Light point;
  point.kind = LightKind::Point;
  point.position = {100, 500, 300};
  point.intensity = Rgb::gray(1e4);
  Light sun;
  sun.kind = LightKind::Directional;
  sun.direction = normalize(Vec3{0.3, -1, 0.2});
  sun.irradiance = Rgb::gray(0.5);
  DirectLightInjection injection(options);
  std::vector<Rgb> previous;
  std::size_t narrowUpdates = 0, changedInNarrowUpdates = 0;
  const int frames = 12;
  for (int frame = 0; frame < frames; ++frame) {
    const double t = static_cast<double>(frame) / (frames - 1);
    const Light moving = spotAt({100 + 350 * t, 540, 150 + 250 * t}, {std::cos(4 * t), -2, std::sin(4 * t)}, 12);
    const Light second = frame < 4   ? spotAt({400, 300, 100}, {-1, -0.5, 1}, 10)
                         : frame < 8 ? spotAt({400, 300, 100}, {-1, -0.5, 1}, 120)
                                     : spotAt({185, 200, 170}, {0, 1, 0.2}, 35);  // over the short block's top
    const std::vector<Light> lights{moving, point, second, sun};
    const DirectLightInjection::Update update = injection.update(mesh, *caster, albedo, lights, scene.metresPerUnit);
    EXPECT_EQ(update.lightsTraced, frame == 0 ? 4 : frame == 4 || frame == 8 ? 2 : 1) << "frame " << frame;
    EXPECT_EQ(update.allPatches, frame == 0) << "frame " << frame;
    const std::vector<Rgb> expected = tracedOnEveryPatch(mesh, *caster, albedo, lights, scene.metresPerUnit, options);
    const std::vector<Rgb>& total = injection.total();
    ASSERT_EQ(total.size(), expected.size());
    std::size_t lit = 0;
    for (std::size_t i = 0; i < total.size(); ++i) {
      ASSERT_EQ(total[i].r, expected[i].r) << "frame " << frame << ", patch " << i;
      ASSERT_EQ(total[i].g, expected[i].g) << "frame " << frame << ", patch " << i;
      ASSERT_EQ(total[i].b, expected[i].b) << "frame " << frame << ", patch " << i;
      lit += expected[i].maxComponent() > 0;
    }
    EXPECT_GT(lit, 100u);
    if (frame > 0 && !update.allPatches) {
      for (std::size_t i = 0; i < total.size(); ++i)
        if (!(total[i] == previous[i])) {
          EXPECT_TRUE(std::binary_search(update.changedPatches.begin(), update.changedPatches.end(), i))
              << "frame " << frame << ": patch " << i << " changed unannounced";
        }
      if (update.lightsTraced == 1) ++narrowUpdates, changedInNarrowUpdates += update.changedPatches.size();
    }
    previous = total;
  }
  // The frames where only the moving spot moved touched its cone's patches, not the box.
  ASSERT_GT(narrowUpdates, 5u);
  EXPECT_LT(changedInNarrowUpdates / narrowUpdates, mesh.numPatches() / 4);
  // Unchanged lights are not traced again; removing one starts afresh.
  const Light still = spotAt({100 + 350, 540, 150 + 250}, {std::cos(4.0), -2, std::sin(4.0)}, 12);
  const DirectLightInjection::Update none =
      injection.update(mesh, *caster, albedo, {still, point, spotAt({185, 200, 170}, {0, 1, 0.2}, 35), sun}, scene.metresPerUnit);
  EXPECT_EQ(none.lightsTraced, 0);
  EXPECT_FALSE(none.changed);
  const DirectLightInjection::Update fewer = injection.update(mesh, *caster, albedo, {point}, scene.metresPerUnit);
  EXPECT_TRUE(fewer.changed && fewer.allPatches);
  const std::vector<Rgb> pointOnly = tracedOnEveryPatch(mesh, *caster, albedo, {point}, scene.metresPerUnit, options);
  for (std::size_t i = 0; i < pointOnly.size(); ++i) ASSERT_EQ(injection.total()[i], pointOnly[i]) << "patch " << i;
}

// A scene lit by its surfaces alone updates with no lights (nothing injected, and no spot tree
// made for it); lights given afterwards (an animation adding a spot) are traced as on a fresh
// injection: the same bits as tracing them on every patch.
TEST(InjectionTest, LightsAddedAfterAnUnlitUpdateAreTracedInFull) {
  const CornellPatches box(20);
  const Scene& scene = box.scene;
  const Mesh& mesh = box.mesh;
  const RayCaster* caster = box.caster.get();
  const std::vector<Rgb>& albedo = box.albedo;
  const DirectLightOptions options{4, 3};
  DirectLightInjection injection(options);
  const DirectLightInjection::Update unlit = injection.update(mesh, *caster, albedo, {}, scene.metresPerUnit);
  EXPECT_EQ(unlit.lightsTraced, 0);
  ASSERT_EQ(injection.total().size(), mesh.numPatches());
  for (const Rgb& e : injection.total()) ASSERT_EQ(e, Rgb{});
  const std::vector<Light> lights{spotAt({278, 540, 280}, {0.2, -1, 0.1}, 25)};
  const DirectLightInjection::Update lit = injection.update(mesh, *caster, albedo, lights, scene.metresPerUnit);
  EXPECT_EQ(lit.lightsTraced, 1);
  EXPECT_TRUE(lit.changed && lit.allPatches);
  const std::vector<Rgb> expected = tracedOnEveryPatch(mesh, *caster, albedo, lights, scene.metresPerUnit, options);
  std::size_t litPatches = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(injection.total()[i], expected[i]) << "patch " << i;
    litPatches += expected[i].maxComponent() > 0;
  }
  EXPECT_GT(litPatches, 10u);
}

// More lights than are traced one by one (a sky through the Cornell box's open front and nine
// points, traced together under Ward's testing): the sky is traced on its own, so its part of the
// injection stays known for a hybrid image (skyTotal) and holds the very bits the sky alone
// injects; the rest is what the points inject, within the testing's tolerance. Before, the sky
// went through the joint testing at every point and its part was lost (skyTotal empty).
TEST(InjectionTest, ASkyAmongManyLightsKeepsItsPartKnown) {
  const CornellPatches box(80);
  const Scene& scene = box.scene;
  const Mesh& mesh = box.mesh;
  const RayCaster* caster = box.caster.get();
  const std::vector<Rgb>& albedo = box.albedo;
  const DirectLightOptions options{4, 3};
  Light sky;
  sky.kind = LightKind::Sky;
  sky.sky = std::make_shared<const SkyModel>(SkyModel::traditionalOvercast(3000));
  sky.skyDirections = 256;
  std::vector<Light> points;
  for (int k = 0; k < 9; ++k) {
    Light point;
    point.kind = LightKind::Point;
    point.position = {60.0 + 50 * k, 500, 280};
    point.intensity = Rgb::gray(0.1);
    points.push_back(point);
  }
  std::vector<Light> lights{sky};
  lights.insert(lights.end(), points.begin(), points.end());
  ASSERT_GT(lights.size(), kPerLightInjectionLights);
  DirectLightInjection injection(options);
  injection.update(mesh, *caster, albedo, lights, scene.metresPerUnit);
  const std::vector<Rgb> skyAlone = tracedOnEveryPatch(mesh, *caster, albedo, {sky}, scene.metresPerUnit, options);
  const std::vector<Rgb> pointsAlone = tracedOnEveryPatch(mesh, *caster, albedo, points, scene.metresPerUnit, options);
  ASSERT_EQ(injection.skyTotal().size(), mesh.numPatches());
  double skySum = 0, pointsSum = 0, restSum = 0;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    ASSERT_EQ(injection.skyTotal()[i], skyAlone[i]) << "patch " << i;
    skySum += skyAlone[i].g;
    pointsSum += pointsAlone[i].g;
    restSum += (injection.total()[i] - injection.skyTotal()[i]).g;
  }
  ASSERT_GT(skySum, 0.1 * pointsSum);  // both matter
  ASSERT_GT(pointsSum, 0.1 * skySum);
  EXPECT_NEAR(restSum / pointsSum, 1, options.shadowTolerance);
}

// The tree's candidates for a spot hold every patch its cone's points reach (the spot evaluated
// unshadowed at each patch's corners and points inside, patch by patch), for narrow and wide
// cones, from outside the box and from inside it; a narrow cone's are a small share of the mesh.
TEST(InjectionTest, ASpotsCandidatesHoldEveryPatchItsConeReaches) {
  const Scene scene = cornellBox();
  const Mesh mesh = subdivideScene(scene, 30);
  const PatchSphereTree tree(mesh);
  for (double cone : {5.0, 25.0, 70.0, 100.0, 170.0})
    for (const Vec3& position : {Vec3{278, 540, 280}, Vec3{185, 150, 170}, Vec3{278, 274, -800}}) {
      const Light spot = spotAt(position, Vec3{278, 0, 280} - position + Vec3{50, 0, 0}, cone);
      const std::vector<std::uint32_t> candidates = tree.candidates(spot);
      ASSERT_TRUE(std::is_sorted(candidates.begin(), candidates.end()));
      std::size_t reached = 0;
      for (std::uint32_t i = 0; i < mesh.numPatches(); ++i) {
        const PatchCorners corners = mesh.corners(i);
        bool reaches = false;
        for (std::size_t k = 0; k < corners.size(); ++k)
          for (double w : {0.0, 0.5, 0.9}) {
            const Vec3 x = corners[k] * (1 - w) + mesh.patches[i].centroid * w;
            reaches |= spotFalloff(spot, x - spot.position) > 0;
          }
        if (!reaches) continue;
        ++reached;
        EXPECT_TRUE(std::binary_search(candidates.begin(), candidates.end(), i)) << "cone " << cone << "°, patch " << i;
      }
      EXPECT_GT(reached, 0u);
      if (cone <= 25 && position.z > 0) {
        EXPECT_LT(candidates.size(), mesh.numPatches() / 3) << "cone " << cone << "°";
      }
    }
}

}  // namespace
}  // namespace lambert
