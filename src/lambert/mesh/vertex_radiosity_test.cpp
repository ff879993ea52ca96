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
  // The more open square wins however little: 0.25 and 0.75 put it in the right one too.
  const std::vector<VertexSite> partly = vertexSites(twoSquares(0.25, 0.75), nudge);
  EXPECT_NEAR(partly[1].point.x, 1 + nudge / std::sqrt(2.0), 1e-12);
  // Alike (both open, or both covered: a vertex well under the block), the first: into the left one.
  for (const double open : {1.0, 0.0}) {
    const std::vector<VertexSite> alike = vertexSites(twoSquares(open, open), nudge);
    EXPECT_NEAR(alike[1].point.x, 1 - nudge / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(alike[1].point.y, nudge / std::sqrt(2.0), 1e-12);
    EXPECT_EQ(vertexSitePatches(twoSquares(open, open))[1], 0u);
  }
}

// A ridge: two squares folded down 30° each side of the edge x = 0, as the faces round a convex
// curved surface's vertex meet. The site of a ridge vertex lies on one of the faces, never under
// both (toward the mean of their centroids it went inside the solid, behind every face, and a lit
// sphere's vertices were black), with the mean normal of the two.
TEST(VertexSitesTest, AVertexOnARidgeStaysOnAFace) {
  Mesh mesh;
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  mesh.positions = {{-c, -s, 0}, {0, 0, 0}, {0, 0, 1}, {-c, -s, 1}, {c, -s, 0}, {c, -s, 1}};
  mesh.vertexSurface.assign(mesh.positions.size(), 0);
  const std::vector<std::uint32_t> left{0, 3, 2, 1}, right{1, 2, 5, 4};
  mesh.patches.push_back(makePatch(mesh.positions, left, 0));
  mesh.patches.push_back(makePatch(mesh.positions, right, 0));
  ASSERT_GT(mesh.patches[0].normal.y, 0);
  ASSERT_GT(mesh.patches[1].normal.y, 0);
  const double nudge = 1e-3;
  const VertexSite site = vertexSites(mesh, nudge)[1];
  const double aboveLeft = dot(site.point - mesh.positions[1], mesh.patches[0].normal);
  const double aboveRight = dot(site.point - mesh.positions[1], mesh.patches[1].normal);
  EXPECT_NEAR(std::fmax(aboveLeft, aboveRight), 0, 1e-12) << "on one face's plane";
  EXPECT_GE(std::fmin(aboveLeft, aboveRight), -nudge) << "and within the nudge of the other";
  EXPECT_NEAR(length(site.point - mesh.positions[1]), nudge, 1e-12);
  EXPECT_NEAR(site.normal.y, 1, 1e-12);
}

}  // namespace
}  // namespace lambert
