#include <gtest/gtest.h>

#include <map>
#include <set>

#include "lambert/mesh/mesh.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

TEST(MeshTest, EdgesRespectTheLimitAndAreaIsPreserved) {
  Scene scene = cornellBox();
  for (double maxEdge : {300.0, 100.0, 40.0}) {
    Mesh mesh = subdivideScene(scene, maxEdge);
    std::vector<double> area(scene.surfaces.size(), 0.0);
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      auto c = mesh.corners(i);
      ASSERT_EQ(c.size(), 3u);
      for (int k = 0; k < 3; ++k) EXPECT_LE(length(c[(k + 1) % 3] - c[k]), maxEdge * (1 + 1e-12));
      area[mesh.patches[i].surface] += mesh.patches[i].area;
      EXPECT_GT(dot(mesh.patches[i].normal, surfaceNormal(scene.surfaces[mesh.patches[i].surface])), 0.999);
    }
    for (std::size_t s = 0; s < scene.surfaces.size(); ++s)
      EXPECT_NEAR(area[s], surfaceArea(scene.surfaces[s]), 1e-9 * surfaceArea(scene.surfaces[s])) << scene.surfaces[s].name;
  }
}

// Every interior edge of a surface's patches is shared by exactly two patches, with opposite
// directions: no T-junctions, no flipped patches.
TEST(MeshTest, SubdivisionIsConforming) {
  Scene scene = cornellBox();
  Mesh mesh = subdivideScene(scene, 60);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directedEdges;
  for (const Patch& p : mesh.patches)
    for (int k = 0; k < 3; ++k) ++directedEdges[{p.vertices[k], p.vertices[(k + 1) % 3]}];
  for (const auto& [edge, count] : directedEdges) {
    EXPECT_EQ(count, 1);
    if (directedEdges.count({edge.second, edge.first})) continue;
    // A boundary edge: both ends lie on the boundary of the surface polygon.
    const Surface& surface = scene.surfaces[mesh.vertexSurface[edge.first]];
    auto onBoundary = [&](const Vec3& p) {
      for (std::size_t k = 0; k < surface.vertices.size(); ++k) {
        Vec3 a = surface.vertices[k], b = surface.vertices[(k + 1) % surface.vertices.size()];
        if (length(cross(b - a, p - a)) <= 1e-9 * lengthSquared(b - a)) return true;
      }
      return false;
    };
    EXPECT_TRUE(onBoundary(mesh.positions[edge.first]) && onBoundary(mesh.positions[edge.second]));
  }
}

TEST(MeshTest, VerticesAreNeverSharedAcrossSurfaces) {
  Mesh mesh = subdivideScene(cornellBox(), 80);
  for (const Patch& p : mesh.patches)
    for (std::uint32_t k = 0; k < p.numCorners; ++k) EXPECT_EQ(mesh.vertexSurface[p.vertices[k]], p.surface);
}

TEST(MeshTest, PatchCountTargetIsReachedClosely) {
  Scene scene = cornellBox();
  for (std::size_t target : {192u, 304u, 464u, 784u, 3000u}) {
    std::size_t count = subdivideScene(scene, edgeLengthForPatchCount(scene, target)).numPatches();
    EXPECT_GE(count, target);
    EXPECT_LE(count, target * 1.15) << "target " << target;
  }
}

}  // namespace
}  // namespace lambert
