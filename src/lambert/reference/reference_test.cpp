#include "lambert/reference/reference.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>

#include "lambert/formfactor/kernels.h"
#include "lambert/light/lights.h"
#include "lambert/scene/builtin.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

using testing::quietReferenceOptions;

// The geometry the path tracer traces against: each surface as its fan triangles.
Mesh coarse(const Scene& scene) { return subdivideScene(scene, 2 * sceneDiagonal(scene)); }

void expectNearRelative(const Rgb& value, const Rgb& expected, double tolerance, const char* what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(value[c], expected[c], tolerance * std::fabs(expected[c])) << what << " channel " << c;
}

// ---------------------------------------------------------------------------------------------
// Furnace: inside a closed cube whose every face emits L_e, with albedo ρ everywhere, the radiance
// is L_e (1 + ρ + ρ² + …) = L_e / (1 − ρ) at every point and in every direction.

constexpr Rgb kFurnaceEmission{1.0, 0.5, 0.25};

TEST(ReferenceFurnace, OutgoingRadianceIsEmissionOverOneMinusAlbedo) {
  Scene cube = testing::closedCube(1, kFurnaceEmission, Rgb::gray(0.5));
  ReferenceRenderer reference(cube, coarse(cube), quietReferenceOptions(8192, 16));
  const Rgb expected = kFurnaceEmission / (1 - 0.5);
  // Face z0 (normal +z): its centre, near an edge, near a corner, and next to one.
  const std::uint32_t face = 0;
  const Vec3 n = surfaceNormal(cube.surfaces[face]);
  ASSERT_NEAR(n.z, 1, 1e-12);
  std::uint64_t stream = 0;
  for (Vec3 x : {Vec3{0.5, 0.5, 0}, Vec3{0.5, 1e-3, 0}, Vec3{0.999, 0.3, 0}, Vec3{1e-3, 1e-3, 0},
                 Vec3{1e-4, 0.9999, 0}, Vec3{0.2, 0.7, 0}})
    expectNearRelative(reference.outgoingRadiance(x, n, face, stream++), expected, 0.01, "furnace point");
}

TEST(ReferenceFurnace, VertexRadianceIsUniform) {
  Scene cube = testing::closedCube(2, kFurnaceEmission, Rgb::gray(0.5));
  Mesh mesh = subdivideScene(cube, 1.0);  // vertices on every edge and at every corner
  ReferenceRenderer reference(cube, coarse(cube), quietReferenceOptions(8192, 16));
  std::vector<Rgb> radiance = reference.vertexRadiance(mesh);
  ASSERT_EQ(radiance.size(), mesh.numVertices());
  const Rgb expected = kFurnaceEmission / (1 - 0.5);
  for (std::size_t i = 0; i < radiance.size(); ++i)
    expectNearRelative(radiance[i], expected, 0.01, "furnace vertex");
}

TEST(ReferenceFurnace, ImageFromInsideTheBoxIsUniform) {
  Scene cube = testing::closedCube(1, kFurnaceEmission, Rgb::gray(0.5));
  cube.camera = {{0.5, 0.4, 0.3}, {0.8, 0.6, 1}, {0, 1, 0}, 100};  // sees edges and corners
  ReferenceRenderer reference(cube, coarse(cube), quietReferenceOptions(256, 512));
  Image image = reference.render(16, 12);
  ASSERT_EQ(image.pixels.size(), 16u * 12u);
  const Rgb expected = kFurnaceEmission / (1 - 0.5);
  Rgb mean;
  double squaredError = 0;
  for (const Rgb& p : image.pixels) {
    mean += p / static_cast<double>(image.pixels.size());
    squaredError += std::pow(p.r / expected.r - 1, 2) / static_cast<double>(image.pixels.size());
    expectNearRelative(p, expected, 0.08, "furnace pixel");  // noise: about 1.3% rms at 512 spp
  }
  EXPECT_LT(std::sqrt(squaredError), 0.025);
  expectNearRelative(mean, expected, 0.01, "furnace image mean");
}

// ---------------------------------------------------------------------------------------------
// Lights without area on an open floor: nothing comes back, so L_o = ρ/π E exactly.

TEST(ReferenceLights, FloorUnderPointDirectionalAndSpotLightsIsExact) {
  const double mpu = 0.001;  // millimetres: r² must be converted to metres
  const Rgb rho{0.6, 0.4, 0.2};
  const double s = 20000;
  Scene scene = testing::sceneOf({{"floor", {{-s, 0, -s}, {-s, 0, s}, {s, 0, s}, {s, 0, -s}}, 0, {}}}, rho);
  scene.metresPerUnit = mpu;
  Light point;
  point.kind = LightKind::Point;
  point.position = {300, 1500, -200};
  point.intensity = {2, 1, 0.5};
  Light sun;
  sun.kind = LightKind::Directional;
  sun.direction = normalize(Vec3{1, -2, 0.5});
  sun.irradiance = {0.3, 0.2, 0.1};
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = {-500, 2000, 400};
  spot.direction = {0, -1, 0};
  spot.intensity = {1, 3, 2};
  spot.coneAngleDegrees = 60;
  spot.falloffDegrees = 5;
  scene.lights = {point, sun, spot};
  ReferenceRenderer reference(scene, coarse(scene), quietReferenceOptions(64, 16));
  const Vec3 up{0, 1, 0};
  ASSERT_NEAR(dot(surfaceNormal(scene.surfaces[0]), up), 1, 1e-12);
  std::uint64_t stream = 0;
  for (Vec3 x : {Vec3{300, 0, -200}, Vec3{0, 0, 0}, Vec3{-700, 0, 900}, Vec3{1200, 0, 100}}) {
    Rgb e;
    for (const Light& l : {point, spot}) {  // I cosθ / r², r in metres; x is inside the spot's inner cone
      Vec3 d = l.position - x;
      double r = length(d);
      e += l.intensity * ((d.y / r) / (r * r * mpu * mpu));
    }
    e += sun.irradiance * (-sun.direction.y);
    Rgb expected = rho * e / kPi;
    expectNearRelative(reference.outgoingRadiance(x, up, 0, stream++), expected, 1e-9, "lit floor");
    // What a light meter on the floor reads: the irradiance itself, whatever the albedo.
    expectNearRelative(reference.irradianceAt(x, up, 0, stream++), e, 1e-9, "meter on the floor");
  }
}

TEST(ReferenceLights, ShadowedPointGetsNothingFromTheLight) {
  Scene scene = testing::sceneOf({{"floor", {{-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}}, 0, {}},
                                  // a blocker at y = 1, facing up (its black back faces the floor)
                                  {"blocker", {{-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}}, 0, {}}},
                                 Rgb::gray(0.5));
  scene.materials.push_back({"black", {0, 0, 0}});
  scene.surfaces[1].material = 1;
  Light point;
  point.position = {0, 3, 0};
  point.intensity = {1, 1, 1};
  scene.lights = {point};
  ReferenceRenderer reference(scene, coarse(scene), quietReferenceOptions(64, 16));
  EXPECT_EQ(reference.outgoingRadiance({0, 0, 0}, {0, 1, 0}, 0, 0), Rgb{});
  Rgb lit = reference.outgoingRadiance({4, 0, 4}, {0, 1, 0}, 0, 1);
  EXPECT_NEAR(lit.g, 0.5 / kPi * 3 / std::pow(41.0, 1.5), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// An area light over a floor: L_o = ρ/π · π L_e F(x → emitter) = ρ L_e F, with F from Lambert's
// contour integral. The emitter is black, so nothing is reflected back.

Scene emitterOverFloor() {
  Scene scene = testing::sceneOf(
      {{"floor", {{-20, 0, -20}, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}}, 0, {}},
       {"light", {{-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}}, 1, {10, 5, 2}}},
      Rgb::gray(0.3));
  scene.materials.push_back({"black emitter", {0, 0, 0}});
  return scene;
}

TEST(ReferenceAreaLight, FloorMatchesThePointToPolygonFormFactor) {
  Scene scene = emitterOverFloor();
  ASSERT_LT(surfaceNormal(scene.surfaces[1]).y, 0);  // faces the floor
  ReferenceRenderer reference(scene, coarse(scene), quietReferenceOptions(1024, 16));
  const Vec3 up{0, 1, 0};
  std::uint64_t stream = 0;
  for (Vec3 x : {Vec3{0, 0, 0}, Vec3{0.4, 0, 0.3}, Vec3{0.5, 0, -0.5}, Vec3{1.5, 0, -1}, Vec3{4, 0, 2}}) {
    double f = pointToPolygonFormFactor(x, up, scene.surfaces[1].vertices, surfaceNormal(scene.surfaces[1]));
    Rgb expected = Rgb::gray(0.3) * scene.surfaces[1].emittedRadiance * f;
    expectNearRelative(reference.outgoingRadiance(x, up, 0, stream++), expected, 0.01, "floor under light");
  }
}

// An emitting wall standing on the floor: next to their shared edge next-event estimation alone
// has unbounded variance (cosθ cosθ'/r²); the MIS estimate converges there too.
TEST(ReferenceAreaLight, FloorNextToAnEmittingWall) {
  Scene scene = testing::sceneOf(
      {{"floor", {{0, 0, -2}, {0, 0, 2}, {4, 0, 2}, {4, 0, -2}}, 0, {}},
       {"wall", {{0, 0, -1}, {0, 1, -1}, {0, 1, 1}, {0, 0, 1}}, 1, {3, 2, 1}}},
      Rgb::gray(0.5));
  scene.materials.push_back({"black emitter", {0, 0, 0}});
  ASSERT_GT(surfaceNormal(scene.surfaces[1]).x, 0);  // faces the floor side
  ReferenceRenderer reference(scene, coarse(scene), quietReferenceOptions(1024, 16));
  const Vec3 up{0, 1, 0};
  std::uint64_t stream = 0;
  for (Vec3 x : {Vec3{1e-3, 0, 0}, Vec3{1e-4, 0, 0.5}, Vec3{1e-3, 0, 0.999}, Vec3{0.3, 0, 0}}) {
    double f = pointToPolygonFormFactor(x, up, scene.surfaces[1].vertices, surfaceNormal(scene.surfaces[1]));
    Rgb expected = Rgb::gray(0.5) * scene.surfaces[1].emittedRadiance * f;
    expectNearRelative(reference.outgoingRadiance(x, up, 0, stream++), expected, 0.01, "floor by the wall");
  }
}

// ---------------------------------------------------------------------------------------------
// The Cornell box.

Mesh smallCornellMesh(const Scene& scene) { return subdivideScene(scene, edgeLengthForPatchCount(scene, 150)); }

TEST(ReferenceDeterminism, SameSeedSameResultsWhateverTheThreadCount) {
  Scene scene = cornellBox();
  Mesh mesh = smallCornellMesh(scene);
  ReferenceOptions options = quietReferenceOptions(16, 4);
  options.seed = 7;
  ReferenceRenderer a(scene, coarse(scene), options);
  ReferenceRenderer b(scene, coarse(scene), options);
  std::vector<Rgb> va = a.vertexRadiance(mesh);
  Image ia = a.render(24, 16);
  EXPECT_EQ(va, b.vertexRadiance(mesh));
  EXPECT_EQ(ia.pixels, b.render(24, 16).pixels);
  EXPECT_GT(a.raysCast(), 0u);

  tbb::task_arena single(1);
  std::vector<Rgb> v1;
  Image i1;
  single.execute([&] {
    v1 = b.vertexRadiance(mesh);
    i1 = b.render(24, 16);
  });
  EXPECT_EQ(va, v1);
  EXPECT_EQ(ia.pixels, i1.pixels);

  options.seed = 8;
  ReferenceRenderer c(scene, coarse(scene), options);
  EXPECT_NE(va, c.vertexRadiance(mesh));
}

TEST(ReferenceCornell, VertexRadianceIsFiniteAndTheRedWallIsRed) {
  Scene scene = cornellBox();
  ASSERT_EQ(scene.surfaces[3].name, "green wall");
  ASSERT_EQ(scene.surfaces[4].name, "red wall");
  Mesh mesh = smallCornellMesh(scene);
  ReferenceRenderer reference(scene, coarse(scene), quietReferenceOptions(64, 16));
  std::vector<Rgb> radiance = reference.vertexRadiance(mesh);
  ASSERT_EQ(radiance.size(), mesh.numVertices());
  Rgb red, green;
  for (std::size_t i = 0; i < radiance.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(radiance[i][c]));
      EXPECT_GE(radiance[i][c], 0);
    }
    if (mesh.vertexSurface[i] == 4) red += radiance[i];
    if (mesh.vertexSurface[i] == 3) green += radiance[i];
  }
  EXPECT_GT(red.r, 2 * red.g);
  EXPECT_GT(green.g, 2 * green.r);
  // The light's own vertices carry at least its emission.
  for (std::size_t i = 0; i < radiance.size(); ++i) {
    if (mesh.vertexSurface[i] == 5) {
      EXPECT_GE(radiance[i].r, 17.0);
    }
  }
}

}  // namespace
}  // namespace lambert
