#include <gtest/gtest.h>

#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

const Surface& surfaceNamed(const Scene& scene, const std::string& name) {
  for (const Surface& s : scene.surfaces)
    if (s.name == name) return s;
  ADD_FAILURE() << "no surface " << name;
  return scene.surfaces.front();
}

TEST(SceneTest, CornellBoxWallsFaceIntoTheRoom) {
  Scene scene = cornellBox();
  const Vec3 roomCentre{278, 274, 280};
  for (const char* name : {"floor", "ceiling", "back wall", "red wall", "green wall"}) {
    const Surface& s = surfaceNamed(scene, name);
    EXPECT_GT(dot(surfaceNormal(s), roomCentre - s.vertices[0]), 0) << name;
  }
  EXPECT_NEAR(surfaceNormal(surfaceNamed(scene, "floor")).y, 1, 1e-9);
  EXPECT_NEAR(surfaceNormal(surfaceNamed(scene, "ceiling")).y, -1, 1e-9);
  EXPECT_NEAR(surfaceNormal(surfaceNamed(scene, "light")).y, -1, 1e-9);
  EXPECT_NEAR(surfaceNormal(surfaceNamed(scene, "green wall")).x, 1, 1e-9);
  EXPECT_LT(surfaceNormal(surfaceNamed(scene, "red wall")).x, -0.99);
  EXPECT_NEAR(surfaceNormal(surfaceNamed(scene, "back wall")).z, -1, 1e-9);
}

TEST(SceneTest, CornellBlocksFaceOutward) {
  Scene scene = cornellBox();
  struct Block { const char* prefix; Vec3 axis; };
  for (Block block : {Block{"short block", {185, 0, 169}}, Block{"tall block", {368, 0, 351}}}) {
    int sides = 0;
    for (const Surface& s : scene.surfaces) {
      if (s.name.rfind(block.prefix, 0) != 0) continue;
      Vec3 n = surfaceNormal(s);
      if (s.name.find("top") != std::string::npos) {
        EXPECT_NEAR(n.y, 1, 1e-9) << s.name;
        continue;
      }
      ++sides;
      Vec3 centroid;
      for (const Vec3& v : s.vertices) centroid += v / 4.0;
      Vec3 outward = centroid - block.axis;
      outward.y = 0;
      EXPECT_GT(dot(n, outward), 0) << s.name;
      EXPECT_NEAR(n.y, 0, 1e-9) << s.name;
    }
    EXPECT_EQ(sides, 4) << block.prefix;
  }
}

TEST(SceneTest, CornellLightMatchesPublishedData) {
  Scene scene = cornellBox();
  const Surface& light = surfaceNamed(scene, "light");
  EXPECT_EQ(light.emittedRadiance, (Rgb{17, 12, 4}));
  EXPECT_NEAR(surfaceArea(light), 130.0 * 105.0, 1e-9);
  int emitters = 0;
  for (const Surface& s : scene.surfaces) emitters += s.emittedRadiance.sum() > 0;
  EXPECT_EQ(emitters, 1);
  EXPECT_EQ(scene.camera.eye, (Vec3{278, 273, -800}));
  EXPECT_DOUBLE_EQ(scene.camera.verticalFovDegrees, 39.3);
}

TEST(SceneTest, BuiltinLookupByName) {
  EXPECT_TRUE(builtinScene("cornell").has_value());
  EXPECT_FALSE(builtinScene("no such scene").has_value());
  for (const std::string& name : builtinSceneNames()) EXPECT_TRUE(builtinScene(name).has_value()) << name;
}

// Bilinear, repeating, and safe on coordinates a broken file gives.
TEST(TextureTest, SamplesBilinearlyAndRepeats) {
  Texture t;
  t.width = 2;
  t.height = 1;
  t.pixels = {Rgb::gray(0.2), Rgb::gray(0.6)};
  EXPECT_NEAR(t.sample(0.25, 0.5).r, 0.2, 1e-12);  // the first pixel's centre
  EXPECT_NEAR(t.sample(0.75, 0.5).r, 0.6, 1e-12);
  EXPECT_NEAR(t.sample(0.5, 0.5).r, 0.4, 1e-12);   // halfway between the centres
  EXPECT_NEAR(t.sample(0.0, 0.5).r, 0.4, 1e-12);   // the edge blends with the far side: it repeats
  EXPECT_NEAR(t.sample(3.25, -7.5).r, 0.2, 1e-12);
  EXPECT_NEAR(t.sample(NAN, INFINITY).r, 0.4, 1e-12);  // read as (0, 0)
}

}  // namespace
}  // namespace lambert
