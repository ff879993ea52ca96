#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "lambert/flat/form_factors.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/light/emission.h"
#include "lambert/solve/problem.h"
#include "lambert/solve/solver.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

constexpr double kDegrees = kPi / 180;

Scene floorScene(double metresPerUnit = 1) {
  const double s = 1 / metresPerUnit;  // a 2 m × 2 m floor whatever the unit
  Scene scene = testing::sceneOf({{"floor", {{-s, 0, -s}, {-s, 0, s}, {s, 0, s}, {s, 0, -s}}, 0, {}}});
  scene.metresPerUnit = metresPerUnit;
  return scene;
}

Light pointLight(Vec3 position, Rgb intensity) {
  Light light;
  light.kind = LightKind::Point;
  light.position = position;
  light.intensity = intensity;
  return light;
}

// E = I cosθ / r² over a plane, at points near and far from the foot of the light, in metres and
// in millimetres.
TEST(LightTest, PointLightFollowsTheInverseSquareCosineLaw) {
  for (double metresPerUnit : {1.0, 0.001}) {
    Scene scene = floorScene(metresPerUnit);
    Mesh mesh = subdivideScene(scene, 0.5 / metresPerUnit);
    auto caster = makeEmbreeRayCaster(mesh);
    const double h = 0.7;  // metres
    Light light = pointLight(Vec3{0.1, h, -0.2} / metresPerUnit, {2, 1, 0.5});
    for (Vec3 metres : {Vec3{0.1, 0, -0.2}, Vec3{0.5, 0, 0.3}, Vec3{-0.9, 0, 0.9}, Vec3{0.95, 0, -0.95}}) {
      Vec3 x = metres / metresPerUnit;
      double r2 = lengthSquared(metres - Vec3{0.1, h, -0.2});
      double expected = h / std::sqrt(r2) / r2;  // cosθ / r²
      Rgb e = irradiance(light, x, {0, 1, 0}, *caster, rayEpsilon(mesh), metresPerUnit);
      EXPECT_NEAR(e.r, 2 * expected, 1e-4 * 2 * expected) << metres.x << " " << metres.z;
      EXPECT_NEAR(e.b, 0.5 * expected, 1e-4 * 0.5 * expected);
    }
  }
}

TEST(LightTest, SpotRespectsItsConeAndFalloff) {
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = {0, 1, 0};
  spot.direction = {0, -1, 0};
  spot.intensity = {1, 1, 1};
  spot.coneAngleDegrees = 30;
  spot.falloffDegrees = 10;
  auto at = [&](double degrees) {
    Vec3 x{std::tan(degrees * kDegrees), 0, 0};
    double cosine = 1 / std::sqrt(1 + x.x * x.x);
    double unfaded = cosine * cosine * cosine;  // I cosθ / r² with h = 1
    return unshadowedIrradiance(spot, x, {0, 1, 0}, 1).r / unfaded;
  };
  EXPECT_NEAR(at(0), 1, 1e-12);
  EXPECT_NEAR(at(19.9), 1, 1e-12);  // inside the inner cone (30° − 10°)
  EXPECT_EQ(at(30.1), 0);           // outside the cone
  EXPECT_EQ(at(60), 0);
  double mid = at(25);              // halfway through the band in angle
  double t = (std::cos(25 * kDegrees) - std::cos(30 * kDegrees)) / (std::cos(20 * kDegrees) - std::cos(30 * kDegrees));
  EXPECT_NEAR(mid, t * t * (3 - 2 * t), 1e-12);
  EXPECT_GT(at(22), at(25));
  EXPECT_GT(at(25), at(28));
}

// A 0.2 m square blocker halfway between a point light and the floor casts a 0.4 m shadow.
TEST(LightTest, BlockerCastsAShadow) {
  Scene scene = floorScene();
  scene.surfaces.push_back({"blocker", {{-0.1, 0.5, -0.1}, {0.1, 0.5, -0.1}, {0.1, 0.5, 0.1}, {-0.1, 0.5, 0.1}}, 0, {}});
  EXPECT_LT(surfaceNormal(scene.surfaces.back()).y, 0);  // faces the floor
  Mesh mesh = subdivideScene(scene, 0.5);
  auto caster = makeEmbreeRayCaster(mesh);
  Light light = pointLight({0, 1, 0}, {1, 1, 1});
  const double eps = rayEpsilon(mesh);
  for (double x : {0.0, 0.1, 0.19, -0.19}) EXPECT_EQ(irradiance(light, {x, 0, 0.05}, {0, 1, 0}, *caster, eps, 1).r, 0) << x;
  for (double x : {0.21, 0.5, -0.3}) {
    Vec3 p{x, 0, 0.05};
    EXPECT_EQ(irradiance(light, p, {0, 1, 0}, *caster, eps, 1), unshadowedIrradiance(light, p, {0, 1, 0}, 1)) << x;
  }
}

TEST(LightTest, DirectionalLightGivesCosineWeightedIrradianceAndShadows) {
  Scene scene = floorScene();
  scene.surfaces.push_back({"blocker", {{-0.1, 0.5, -0.1}, {0.1, 0.5, -0.1}, {0.1, 0.5, 0.1}, {-0.1, 0.5, 0.1}}, 0, {}});
  Mesh mesh = subdivideScene(scene, 0.5);
  auto caster = makeEmbreeRayCaster(mesh);
  Light sun;
  sun.kind = LightKind::Directional;
  sun.direction = normalize(Vec3{1, -1, 0});  // 45° from the zenith, travelling toward +x
  sun.irradiance = {100, 100, 100};
  const double eps = rayEpsilon(mesh);
  EXPECT_NEAR(irradiance(sun, {0.8, 0, 0.5}, {0, 1, 0}, *caster, eps, 1).g, 100 / std::sqrt(2.0), 1e-9);
  EXPECT_EQ(irradiance(sun, {0.5, 0, 0}, {0, 1, 0}, *caster, eps, 1).g, 0);  // the blocker's shadow, shifted 0.5 m
  EXPECT_EQ(unshadowedIrradiance(sun, {0, 0, 0}, {0, -1, 0}, 1).g, 0);      // facing away
}

// Σ E_i A_i over a floor is the power reaching it: compare with a fine numeric integral of the
// closed form, for a point light and for a tilted spot (whose cone culling must not drop patches
// that its beam reaches).
TEST(LightTest, PatchIrradianceIntegratesToThePowerReceived) {
  Scene scene = floorScene();
  Mesh mesh = subdivideScene(scene, 0.3);
  auto caster = makeEmbreeRayCaster(mesh);
  Light point = pointLight({0, 0.3, 0}, {1, 1, 1});
  Light spot = point;
  spot.kind = LightKind::Spot;
  spot.position = {0.2, 0.5, -0.1};
  spot.direction = normalize(Vec3{-0.4, -1, 0.3});
  spot.coneAngleDegrees = 20;
  spot.falloffDegrees = 5;
  for (const Light& light : {point, spot}) {
    std::vector<Rgb> e = patchIrradiance(mesh, *caster, light, 1, {64, 1});
    double power = 0;
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) power += e[i].r * mesh.patches[i].area;
    double exact = 0;
    const int n = 1500;
    const double cell = 2.0 / n;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        Vec3 x{-1 + (a + 0.5) * cell, 0, -1 + (b + 0.5) * cell};
        exact += unshadowedIrradiance(light, x, {0, 1, 0}, 1).r * cell * cell;
      }
    EXPECT_GT(exact, 0.1);
    EXPECT_NEAR(power, exact, 0.01 * exact) << (light.kind == LightKind::Spot ? "spot" : "point");
  }
}

// patchIrradiance skips the patches whose bounding sphere is outside a spot's cone, without their
// shadow rays. Against the same points evaluated one by one with no culling, patch by patch, for
// narrow and wide cones (beyond 90° the cone is tested the other way round) aimed so that their
// edges cross the floor's patches at many angles: no patch the light reaches may be skipped.
TEST(LightTest, SpotCullingSkipsOnlyPatchesTheConeMisses) {
  Scene scene = floorScene();
  Mesh mesh = subdivideScene(scene, 0.1);
  auto caster = makeEmbreeRayCaster(mesh);
  const double epsilon = rayEpsilon(mesh);
  const DirectLightOptions options{4, 7};
  int lit = 0, dark = 0;
  for (double cone : {10.0, 35.0, 80.0, 100.0, 150.0})
    for (const Vec3& direction : {Vec3{0, -1, 0}, Vec3{0.8, -0.3, 0.1}, Vec3{-0.2, 0.5, 0.6}}) {
      Light spot = pointLight({0.3, 0.4, -0.2}, {1, 1, 1});
      spot.kind = LightKind::Spot;
      spot.direction = normalize(direction);
      spot.coneAngleDegrees = cone;
      spot.falloffDegrees = 0.3 * cone;
      const std::vector<Rgb> e = patchIrradiance(mesh, *caster, spot, 1, options);
      for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
        Pcg32 rng(options.seed, i);
        const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
        Rgb sum;
        for (int k = 0; k < options.samplesPerPatch; ++k) {
          auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
          sum += irradiance(spot, sampleConvexPolygon(mesh.corners(i), u, v), mesh.patches[i].normal, *caster, epsilon, 1);
        }
        const Rgb expected = sum / options.samplesPerPatch;
        EXPECT_EQ(e[i].r, expected.r) << "cone " << cone << "°, patch " << i;
        (expected.r > 0 ? lit : dark) += 1;
      }
    }
  EXPECT_GT(lit, 500);  // the cones reach many patches and miss many
  EXPECT_GT(dark, 500);
}

TEST(LightTest, AnimationTurnsTheDirection) {
  Light spot;
  spot.kind = LightKind::Spot;
  spot.direction = {1, 0, 0};
  spot.angularVelocity = {0, kPi / 2, 0};  // a quarter turn a second about +y
  Light later = lightAtTime(spot, 1);
  EXPECT_NEAR(later.direction.x, 0, 1e-12);
  EXPECT_NEAR(later.direction.z, -1, 1e-12);  // right-handed: +x turns toward −z about +y
  EXPECT_EQ(lightAtTime(spot, 0).direction, spot.direction);
  EXPECT_NEAR(length(lightAtTime(spot, 0.37).direction), 1, 1e-12);
}

// A tiny emissive geodesic sphere of radiance L and area A is, seen from afar, an isotropic point
// light of intensity I = L·A/4 (Cauchy: a convex body's mean projected area is A/4). Injecting a
// point light and solving must give the room the same radiosity as solving with the sphere.
Scene roomWithTinySphere(double radius, Rgb radiance) {
  Scene scene = testing::closedCube(1, {}, Rgb::gray(0.5));
  scene.materials.push_back({"black", {0, 0, 0}});
  const int black = 1;
  // Icosahedron, each face split in four twice and pushed onto the sphere.
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> faces{{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (Vec3& p : v) p = normalize(p);
  for (int level = 0; level < 2; ++level) {
    std::vector<std::array<int, 3>> finer;
    std::map<std::pair<int, int>, int> midpoints;
    auto mid = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto [it, inserted] = midpoints.try_emplace(key, static_cast<int>(v.size()));
      if (inserted) v.push_back(normalize(v[a] + v[b]));
      return it->second;
    };
    for (auto [a, b, c] : faces) {
      int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    faces = finer;
  }
  const Vec3 centre{0.5, 0.5, 0.5};
  for (auto [a, b, c] : faces) {
    Surface face{"emitter", {centre + v[a] * radius, centre + v[b] * radius, centre + v[c] * radius}, black, radiance};
    if (dot(surfaceNormal(face), face.vertices[0] - centre) < 0) std::swap(face.vertices[1], face.vertices[2]);
    scene.surfaces.push_back(face);
  }
  return scene;
}

TEST(LightTest, InjectedPointLightMatchesATinyEmissiveSphere) {
  const double radius = 0.004;
  const Rgb radiance{3e4, 2e4, 1e4};
  Scene withSphere = roomWithTinySphere(radius, radiance);
  Mesh mesh = subdivideScene(withSphere, 0.2);
  auto caster = makeEmbreeRayCaster(mesh);
  FormFactorOptions ffOptions;
  ffOptions.showProgress = false;
  auto F = std::make_shared<DenseTransport>(std::make_shared<FormFactorMatrix>(computeFormFactors(mesh, *caster, ffOptions)));
  double sphereArea = 0;
  for (std::size_t s = 6; s < withSphere.surfaces.size(); ++s) sphereArea += surfaceArea(withSphere.surfaces[s]);

  // Emitter: the sphere's patches emit.
  RadiosityProblem emitting = makeRadiosityProblem(mesh, emittedRadiosity(withSphere, mesh), patchAlbedo(withSphere, mesh), F);
  std::vector<Rgb> fromSphere;
  makeSolver(SolverKind::Direct)->solve(emitting, fromSphere);

  // Point light: the same mesh with the sphere dark (it still occludes, but is 4 mm across).
  Light light = pointLight({0.5, 0.5, 0.5}, radiance * (sphereArea / 4));
  Scene dark = withSphere;
  for (Surface& s : dark.surfaces) s.emittedRadiance = {};
  RadiosityProblem injected = makeRadiosityProblem(mesh, emittedRadiosity(dark, mesh), patchAlbedo(dark, mesh), F);
  // Sample points on the sphere would be inside it: the light sits at its centre, so shadow rays
  // from the walls would hit the sphere. Cast them against the room alone.
  Mesh roomOnly = subdivideScene(testing::closedCube(1, {}, Rgb::gray(0.5)), 0.2);
  ASSERT_EQ(roomOnly.numPatches() + (withSphere.surfaces.size() - 6), mesh.numPatches());
  auto roomCaster = makeEmbreeRayCaster(roomOnly);
  std::vector<Rgb> e = patchIrradiance(roomOnly, *roomCaster, light, 1);
  std::vector<Rgb> inject = injectedRadiosity(roomOnly, std::vector<Rgb>(roomOnly.numPatches(), Rgb::gray(0.5)), e);
  for (std::size_t i = 0; i < roomOnly.numPatches(); ++i) injected.emitted[i] = inject[i];
  std::vector<Rgb> fromLight;
  makeSolver(SolverKind::Direct)->solve(injected, fromLight);

  double worst = 0, mean = 0;
  for (std::size_t i = 0; i < roomOnly.numPatches(); ++i) {
    for (int c = 0; c < 3; ++c) {
      double error = testing::relativeError(fromLight[i][c], fromSphere[i][c]);
      worst = std::fmax(worst, error);
      mean += error / (3.0 * roomOnly.numPatches());
    }
  }
  EXPECT_LT(mean, 0.01) << "worst " << worst;
  EXPECT_LT(worst, 0.02) << "mean " << mean;
}

}  // namespace
}  // namespace lambert
