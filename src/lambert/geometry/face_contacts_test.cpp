// Faces in contact against the geometry written down: a block standing on a tiled floor, turned
// 20° so that no edge of its bottom follows the tiles', touches the floor exactly under its
// footprint; a block hung 2 cm above it touches nothing; a face's own twin is not a contact.
#include "lambert/geometry/face_contacts.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/geometry/enclosures.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"

namespace lambert {
namespace {

// A floor of n × n square tiles over [0, size]² at y = 0, facing up, two-sided.
Surface tiledFloor(double size, int n) {
  Surface s{"floor", {}, 0, {}};
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.vertices.push_back({size * i / n, 0, size * j / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
      s.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});  // counter-clockwise from +y
    }
  return s;
}

// The six faces of a box of half-width h about (cx, ·, cz), turned by `angle` about y, from
// height y0 to y1, facing out.
std::vector<Surface> turnedBox(double cx, double cz, double h, double y0, double y1, double angle, int material) {
  const double c = std::cos(angle), s = std::sin(angle);
  const auto at = [&](double x, double y, double z) { return Vec3{cx + c * x - s * z, y, cz + s * x + c * z}; };
  const Vec3 b0 = at(-h, y0, -h), b1 = at(h, y0, -h), b2 = at(h, y0, h), b3 = at(-h, y0, h);
  const Vec3 t0 = at(-h, y1, -h), t1 = at(h, y1, -h), t2 = at(h, y1, h), t3 = at(-h, y1, h);
  std::vector<Surface> faces = {{"bottom", {b0, b1, b2, b3}, material, {}}, {"top", {t0, t3, t2, t1}, material, {}},
                                {"side", {b0, t0, t1, b1}, material, {}},   {"side", {b1, t1, t2, b2}, material, {}},
                                {"side", {b2, t2, t3, b3}, material, {}},   {"side", {b3, t3, t0, b0}, material, {}}};
  // Outward: each face's normal points away from the box's centre.
  const Vec3 centre = at(0, 0.5 * (y0 + y1), 0);
  for (Surface& f : faces)
    if (dot(surfaceNormal(f), f.vertices[0] - centre) < 0) std::reverse(f.vertices.begin(), f.vertices.end());
  return faces;
}

// Whether (x, z) lies in the turned square's footprint.
bool underBox(double x, double z, double cx, double cz, double h, double angle) {
  const double dx = x - cx, dz = z - cz, c = std::cos(angle), s = std::sin(angle);
  return std::fabs(c * dx + s * dz) < h && std::fabs(-s * dx + c * dz) < h;
}

Scene floorAndBox(double lift) {
  Scene scene;
  scene.materials = {{"grey", Rgb::gray(0.5), true}};
  scene.surfaces.push_back(tiledFloor(2, 6));
  for (Surface& f : turnedBox(1.05, 0.93, 0.4, lift, lift + 0.8, 0.35, 0)) scene.surfaces.push_back(std::move(f));
  addTwins(scene);
  return scene;
}

TEST(FaceContactsTest, TheFloorTouchesABlockExactlyUnderItsFootprint) {
  const Scene scene = floorAndBox(0);
  const Mesh mesh = subdivideScene(scene, 10);
  const FaceContacts contacts(mesh, scene, 1e-6);
  Pcg32 rng(3, 5);
  int under = 0, outside = 0;
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    if (scene.surfaces[patch.surface].name != "floor") continue;  // the floor's top, not its twin
    for (int k = 0; k < 40; ++k) {
      const Vec3 x = sampleConvexPolygon(mesh.corners(p), rng.nextDouble(), rng.nextDouble());
      const bool expected = underBox(x.x, x.z, 1.05, 0.93, 0.4, 0.35);
      // A point within a millimetre of the footprint's edge could round either way.
      bool nearEdge = false;
      for (double dx : {-1e-3, 1e-3})
        for (double dz : {-1e-3, 1e-3}) nearEdge |= underBox(x.x + dx, x.z + dz, 1.05, 0.93, 0.4, 0.35) != expected;
      if (nearEdge) continue;
      EXPECT_EQ(contacts.inContact(x, p), expected) << "at (" << x.x << ", " << x.z << ")";
      (expected ? under : outside) += 1;
    }
  }
  EXPECT_GT(under, 50);
  EXPECT_GT(outside, 500);
  // The box's bottom touches the floor where it stands on it; its top touches nothing; and the
  // floor's twin, facing down, is not inside the box's inner bottom, a twin, facing up under it.
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const std::string& name = scene.surfaces[mesh.patches[p].surface].name;
    if (name == "bottom") {
      EXPECT_TRUE(contacts.inContact(mesh.patches[p].centroid, p));
    } else if (name == "top" || name == "floor (back)") {
      EXPECT_FALSE(contacts.inContact(mesh.patches[p].centroid, p)) << name;
    }
  }
}

TEST(FaceContactsTest, ABlockHungAboveTheFloorTouchesNothing) {
  const Scene scene = floorAndBox(0.02);
  const Mesh mesh = subdivideScene(scene, 10);
  const FaceContacts contacts(mesh, scene, 1e-6);
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) EXPECT_FALSE(contacts.inContact(mesh.patches[p].centroid, p)) << p;
}

// The inside of a two-sided block standing on a two-sided floor is an enclosure: from inside it,
// a ray down meets the floor where it lies on the block's bottom, and joined there the inside
// was lit with the floor (a lamp over it).
TEST(FaceContactsTest, TheInsideOfABlockStandingOnTheFloorIsEnclosed) {
  Scene scene = floorAndBox(0);
  Light lamp;
  lamp.kind = LightKind::Point;
  lamp.position = {0.3, 2, 0.3};
  lamp.intensity = Rgb::gray(10);
  scene.lights.push_back(lamp);
  const Mesh mesh = subdivideScene(scene, 0.25);
  const auto caster = makeEmbreeRayCaster(mesh);
  const std::vector<std::uint8_t> enclosed = findEnclosures(mesh, *caster, scene, 64).enclosed;
  int inside = 0;
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const std::string& name = scene.surfaces[mesh.patches[p].surface].name;
    const bool innerShell = name.find("(back)") != std::string::npos && name != "floor (back)";
    if (innerShell) {
      ++inside;
      EXPECT_EQ(enclosed[p], 1) << name << " patch " << p;
    } else if (name == "top" || name == "side" || (name == "floor" && !underBox(mesh.patches[p].centroid.x, mesh.patches[p].centroid.z, 1.05, 0.93, 0.45, 0.35))) {
      EXPECT_EQ(enclosed[p], 0) << name << " patch " << p;  // (a floor patch under the box is dark too)
    }
  }
  EXPECT_GT(inside, 20);
}

}  // namespace
}  // namespace lambert
