#include "lambert/mesh/vertex_radiosity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace lambert {
namespace {

// Two unit squares side by side on the floor plane, sharing the edge x = 1; the left one is
// covered (under a block), the right one open. A vertex on the shared edge is evaluated on the
// open side, where the light it shows falls: moved toward the plain mean of the centroids it
// would sit on the edge itself (the mean is on the edge) or, with a covered square to one side
// only, under the block.
Mesh twoSquares(double leftOpen, double rightOpen) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.vertexSurface.assign(mesh.positions.size(), 0);
  const std::vector<std::uint32_t> left{0, 1, 4, 5}, right{1, 2, 3, 4};
  mesh.patches.push_back(makePatch(mesh.positions, left, 0));
  mesh.patches.push_back(makePatch(mesh.positions, right, 0));
  mesh.patches[0].openFraction = leftOpen;
  mesh.patches[1].openFraction = rightOpen;
  return mesh;
}

TEST(VertexSitesTest, AVertexOnAContactLineIsEvaluatedOnItsOpenSide) {
  const double nudge = 1e-3;
  const std::vector<VertexSite> sites = vertexSites(twoSquares(0, 1), nudge);
  // Vertex 1, (1, 0, 0): on the shared edge and the floor's rim; the open square's centroid is
  // (1.5, 0.5, 0), so the site moves along (0.5, 0.5)/|…| by the nudge, into the open square.
  EXPECT_NEAR(sites[1].point.x, 1 + nudge / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(sites[1].point.y, nudge / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(sites[1].normal.z, 1, 1e-12);
  // With both squares open the plain mean of the two centroids, (1, 0.5, 0): straight in.
  const std::vector<VertexSite> open = vertexSites(twoSquares(1, 1), nudge);
  EXPECT_NEAR(open[1].point.x, 1, 1e-12);
  EXPECT_NEAR(open[1].point.y, nudge, 1e-12);
  // Both covered (a vertex well under the block): the plain mean too.
  const std::vector<VertexSite> covered = vertexSites(twoSquares(0, 0), nudge);
  EXPECT_NEAR(covered[1].point.x, 1, 1e-12);
  EXPECT_NEAR(covered[1].point.y, nudge, 1e-12);
  // Partly open squares weigh by their open share: 0.25 and 0.75 put the mean at x = 1.25.
  const std::vector<VertexSite> partly = vertexSites(twoSquares(0.25, 0.75), nudge);
  const Vec3 toMean = normalize(Vec3{0.25, 0.5, 0});
  EXPECT_NEAR(partly[1].point.x, 1 + nudge * toMean.x, 1e-12);
  EXPECT_NEAR(partly[1].point.y, nudge * toMean.y, 1e-12);
}

}  // namespace
}  // namespace lambert
