#include "lambert/scene/building.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "lambert/load/obj.h"
#include "lambert/load/scene_file.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

Scene building(int rooms, double faceSize = 0, std::uint64_t seed = 1) {
  Result<Scene> scene = generateBuilding({rooms, faceSize, seed});
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  return scene.ok() ? *scene : Scene{};
}

std::size_t faceCount(const Scene& scene) {
  std::size_t n = 0;
  for (const Surface& s : scene.surfaces) n += surfaceFaces(s).size();
  return n;
}

bool contains(const std::string& name, const std::string& part) { return name.find(part) != std::string::npos; }

// Every floor faces up, every ceiling and lamp down, and every wall of a room faces the room's
// centre (a face turned the wrong way would show its black back to the room).
TEST(BuildingTest, EveryFaceFacesTheSpaceItBounds) {
  const Scene scene = building(20);  // two storeys, the second one partly filled
  int rooms = 0;
  for (const Surface& s : scene.surfaces) {
    const Vec3 n = surfaceNormal(s);
    if (contains(s.name, "floor")) {
      EXPECT_NEAR(n.y, 1, 1e-12) << s.name;
    }
    if (contains(s.name, "ceiling") || contains(s.name, "lamp")) {
      EXPECT_NEAR(n.y, -1, 1e-12) << s.name;
    }
    if (!contains(s.name, " room ") || contains(s.name, "reveal") || contains(s.name, "sill") || contains(s.name, "desk") ||
        contains(s.name, "cabinet") || contains(s.name, "floor") || contains(s.name, "ceiling") || contains(s.name, "lamp"))
      continue;
    // The room's floor names its centre.
    const std::size_t number = s.name.find(" room ") + 6;
    const std::string room = s.name.substr(0, s.name.find(' ', number));  // "storey 1 south room 3"
    for (const Surface& f : scene.surfaces)
      if (f.name == room + " floor") {
        Vec3 centre;
        for (const Vec3& v : f.vertices) centre += v / static_cast<double>(f.vertices.size());
        centre.y += 1.4;
        EXPECT_GT(dot(centre - s.vertices[0], n), 0) << s.name;
        ++rooms;
      }
  }
  EXPECT_GT(rooms, 20 * 4);  // every room's walls were checked
}

TEST(BuildingTest, SizeGrowsWithRoomsAndFaceSizeAndIsDeterministic) {
  const Scene one = building(1), sixteen = building(16), seventeen = building(17);
  EXPECT_GT(faceCount(sixteen), 12 * faceCount(one));
  EXPECT_GT(faceCount(seventeen), faceCount(sixteen));
  double lamps = 0;
  for (const Surface& s : sixteen.surfaces) lamps += s.emittedRadiance.r > 0;
  EXPECT_EQ(lamps, 16 + 8);  // one per room, one per corridor bay
  // Split into faces of at most 0.5 m: many more faces, the same area.
  const Scene fine = building(16, 0.5);
  EXPECT_GT(faceCount(fine), 10 * faceCount(sixteen));
  double area = 0, fineArea = 0;
  for (const Surface& s : sixteen.surfaces) area += surfaceArea(s);
  for (const Surface& s : fine.surfaces) fineArea += surfaceArea(s);
  EXPECT_NEAR(fineArea, area, 1e-9 * area);
  // The seed moves the furniture, and only the seed.
  const Scene again = building(16), other = building(16, 0, 2);
  ASSERT_EQ(again.surfaces.size(), sixteen.surfaces.size());
  bool same = true, moved = false;
  for (std::size_t i = 0; i < sixteen.surfaces.size(); ++i) {
    same &= again.surfaces[i].vertices == sixteen.surfaces[i].vertices;
    moved |= other.surfaces[i].vertices != sixteen.surfaces[i].vertices;
  }
  EXPECT_TRUE(same);
  EXPECT_TRUE(moved);
  EXPECT_FALSE(generateBuilding({0, 0, 1}).ok());
  EXPECT_FALSE(generateBuilding({4, 0.001, 1}).ok());
}

// Written as OBJ + MTL and read back: the same area, emission and materials.
TEST(BuildingTest, ObjRoundTrip) {
  const std::filesystem::path dir = testing::scratchDirectory("building", "obj");
  const Scene scene = building(3, 1.0);
  ASSERT_TRUE(writeObj((dir / "b.obj").string(), scene).ok());
  Result<Scene> back = loadScene((dir / "b.obj").string());
  ASSERT_TRUE(back.ok()) << back.error().message;
  double area = 0, backArea = 0, power = 0, backPower = 0;
  for (const Surface& s : scene.surfaces) area += surfaceArea(s), power += surfaceArea(s) * s.emittedRadiance.r;
  for (const Surface& s : back->surfaces) backArea += surfaceArea(s), backPower += surfaceArea(s) * s.emittedRadiance.r;
  EXPECT_NEAR(backArea, area, 1e-6 * area);
  EXPECT_NEAR(backPower, power, 1e-6 * power);
  EXPECT_EQ(faceCount(*back), faceCount(scene));
}

}  // namespace
}  // namespace lambert
