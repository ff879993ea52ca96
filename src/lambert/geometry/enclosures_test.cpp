// The walls lit on both sides (geometry/enclosures.h) and the hierarchy that keeps their sides apart
// (hierarchical/element_hierarchy.h): a closed two-sided room lit inside, under a sky or not.
#include "lambert/geometry/enclosures.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/load/scene_file.h"
#include "lambert/mesh/mesh.h"

namespace lambert {
namespace {

// A 4 × 2.5 × 4 m room of two-sided walls, a one-sided emitting panel under its ceiling, and, with
// `sky`, a uniform environment outside; `closed` false leaves its east wall out.
Scene room(bool sky, bool closed) {
  std::string surfaces = R"({"name": "floor", "material": "wall", "vertices": [[0, 0, 0], [0, 0, 4], [4, 0, 4], [4, 0, 0]]},
    {"name": "ceiling", "material": "wall", "vertices": [[0, 2.5, 0], [4, 2.5, 0], [4, 2.5, 4], [0, 2.5, 4]]},
    {"name": "north", "material": "wall", "vertices": [[0, 0, 0], [4, 0, 0], [4, 2.5, 0], [0, 2.5, 0]]},
    {"name": "south", "material": "wall", "vertices": [[0, 0, 4], [0, 2.5, 4], [4, 2.5, 4], [4, 0, 4]]},
    {"name": "west", "material": "wall", "vertices": [[0, 0, 0], [0, 2.5, 0], [0, 2.5, 4], [0, 0, 4]]},
    {"name": "panel", "material": "lamp", "vertices": [[1.5, 2.3, 1.5], [2.5, 2.3, 1.5], [2.5, 2.3, 2.5], [1.5, 2.3, 2.5]]})";
  if (closed) surfaces += R"(, {"name": "east", "material": "wall", "vertices": [[4, 0, 0], [4, 0, 4], [4, 2.5, 4], [4, 2.5, 0]]})";
  Result<Scene> scene = parseSceneFile(R"({"materials": [{"name": "wall", "albedo": [0.7, 0.7, 0.7], "twoSided": true},
    {"name": "lamp", "albedo": [0, 0, 0], "emittedRadiance": [10, 10, 10]}], "surfaces": [)" + surfaces + "]" +
                                           (sky ? R"(, "lights": [{"type": "sky", "radiance": [0.05, 0.05, 0.05]}])" : "") + "}",
                                       "room.json");
  EXPECT_TRUE(scene) << scene.error().message;
  addTwins(*scene);  // as loadScene makes two-sided materials' backs
  return *scene;
}

// Under a sky, the closed room's walls are lit on both sides: their twins outside are the outer
// side, the inner faces and the panel not. Without the sky the twins are dark (no wall lit on
// both sides); with the east wall open, inside and outside are one set (nor then).
TEST(EnclosuresTest, TheOuterSideOfWallsLitOnBothSidesIsFound) {
  struct Case {
    bool sky, closed, both;
  };
  for (const Case& c : {Case{false, true, false}, Case{true, true, true}, Case{true, false, false}}) {
    SCOPED_TRACE("sky " + std::to_string(c.sky) + ", closed " + std::to_string(c.closed));
    const Scene scene = room(c.sky, c.closed);
    const Mesh mesh = subdivideScene(scene, 1.0);
    const auto caster = makeEmbreeRayCaster(mesh);
    const Enclosures found = findEnclosures(mesh, *caster, scene, 64);
    EXPECT_EQ(found.wallsLitOnBothSides, c.both);
    for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
      const std::string& name = scene.surfaces[mesh.patches[p].surface].name;
      const bool outer = name.find("(back)") != std::string::npos;
      EXPECT_EQ(found.outerSide[p], c.both && outer ? 1u : 0u) << name;
      EXPECT_EQ(found.enclosed[p], !c.sky && c.closed && outer ? 1 : 0) << name;
    }
  }
}

// Given groups, no cluster below the root holds faces of two: every node's faces, gathered from
// its leaves, are of one group.
TEST(EnclosuresTest, TheHierarchyKeepsGroupsApartBelowTheRoot) {
  const Scene scene = room(true, true);
  std::vector<std::vector<std::uint32_t>> groups;
  for (const Surface& surface : scene.surfaces)
    groups.push_back(std::vector<std::uint32_t>(surfaceFaces(surface).size(), surface.name.find("(back)") != std::string::npos ? 7u : 3u));
  for (bool grouped : {false, true}) {
    const ElementHierarchy hierarchy(scene, grouped ? groups : std::vector<std::vector<std::uint32_t>>{});
    int mixed = 0;
    for (std::uint32_t n = 1; n < hierarchy.nodes().size(); ++n) {
      if (!hierarchy.node(n).isCluster()) continue;
      std::set<std::uint32_t> seen;
      std::vector<std::uint32_t> stack{n};
      while (!stack.empty()) {
        const std::uint32_t at = stack.back();
        stack.pop_back();
        if (!hierarchy.node(at).isCluster()) seen.insert(groups[hierarchy.node(at).surface][hierarchy.node(at).face]);
        for (std::uint32_t child : hierarchy.children(at)) stack.push_back(child);
      }
      mixed += seen.size() > 1;
    }
    if (grouped)
      EXPECT_EQ(mixed, 0);
    else
      EXPECT_GT(mixed, 0) << "by place alone, clusters hold both sides of the walls";
  }
}

}  // namespace
}  // namespace lambert
