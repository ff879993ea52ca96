#include <gtest/gtest.h>

#include <cmath>

#include "lambert/core/rng.h"
#include "lambert/flat/quadtree.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

AdaptiveMesh build(const Scene& scene, double baseEdge, int maxLevel) {
  Result<AdaptiveMesh> mesh = AdaptiveMesh::build(scene, {baseEdge, maxLevel});
  EXPECT_TRUE(mesh.ok()) << mesh.error().message;
  return std::move(*mesh);
}

TEST(QuadtreeTest, BaseGridCoversEverySurface) {
  Scene scene = cornellBox();
  AdaptiveMesh mesh = build(scene, 100, 3);
  Mesh active = mesh.activeMesh();
  std::vector<double> area(scene.surfaces.size(), 0.0);
  for (const Patch& p : active.patches) {
    EXPECT_EQ(p.numCorners, 4u);
    area[p.surface] += p.area;
  }
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s)
    EXPECT_NEAR(area[s], surfaceArea(scene.surfaces[s]), 1e-3 * surfaceArea(scene.surfaces[s])) << scene.surfaces[s].name;
  // The floor is 552.8 × 559.2: six by six cells of at most 100.
  int floorCells = 0;
  for (const Patch& p : active.patches) floorCells += p.surface == 0;
  EXPECT_EQ(floorCells, 36);
}

TEST(QuadtreeTest, NonQuadSurfacesAreAnError) {
  Scene scene = testing::sceneOf({{"triangle", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 0, {}}});
  Result<AdaptiveMesh> mesh = AdaptiveMesh::build(scene, {0.5, 2});
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("'triangle'"), std::string::npos) << mesh.error().message;
}

TEST(QuadtreeTest, RefineAndCoarsenKeepIdsAndArea) {
  Scene scene = testing::parallelSquares();
  AdaptiveMesh mesh = build(scene, 0.5, 3);
  ASSERT_EQ(mesh.activeNodes().size(), 8u);
  const std::uint32_t target = mesh.activeNodes()[0];
  ASSERT_TRUE(mesh.refine(target));
  EXPECT_EQ(mesh.activeNodes().size(), 11u);
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.node(target).firstChild);
  ASSERT_TRUE(mesh.refine(first));
  double area = 0;
  for (const Patch& p : mesh.activeMesh().patches) area += p.area;
  EXPECT_NEAR(area, 2.0, 1e-12);
  const std::size_t nodes = mesh.numNodes();
  mesh.coarsen(first);
  mesh.coarsen(target);
  EXPECT_EQ(mesh.activeNodes().size(), 8u);
  // Refining again reuses the nodes made before: same ids, no new nodes.
  ASSERT_TRUE(mesh.refine(target));
  EXPECT_EQ(mesh.node(target).firstChild, static_cast<std::int32_t>(first));
  EXPECT_EQ(mesh.numNodes(), nodes);
  // The deepest level does not split.
  std::uint32_t leaf = first;
  while (mesh.node(leaf).level < 3) {
    ASSERT_TRUE(mesh.refine(leaf));
    leaf = static_cast<std::uint32_t>(mesh.node(leaf).firstChild);
  }
  EXPECT_FALSE(mesh.refine(leaf));
}

// Rendering the finest level from the active level: every active node's finest vertices carry the
// bilinear interpolation of its corners, and where nodes of different levels meet, both sides
// agree at every shared vertex (no cracks, no steps at T-junctions).
TEST(QuadtreeTest, FineVerticesAreContinuousAcrossLevels) {
  Scene scene = testing::parallelSquares();
  AdaptiveMesh mesh = build(scene, 0.5, 3);
  Pcg32 rng(5, 5);
  for (int round = 0; round < 12; ++round) {
    auto active = mesh.activeNodes();
    mesh.refine(active[rng.nextBelow(static_cast<std::uint32_t>(active.size()))]);
  }
  std::vector<Rgb> radiosity;
  for (std::size_t k = 0; k < mesh.activeNodes().size(); ++k)
    radiosity.push_back({rng.nextDouble(), rng.nextDouble(), rng.nextDouble()});
  std::vector<Rgb> fine = mesh.fineVertexRadiosity(radiosity);
  std::vector<std::array<Rgb, 4>> corners = mesh.cornerRadiosity(radiosity);
  const Mesh& fineMesh = mesh.fineMesh();

  int levels[4] = {0, 0, 0, 0};
  for (std::size_t k = 0; k < mesh.activeNodes().size(); ++k) {
    const std::uint32_t id = mesh.activeNodes()[k];
    ++levels[mesh.node(id).level];
    PatchCorners quad = mesh.nodeMesh().corners(id);
    // Every fine vertex inside or on this node must equal its bilinear interpolation.
    for (std::size_t v = 0; v < fineMesh.numVertices(); ++v) {
      if (fineMesh.vertexSurface[v] != mesh.node(id).surface) continue;
      const Vec3& p = fineMesh.positions[v];
      // Parameters (u, v) of p in the node's parallelogram-shaped cell.
      Vec3 e1 = quad[1] - quad[0], e2 = quad[3] - quad[0], d = p - quad[0];
      double u = dot(d, e1) / dot(e1, e1), w = dot(d, e2) / dot(e2, e2);
      if (u < -1e-9 || u > 1 + 1e-9 || w < -1e-9 || w > 1 + 1e-9) continue;
      const auto& c = corners[k];
      Rgb expected = c[0] * ((1 - u) * (1 - w)) + c[1] * (u * (1 - w)) + c[2] * (u * w) + c[3] * ((1 - u) * w);
      for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(fine[v][ch], expected[ch], 1e-9) << "node " << id << " vertex " << v;
    }
  }
  EXPECT_GT(levels[0], 0);
  EXPECT_GT(levels[1] + levels[2] + levels[3], 0);
}

TEST(QuadtreeTest, UniformRadiosityStaysUniform) {
  Scene scene = testing::perpendicularSquares();
  AdaptiveMesh mesh = build(scene, 0.5, 2);
  mesh.refine(mesh.activeNodes()[1]);
  std::vector<Rgb> radiosity(mesh.activeNodes().size(), Rgb{1, 2, 3});
  for (const Rgb& v : mesh.fineVertexRadiosity(radiosity)) {
    EXPECT_NEAR(v.r, 1, 1e-12);
    EXPECT_NEAR(v.b, 3, 1e-12);
  }
}

}  // namespace
}  // namespace lambert
