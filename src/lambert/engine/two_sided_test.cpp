// Two-sided faces are two surfaces back to back (Surface::twin): each side has its own
// radiosity, and neither hides the other from a ray or a camera.
#include <gtest/gtest.h>

#include <cmath>

#include "lambert/engine/radiosity.h"
#include "lambert/reference/reference.h"
#include "lambert/render/solution_image.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

constexpr Rgb kEmission{1.0, 0.5, 0.25};

// A horizontal plate, counter-clockwise seen from above (+y), at height y.
Surface plate(double y, int material, Rgb emitted = {}) {
  return {"plate", {{0.25, y, 0.25}, {0.25, y, 0.75}, {0.75, y, 0.75}, {0.75, y, 0.25}}, material, emitted};
}

// The furnace with a two-sided plate across its middle: every side of everything emits L_e and
// reflects ρ, so the radiance is L_e / (1 − ρ) on both sides of the plate as on the walls, exactly.
// A plate whose sides hid each other, or let light through, would break the balance.
Scene furnaceWithPlate() {
  Scene scene = testing::closedCube(1, kEmission, Rgb::gray(0.5));
  scene.materials.push_back({"plate", Rgb::gray(0.5), true});
  scene.surfaces.push_back(plate(0.5, 1, kEmission));
  addTwins(scene);
  return scene;
}

TEST(TwoSidedTest, TwinsAreReversedCopiesLinkedBothWays) {
  Scene scene = furnaceWithPlate();
  ASSERT_EQ(scene.surfaces.size(), 8u);
  EXPECT_EQ(scene.surfaces[6].twin, 7);
  EXPECT_EQ(scene.surfaces[7].twin, 6);
  EXPECT_EQ(scene.surfaces[7].name, "plate (back)");
  EXPECT_NEAR(surfaceNormal(scene.surfaces[6]).y, 1, 1e-12);
  EXPECT_NEAR(surfaceNormal(scene.surfaces[7]).y, -1, 1e-12);
  EXPECT_EQ(scene.surfaces[7].vertices.front(), scene.surfaces[6].vertices.front());  // same fan
  addTwins(scene);  // once only
  EXPECT_EQ(scene.surfaces.size(), 8u);
  // The mesh keeps the two sides apart: no vertex is shared, every plate patch knows its twin.
  const Mesh mesh = subdivideScene(scene, 0.2);
  for (const Patch& p : mesh.patches) EXPECT_EQ(p.twinned, p.surface >= 6);
}

TEST(TwoSidedTest, FurnaceHoldsOnBothSidesOfAPlate) {
  const Scene scene = furnaceWithPlate();
  auto engine = testing::solved(scene, testing::uniformOptions(800, SolverKind::Direct));
  ASSERT_TRUE(engine);
  const SolutionView view = engine->solution();
  const Rgb expected = kEmission * (kPi / (1 - 0.5));  // B = E / (1 − ρ), E = π L_e
  int plateSides[2] = {0, 0};
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const std::uint32_t s = view.mesh().patches[i].surface;
    if (s >= 6) ++plateSides[s - 6];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(view.radiosity()[i][c], expected[c], 0.03 * expected[c]) << "patch " << i << " of " << scene.surfaces[s].name;
  }
  EXPECT_GT(plateSides[0], 4);
  EXPECT_EQ(plateSides[0], plateSides[1]);

  // The path tracer agrees on both sides, through the same rule for rays meeting a twin.
  ReferenceRenderer reference(scene, subdivideScene(scene, 2), testing::quietReferenceOptions(4096));
  for (std::uint32_t side : {6u, 7u}) {
    const Vec3 n = surfaceNormal(scene.surfaces[side]);
    const Rgb radiance = reference.outgoingRadiance({0.4, 0.5, 0.6}, n, side, side);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance[c], expected[c] / kPi, 0.02 * expected[c] / kPi) << scene.surfaces[side].name;
  }
}

// A lone two-sided plate lit from one side: that side reflects ρ·E, the other nothing; the camera
// on the lit side sees the lit side whole, and on the dark side, the dark side.
TEST(TwoSidedTest, EachSideTakesTheLightOfItsOwnHalfSpace) {
  Scene scene = testing::sceneOf({plate(0, 0)}, Rgb::gray(0.5));
  scene.materials[0].twoSided = true;
  addTwins(scene);
  Light below;
  below.kind = LightKind::Point;
  below.position = {0.5, -1, 0.5};
  below.intensity = Rgb::gray(1);
  scene.lights = {below};
  auto engine = testing::solved(scene, testing::uniformOptions(200, SolverKind::Direct));
  ASSERT_TRUE(engine);
  const SolutionView view = engine->solution();
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const Patch& p = view.mesh().patches[i];
    const double irradiance = dot(below.position - p.centroid, p.normal) / std::pow(length(below.position - p.centroid), 3);
    if (p.surface == 1)  // the back, facing the light: ρ·E within the injection's sampling error
      EXPECT_NEAR(view.radiosity()[i].r, 0.5 * irradiance, 0.02 * 0.5 * irradiance);
    else
      EXPECT_EQ(view.radiosity()[i], Rgb{});
  }
  // Looking up from below: every pixel on the plate is lit (no back of the top side shows
  // through); looking down from above, every one is black.
  auto plateImage = [&](double eyeY) {
    SolutionImageOptions image;
    image.width = image.height = 64;
    image.lighting = Lighting::Radiosity;
    image.camera = Camera{{0.5, eyeY, 0.5}, {0.5, 0, 0.5}, {0, 0, 1}, 30};
    return renderSolution(view, image);
  };
  const Image fromBelow = plateImage(-1.5), fromAbove = plateImage(1.5);
  int lit = 0, dark = 0;
  for (int y = 16; y < 48; ++y)
    for (int x = 16; x < 48; ++x) {  // well inside the plate's image in both views
      lit += fromBelow.at(x, y).r > 0.01;
      dark += fromAbove.at(x, y).r == 0;
    }
  EXPECT_EQ(lit, 32 * 32);
  EXPECT_EQ(dark, 32 * 32);
}

}  // namespace
}  // namespace lambert
