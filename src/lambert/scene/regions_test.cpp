#include "lambert/scene/regions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "lambert/mesh/mesh.h"

namespace lambert {
namespace {

Scene withMaterials(int count) {
  Scene scene;
  for (int m = 0; m < count; ++m) scene.materials.push_back({std::to_string(m), Rgb::gray(0.5)});
  return scene;
}

// The 12 triangles of a unit cube, faces pointing out, all of material 0.
PolygonMesh cube() {
  PolygonMesh mesh;
  mesh.name = "cube";
  for (int k = 0; k < 8; ++k) mesh.positions.push_back({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.faces.push_back({{q[0], q[1], q[2]}, 0});
    mesh.faces.push_back({{q[0], q[2], q[3]}, 0});
  }
  return mesh;
}

// No vertex of a surface's mesh lies inside an edge of one of its patches: the mesh is conforming.
void expectConforming(const Mesh& mesh) {
  for (const Patch& patch : mesh.patches)
    for (std::uint32_t k = 0; k < patch.numCorners; ++k) {
      const Vec3 a = mesh.positions[patch.vertices[k]], b = mesh.positions[patch.vertices[(k + 1) % patch.numCorners]];
      for (std::size_t v = 0; v < mesh.numVertices(); ++v) {
        if (mesh.vertexSurface[v] != patch.surface) continue;
        const Vec3 p = mesh.positions[v];
        const double t = dot(p - a, b - a) / lengthSquared(b - a);
        if (t <= 1e-9 || t >= 1 - 1e-9) continue;
        ASSERT_GT(length(a + (b - a) * t - p), 1e-9 * length(b - a)) << "T-junction at vertex " << v;
      }
    }
}

TEST(RegionsTest, TwoTrianglesOfASquareAreOneSmoothRegion) {
  Scene scene = withMaterials(1);
  PolygonMesh square{"square", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{{0, 1, 2}, 0}, {{0, 2, 3}, 0}}};
  EXPECT_EQ(addSmoothRegions(scene, square, {Rgb{}}).total(), 0u);
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].name, "square");
  EXPECT_EQ(scene.surfaces[0].vertices.size(), 4u);  // the diagonal's ends are shared
  EXPECT_EQ(scene.surfaces[0].faces.size(), 2u);
  EXPECT_NEAR(surfaceArea(scene.surfaces[0]), 1, 1e-15);

  // Meshed finely, the diagonal's vertices are shared by the triangles on both sides: no seam.
  Mesh mesh = subdivideScene(scene, 0.1);
  std::map<std::tuple<double, double, double>, int> atPosition;
  for (const Vec3& p : mesh.positions) ++atPosition[{p.x, p.y, p.z}];
  for (const auto& [position, count] : atPosition) EXPECT_EQ(count, 1) << "a vertex duplicated along a seam";
  expectConforming(mesh);
  double area = 0;
  for (const Patch& patch : mesh.patches) area += patch.area;
  EXPECT_NEAR(area, 1, 1e-12);
}

TEST(RegionsTest, CreasesAndMaterialsSeparateRegions) {
  Scene scene = withMaterials(2);
  EXPECT_EQ(addSmoothRegions(scene, cube(), {Rgb{}, Rgb{}}).total(), 0u);
  ASSERT_EQ(scene.surfaces.size(), 6u);  // 90° edges are creases at the default 20°
  for (const Surface& s : scene.surfaces) {
    EXPECT_EQ(s.vertices.size(), 4u);
    EXPECT_NEAR(surfaceArea(s), 1, 1e-12);
  }
  EXPECT_EQ(scene.surfaces[0].name, "cube 1");
  Scene smooth = withMaterials(1);
  addSmoothRegions(smooth, cube(), {Rgb{}}, RegionOptions{.creaseAngleDegrees = 100});
  ASSERT_EQ(smooth.surfaces.size(), 1u);  // everything within 100°: one region, 8 shared corners
  EXPECT_EQ(smooth.surfaces[0].vertices.size(), 8u);
  EXPECT_EQ(smooth.surfaces[0].name, "cube");

  // Two coplanar triangles of different materials do not merge; emission follows the material.
  Scene two = withMaterials(2);
  PolygonMesh square{"square", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{{0, 1, 2}, 0}, {{0, 2, 3}, 1}}};
  addSmoothRegions(two, square, {Rgb{}, Rgb{1, 2, 3}});
  ASSERT_EQ(two.surfaces.size(), 2u);
  EXPECT_EQ(two.surfaces[1].material, 1);
  EXPECT_EQ(two.surfaces[1].emittedRadiance, (Rgb{1, 2, 3}));

  // Across a crease the mesh stays crack-free: both sides split the shared edge at the same points.
  Mesh mesh = subdivideScene(scene, 0.2);
  expectConforming(mesh);
  std::map<std::tuple<double, double, double>, int> onEdge;
  for (std::size_t v = 0; v < mesh.numVertices(); ++v) {
    const Vec3 p = mesh.positions[v];
    if (p.x == 0 && p.y == 0 && p.z > 0 && p.z < 1) ++onEdge[{p.x, p.y, p.z}];  // inside the edge x = y = 0
  }
  EXPECT_FALSE(onEdge.empty());
  for (const auto& [position, count] : onEdge) EXPECT_EQ(count, 2) << "each side has its own vertex at the same point";
}

// A face given twice (from another corner) would put two patches in one place and count its light
// twice: the second is dropped and counted. Its reverse is the back of a two-sided sheet: kept.
TEST(RegionsTest, DuplicateFacesAreDroppedButReversedOnesKept) {
  Scene scene = withMaterials(1);
  PolygonMesh mesh{"sheet", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                   {{{0, 1, 2, 3}, 0}, {{2, 3, 0, 1}, 0}, {{3, 2, 1, 0}, 0}}};
  DroppedFaces dropped = addSmoothRegions(scene, mesh, {Rgb{}});
  EXPECT_EQ(dropped.duplicate, 1u);
  EXPECT_EQ(dropped.total(), 1u);
  EXPECT_EQ(dropped.describe(), "1 degenerate face dropped: 1 duplicating an earlier face");
  std::size_t faces = 0;
  for (const Surface& s : scene.surfaces) faces += s.faces.size();
  EXPECT_EQ(faces, 2u);  // the front and the reversed back
}

TEST(RegionsTest, NonConvexFacesAreTriangulatedAndDegenerateOnesCounted) {
  Scene scene = withMaterials(1);
  // An L of area 3, counter-clockwise, as one face; then five degenerate faces.
  PolygonMesh mesh{"L", {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {NAN, 0, 0}, {3, 3, 0}, {4, 4, 0}},
                   {{{0, 1, 2, 3, 4, 5}, 0},
                    {{0, 1, 6}, 0},
                    {{0, 1, 1}, 0},
                    {{0, 7, 8}, 0},
                    {{0, 1, 42}, 0},
                    {{0, 1}, 0}}};
  DroppedFaces dropped = addSmoothRegions(scene, mesh, {Rgb{}});
  EXPECT_EQ(dropped.nonFinite, 1u);
  EXPECT_EQ(dropped.repeatedVertex, 1u);
  EXPECT_EQ(dropped.noArea, 2u);
  EXPECT_EQ(dropped.outOfRange, 1u);
  EXPECT_EQ(dropped.describe(),
            "5 degenerate faces dropped: 1 with a NaN or infinite coordinate, 1 with a repeated vertex, 2 with no area, "
            "1 with a vertex index out of range");
  ASSERT_EQ(scene.surfaces.size(), 1u);
  const Surface& l = scene.surfaces[0];
  EXPECT_EQ(l.faces.size(), 4u);  // a hexagon: 4 triangles
  EXPECT_NEAR(surfaceArea(l), 3, 1e-12);
  for (const auto& face : l.faces) EXPECT_GT(polygonNormal(facePositions(l, face)).z, 0.999);  // all kept counter-clockwise
  expectConforming(subdivideScene(scene, 0.3));
}

TEST(RegionsTest, EarClippingOfAConvexPolygonIsAFan) {
  std::vector<Vec3> pentagon;
  for (int k = 0; k < 5; ++k) pentagon.push_back({std::cos(2 * kPi * k / 5), std::sin(2 * kPi * k / 5), 0});
  auto triangles = triangulatePolygon(pentagon, {0, 0, 1});
  ASSERT_EQ(triangles.size(), 3u);
  double area = 0;
  for (const auto& t : triangles) area += 0.5 * length(cross(pentagon[t[1]] - pentagon[t[0]], pentagon[t[2]] - pentagon[t[0]]));
  EXPECT_NEAR(area, 2.5 * std::sin(2 * kPi / 5), 1e-12);
}

}  // namespace
}  // namespace lambert
