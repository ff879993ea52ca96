#include "lambert/load/obj.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "lambert/core/warning.h"
#include "lambert/light/emission.h"
#include "lambert/load/scene_file.h"
#include "tests/support/emissive_strip.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

const char* kRoom = R"(mtllib room.mtl
v 0 0 0
v 2 0 0
v 2 0 2
v 0 0 2
v 0.8 1.9 0.8
v 1.2 1.9 0.8
v 1.2 1.9 1.2
v 0.8 1.9 1.2
o floor
usemtl wall
f 1 4 3
f 1 3 2
g lamp
usemtl lamp
f 5 6 7 8
)";

TEST(ObjTest, GroupsMaterialsAndUnits) {
  const fs::path dir = testing::scratchDirectory("obj", "room");
  write(dir / "room.obj", kRoom);
  write(dir / "room.mtl", "newmtl wall\nKd 0.7 0.6 0.5\nnewmtl lamp\nKd 1 1 1\nKe 5 4.5 4\n");
  WarningCapture captured;
  Result<Scene> scene = readObj((dir / "room.obj").string(), ObjOptions{.metresPerUnit = 0.01, .regions = {}});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->name, "room");
  EXPECT_EQ(scene->metresPerUnit, 0.01);
  ASSERT_EQ(scene->surfaces.size(), 2u);
  const Surface& floor = scene->surfaces[0];
  EXPECT_EQ(floor.name, "floor");
  EXPECT_EQ(floor.faces.size(), 2u);  // two triangles, one smooth region
  EXPECT_EQ(floor.vertices.size(), 4u);
  EXPECT_NEAR(surfaceArea(floor), 4, 1e-12);
  EXPECT_GT(surfaceNormal(floor).y, 0.999);  // counter-clockwise seen from above: facing up
  const Rgb kd = scene->materials[floor.material].albedo;  // tinyobjloader's parse is within an ulp
  EXPECT_NEAR(kd.r, 0.7, 1e-15);
  EXPECT_NEAR(kd.g, 0.6, 1e-15);
  EXPECT_NEAR(kd.b, 0.5, 1e-15);
  EXPECT_EQ(floor.emittedRadiance, Rgb{});
  const Surface& lamp = scene->surfaces[1];
  EXPECT_EQ(lamp.name, "lamp");
  EXPECT_EQ(lamp.emittedRadiance, (Rgb{5, 4.5, 4}));
  EXPECT_LT(surfaceNormal(lamp).y, -0.999);  // facing down into the room
  EXPECT_EQ(scene->materials[lamp.material].albedo, Rgb::gray(0.999));  // Kd 1 lowered, with a warning
  EXPECT_GE(captured.count("material 'lamp': Kd: albedo of 1 or more lowered to 0.999"), 1) << captured.messages().size();
  EXPECT_EQ(scene->camera.target, (Vec3{1, 0.95, 1}));
}

TEST(ObjTest, MissingMtlIsAWarningAndDefaultGrey) {
  const fs::path dir = testing::scratchDirectory("obj", "no-mtl");
  write(dir / "room.obj", kRoom);
  WarningCapture captured;
  Result<Scene> scene = readObj((dir / "room.obj").string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_GE(captured.count((dir / "room.obj").string() + ": "), 1) << captured.messages().size();
  ASSERT_EQ(scene->materials.size(), 1u);
  EXPECT_EQ(scene->materials[0].name, "default");
  EXPECT_EQ(scene->materials[0].albedo, Rgb::gray(0.5));
  ASSERT_EQ(scene->surfaces.size(), 2u);  // one material now, but two groups: two named regions
  EXPECT_EQ(scene->surfaces[1].name, "lamp");
  EXPECT_EQ(scene->surfaces[1].emittedRadiance, Rgb{});
}

// An OBJ written by a program that ran from its project's root names its library from there
// (McGuire's Cornell box as shipped with pathed: `mtllib scenes/CornellBox-Original.mtl` inside
// scenes/): the path is found from the folder above, with a warning naming the line, and the
// materials (here the lamp's Ke) are read.
TEST(ObjTest, MtllibRelativeToAFolderAboveIsFound) {
  const fs::path root = testing::scratchDirectory("obj", "mtllib-from-root");
  fs::create_directories(root / "scenes");
  std::string room = kRoom;
  room.replace(room.find("mtllib room.mtl"), std::string("mtllib room.mtl").size(), "mtllib scenes/room.mtl");
  write(root / "scenes" / "room.obj", room);
  write(root / "scenes" / "room.mtl", "newmtl wall\nKd 0.7 0.6 0.5\nnewmtl lamp\nKd 0.8 0.8 0.8\nKe 5 4.5 4\n");
  WarningCapture captured;
  Result<Scene> scene = readObj((root / "scenes" / "room.obj").string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_GE(captured.count("mtllib 'scenes/room.mtl' is not beside the OBJ; read " + (root / "scenes/room.mtl").string()), 1u);
  const auto lamp = std::find_if(scene->surfaces.begin(), scene->surfaces.end(), [](const Surface& s) { return s.name == "lamp"; });
  ASSERT_NE(lamp, scene->surfaces.end());
  EXPECT_EQ(lamp->emittedRadiance, (Rgb{5, 4.5, 4}));
  // Where no folder holds it, the materials are the default grey, as for a missing library.
  write(root / "scenes" / "lost.obj", std::string(room).replace(room.find("scenes/room.mtl"), 15, "nowhere/x.mtl"));
  Result<Scene> lost = readObj((root / "scenes" / "lost.obj").string());
  ASSERT_TRUE(lost.ok()) << lost.error().message;
  EXPECT_EQ(lost->materials.at(0).name, "default");
}

// MTL's map_Ke (Blender's OBJ exporter writes it beside Ke): the emitted radiance is Ke × the
// sRGB-decoded texture, as glTF's emissiveTexture; the strip of tests/support/emissive_strip.h.
TEST(ObjTest, MapKeScalesTheEmissionPerPatch) {
  const fs::path dir = testing::scratchDirectory("obj", "map-ke");
  testing::writeHalfWhitePng(dir / "emit.png");
  std::string obj = "mtllib strip.mtl\n";
  for (const Vec3& p : testing::kStripPositions) obj += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " 0\n";
  // OBJ's v runs up from the image's bottom row; the texture's halves are left and right.
  for (const Vec3& p : testing::kStripPositions) obj += "vt " + std::to_string(testing::stripU(p)) + " " + std::to_string(p.y) + "\n";
  obj += "o strip\nusemtl lamp\n";
  for (std::size_t t = 0; t < 12; t += 3) {
    obj += "f";
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string index = std::to_string(testing::kStripTriangles[t + k] + 1);
      obj.append(" ").append(index).append("/").append(index);  // (not " " + …: GCC 12's false -Wrestrict)
    }
    obj += "\n";
  }
  write(dir / "strip.obj", obj);
  write(dir / "strip.mtl", "newmtl lamp\nKd 0 0 0\nKe 3 1.5 0.75\nmap_Ke emit.png\n");
  const std::string path = (dir / "strip.obj").string();
  Result<Scene> scene = readObj(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->surfaces.size(), 1u);
  const Rgb radiance{3, 1.5, 0.75};
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(scene->surfaces[0].emittedRadiance[c], radiance[c]);
  const Rgb mean = meanEmittedRadiance(*scene, scene->surfaces[0]);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], radiance[c] / 2, 0.005 * radiance[c]);
  testing::expectEmissionFollowsHalfWhiteTexture(*scene, radiance);

  // A missing map_Ke is a warning naming it, and Ke alone emits, as a missing map_Kd leaves Kd.
  fs::remove(dir / "emit.png");
  WarningCapture warnings;
  Result<Scene> missing = readObj(path);
  ASSERT_TRUE(missing.ok()) << missing.error().message;
  EXPECT_EQ(warnings.count(path + ": material 'lamp': map_Ke: " + (dir / "emit.png").string() +
                           ": no such texture file; the material emits its Ke alone"), 1);
  EXPECT_EQ(missing->materials[0].emissionTexture, nullptr);
  const Rgb uniform = meanEmittedRadiance(*missing, missing->surfaces[0]);
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(uniform[c], radiance[c]);
}

TEST(ObjTest, BadFilesAreErrorsNamingTheFile) {
  const fs::path dir = testing::scratchDirectory("obj", "bad");
  Result<Scene> missing = readObj((dir / "nowhere.obj").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, (dir / "nowhere.obj").string() + ": no such OBJ file");

  write(dir / "empty.obj", "# nothing\nv 0 0 0\n");
  Result<Scene> empty = readObj((dir / "empty.obj").string());
  ASSERT_FALSE(empty.ok());
  EXPECT_TRUE(testing::contains(empty.error().message, "empty.obj: no faces")) << empty.error().message;

  write(dir / "negative.obj", "mtllib negative.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
  write(dir / "negative.mtl", "newmtl m\nKd 0.5 -0.2 0.5\n");
  Result<Scene> negative = readObj((dir / "negative.obj").string());
  ASSERT_FALSE(negative.ok());
  EXPECT_TRUE(testing::contains(negative.error().message, "negative.obj: material 'm': Kd must not be negative")) << negative.error().message;

  WarningCapture captured;
  write(dir / "degenerate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\n");
  Result<Scene> degenerate = readObj((dir / "degenerate.obj").string());
  ASSERT_TRUE(degenerate.ok()) << degenerate.error().message;
  EXPECT_GE(captured.count("degenerate.obj: 2 degenerate faces dropped: 1 with a repeated vertex, 1 with no area"), 1);
  EXPECT_EQ(degenerate->surfaces.size(), 1u);

  write(dir / "allbad.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  Result<Scene> allBad = readObj((dir / "allbad.obj").string());
  ASSERT_FALSE(allBad.ok());
  EXPECT_TRUE(testing::contains(allBad.error().message, "every face is degenerate")) << allBad.error().message;
}

TEST(ObjTest, LoadSceneReadsObjWithAUnitAndRefusesUnitsElsewhere) {
  const fs::path dir = testing::scratchDirectory("obj", "load");
  write(dir / "room.obj", kRoom);
  write(dir / "room.mtl", "newmtl wall\nKd 0.7 0.6 0.5\nnewmtl lamp\nKd 0.5 0.5 0.5\nKe 5 4.5 4\n");
  Result<Scene> scene = loadScene((dir / "room.obj").string(), LoadOptions{.metresPerUnit = 0.001, .creaseAngleDegrees = 20});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->metresPerUnit, 0.001);
  Result<Scene> builtin = loadScene("cornell", LoadOptions{.metresPerUnit = 0.01, .creaseAngleDegrees = 20});
  ASSERT_FALSE(builtin.ok());
  EXPECT_TRUE(testing::contains(builtin.error().message, "a unit is for OBJ and PLY files")) << builtin.error().message;
}

}  // namespace
}  // namespace lambert
