#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "lambert/core/rng.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/injection.h"
#include "lambert/light/lights.h"
#include "lambert/light/many_lights.h"
#include "lambert/light/photometry.h"
#include "lambert/load/photometry_file.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

Light pointLight(Vec3 position, Rgb intensity) {
  Light light;
  light.kind = LightKind::Point;
  light.position = position;
  light.intensity = intensity;
  return light;
}

Light downlight(Vec3 position, Rgb intensity, double cone = 60, double falloff = 20) {
  Light light;
  light.kind = LightKind::Spot;
  light.position = position;
  light.direction = {0, -1, 0};
  light.intensity = intensity;
  light.coneAngleDegrees = cone;
  light.falloffDegrees = falloff;
  return light;
}

// A square floor of side 2·half at y = 0 facing up.
Surface floorSurface(double half) {
  return {"floor", {{-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half}}, 0, {}};
}

// A horizontal quad at height y facing down (an occluder's underside) and up (its top), over
// [x0, x1] × [z0, z1].
std::vector<Surface> slab(const std::string& name, double x0, double x1, double z0, double z1, double y) {
  return {{name + " under", {{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}}, 0, {}},
          {name + " top", {{x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0}}, 0, {}}};
}

// The every-light, every-ray sum, from lights.h's single-light irradiance: what Ward's estimate is
// measured against.
Rgb everyLight(const std::vector<Light>& lights, const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon) {
  Rgb e;
  for (const Light& light : lights) e += irradiance(light, x, n, caster, epsilon, 1);
  return e;
}

struct World {
  Scene scene;
  Mesh mesh;
  std::unique_ptr<RayCaster> caster;
  double epsilon = 0;
  explicit World(Scene s, double edge = 1) : scene(std::move(s)), mesh(subdivideScene(scene, edge)), caster(makeEmbreeRayCaster(mesh)) {
    epsilon = rayEpsilon(mesh);
  }
};

// A floor with slabs hanging over it at several heights: shadows of every size.
World clutteredFloor() {
  std::vector<Surface> surfaces{floorSurface(10)};
  Pcg32 rng(7, 1);
  for (int k = 0; k < 12; ++k) {
    const double x = -9 + 16 * rng.nextDouble(), z = -9 + 16 * rng.nextDouble();
    const double w = 0.5 + 2 * rng.nextDouble(), d = 0.5 + 2 * rng.nextDouble(), y = 0.5 + 1.5 * rng.nextDouble();
    for (Surface& s : slab("slab " + std::to_string(k), x, x + w, z, z + d, y)) surfaces.push_back(std::move(s));
  }
  return World(testing::sceneOf(surfaces), 2);
}

std::vector<Light> mixedLights(int count, std::uint64_t seed) {
  std::vector<Light> lights;
  Pcg32 rng(seed, 3);
  for (int k = 0; k < count; ++k) {
    const Vec3 p{-10 + 20 * rng.nextDouble(), 2.2 + 0.8 * rng.nextDouble(), -10 + 20 * rng.nextDouble()};
    const Rgb i{0.2 + rng.nextDouble(), 0.2 + rng.nextDouble(), 0.2 + rng.nextDouble()};
    lights.push_back(k % 3 == 0 ? pointLight(p, i * 0.3) : downlight(p, i, 20 + 60 * rng.nextDouble(), 10 * rng.nextDouble()));
  }
  return lights;
}

// τ = 0 is the exact sum, bit for bit: every light its ray, in the lights' order.
TEST(ManyLightsTest, ZeroToleranceIsTheEveryLightSum) {
  const World world = clutteredFloor();
  const std::vector<Light> lights = mixedLights(40, 11);
  const DirectLighting exact(lights, 1, 0);
  Pcg32 rng(5, 5);
  for (int k = 0; k < 200; ++k) {
    const Vec3 x{-9.5 + 19 * rng.nextDouble(), 0, -9.5 + 19 * rng.nextDouble()};
    const Rgb expected = everyLight(lights, x, {0, 1, 0}, *world.caster, world.epsilon);
    const Rgb got = exact.irradiance(x, {0, 1, 0}, *world.caster, world.epsilon);
    EXPECT_EQ(got.r, expected.r);
    EXPECT_EQ(got.g, expected.g);
    EXPECT_EQ(got.b, expected.b);
  }
}

// The stated bound, |E − E_exact| ≤ τ·U per channel, at receivers all over a cluttered floor
// (in shadow, in penumbrae, in the open), for several tolerances; and fewer rays than lights.
TEST(ManyLightsTest, ErrorStaysWithinTheToleranceOfTheUnoccludedLight) {
  const World world = clutteredFloor();
  const std::vector<Light> lights = mixedLights(120, 13);
  for (double tolerance : {0.01, 0.05, 0.3}) {
    const DirectLighting ward(lights, 1, tolerance);
    DirectLightingCounts counts;
    Pcg32 rng(9, 9);
    double largestShare = 0;  // of the bound used, over the points
    for (int k = 0; k < 400; ++k) {
      const Vec3 x{-9.5 + 19 * rng.nextDouble(), 0, -9.5 + 19 * rng.nextDouble()};
      const Rgb exact = everyLight(lights, x, {0, 1, 0}, *world.caster, world.epsilon);
      const Rgb unoccluded = ward.unoccluded(x, {0, 1, 0});
      const Rgb got = ward.irradiance(x, {0, 1, 0}, *world.caster, world.epsilon, &counts);
      for (int c = 0; c < 3; ++c) {
        EXPECT_LE(std::fabs(got[c] - exact[c]), tolerance * unoccluded[c] * (1 + 1e-9) + 1e-15) << "τ " << tolerance << " point " << k;
        if (unoccluded[c] > 0) largestShare = std::max(largestShare, std::fabs(got[c] - exact[c]) / (tolerance * unoccluded[c]));
      }
    }
    // Culling happened: fewer rays than lights reaching the points.
    EXPECT_LT(counts.shadowRays, counts.lightsReaching) << "τ " << tolerance;
    // And the estimate is not exact by accident: some point used part of its allowance.
    if (tolerance >= 0.05) {
      EXPECT_GT(largestShare, 1e-3) << "τ " << tolerance;
    }
  }
}

// The case culling by distance or by a fixed contribution threshold gets wrong: a receiver under
// a canopy that hides every near light, lit only by a far, low light through the open side. The
// far light carries a few percent of the unoccluded total, more than τ, so it must be tested;
// dropping it would leave the point dark (an error of its whole share, above the bound).
TEST(ManyLightsTest, AFarLightThatMattersIsTested) {
  std::vector<Surface> surfaces{floorSurface(20)};
  for (Surface& s : slab("canopy", -3, 3, -3, 3, 1)) surfaces.push_back(std::move(s));
  const World world(testing::sceneOf(surfaces), 2);
  std::vector<Light> lights;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) lights.push_back(pointLight({-2.25 + 0.5 * i, 2, -2.25 + 0.5 * j}, Rgb::gray(1)));
  const Vec3 x{0, 0, 0}, up{0, 1, 0};
  const DirectLighting nearOnly(lights, 1, 0);
  const double nearTotal = nearOnly.unoccluded(x, up).g;
  // The far light at 15 m, 0.5 m up, sized to carry 3% of the total unoccluded irradiance.
  const Vec3 far{15, 0.5, 0};
  const double farGeometry = far.y / std::pow(length(far), 3);  // cosθ / r²
  const double share = 0.03;
  lights.push_back(pointLight(far, Rgb::gray(share / (1 - share) * nearTotal / farGeometry)));
  const Rgb exact = everyLight(lights, x, up, *world.caster, world.epsilon);
  ASSERT_GT(exact.g, 0.029 * (nearTotal / (1 - share)));  // the far light alone reaches it
  const DirectLighting ward(lights, 1, 0.01);
  const Rgb unoccluded = ward.unoccluded(x, up);
  EXPECT_NEAR(unoccluded.g * share, exact.g, 1e-9 * exact.g);
  const Rgb got = ward.irradiance(x, up, *world.caster, world.epsilon);
  EXPECT_NEAR(got.g, exact.g, 0.01 * unoccluded.g);
  EXPECT_GT(got.g, 0.5 * exact.g);
}

// In the open (nothing occludes), the estimate is the unoccluded sum whatever τ: the untested
// remainder is weighted by a visibility ratio of 1. Checked against E = Σ I·h/d³ for downlights
// over a plane, within their cones' full-intensity core, written out here.
TEST(ManyLightsTest, UnoccludedGridMatchesTheInverseSquareCosineSum) {
  const World world(testing::sceneOf({floorSurface(40)}), 4);
  std::vector<Light> lights;
  const double h = 2.8;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 10; ++j) lights.push_back(downlight({-24 + 2.4 * (i + 0.5), h, -12 + 2.4 * (j + 0.5)}, Rgb::gray(1.5), 60, 0));
  const DirectLighting ward(lights, 1, 0.01);
  DirectLightingCounts counts;
  Pcg32 rng(3, 3);
  for (int k = 0; k < 100; ++k) {
    const Vec3 x{-20 + 40 * rng.nextDouble(), 0, -10 + 20 * rng.nextDouble()};
    double expected = 0;
    for (const Light& light : lights) {
      const Vec3 d = light.position - x;
      const double r = length(d);
      if (d.y / r > std::cos(60 * kPi / 180)) expected += 1.5 * d.y / (r * r * r);  // inside the 60° cone, no soft edge
    }
    const Rgb got = ward.irradiance(x, {0, 1, 0}, *world.caster, world.epsilon, &counts);
    EXPECT_NEAR(got.g, expected, 1e-9 * expected);
  }
  // Each point is reached by the lights whose cones hold it (about 10 of the 200), and tests fewer.
  EXPECT_LT(counts.lightsReaching, 20 * counts.points);
  EXPECT_LE(counts.shadowRays, counts.lightsReaching);
}

// The joint patch average with τ = 0 is the sum of the single-light averages (the same sample
// points), and the injection of more than kPerLightInjectionLights lights in the open gives ρ
// times it within τ; moving one light traces again.
TEST(ManyLightsTest, PatchAveragesAndInjectionAgreeWithThePerLightTraces) {
  World world = clutteredFloor();
  const std::vector<Light> lights = mixedLights(12, 17);
  const DirectLightOptions options;
  const std::size_t n = world.mesh.numPatches();
  std::vector<Rgb> perLightSum(n);
  for (const Light& light : lights) {
    const std::vector<Rgb> e = patchIrradiance(world.mesh, *world.caster, light, 1, options);
    for (std::size_t i = 0; i < n; ++i) perLightSum[i] += e[i];
  }
  std::vector<std::uint32_t> all(n);
  for (std::uint32_t i = 0; i < n; ++i) all[i] = i;
  std::vector<Rgb> joint(n);
  patchIrradiance(world.mesh, *world.caster, DirectLighting(lights, 1, 0), options, world.epsilon, all, joint);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(joint[i][c], perLightSum[i][c], 1e-12 * (1 + perLightSum[i][c])) << i;

  // The open floor alone: Ward's estimate is the exact one there.
  World open(testing::sceneOf({floorSurface(10)}), 2);
  const std::size_t m = open.mesh.numPatches();
  std::vector<Rgb> exactOpen(m);
  std::vector<Light> moved = lights;
  for (const Light& light : lights) {
    const std::vector<Rgb> e = patchIrradiance(open.mesh, *open.caster, light, 1, options);
    for (std::size_t i = 0; i < m; ++i) exactOpen[i] += e[i];
  }
  const std::vector<Rgb> albedo(m, Rgb{0.5, 0.4, 0.3});
  DirectLightInjection injection(options);
  ASSERT_GT(lights.size(), kPerLightInjectionLights);
  DirectLightInjection::Update update = injection.update(open.mesh, *open.caster, albedo, lights, 1);
  EXPECT_TRUE(update.changed);
  EXPECT_EQ(update.lightsTraced, static_cast<int>(lights.size()));
  EXPECT_GT(injection.counts().points, 0u);
  // In the open U is the exact sum: the injection is within τ of ρ times it (the lights a patch's
  // selection dropped are missing, at most τ/2 of it; Ward's testing adds no error in the open).
  for (std::size_t i = 0; i < m; ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(injection.total()[i][c], albedo[i][c] * exactOpen[i][c], options.shadowTolerance * albedo[i][c] * exactOpen[i][c] + 1e-15) << i;
  // Unchanged lights: nothing traced. One light moved: its light moves with it.
  EXPECT_FALSE(injection.update(open.mesh, *open.caster, albedo, lights, 1).changed);
  moved[0].position = moved[0].position + Vec3{3, 0, 0};
  update = injection.update(open.mesh, *open.caster, albedo, moved, 1);
  EXPECT_TRUE(update.changed);
  const std::vector<Rgb> before = patchIrradiance(open.mesh, *open.caster, lights[0], 1, options);
  const std::vector<Rgb> after = patchIrradiance(open.mesh, *open.caster, moved[0], 1, options);
  for (std::size_t i = 0; i < m; ++i)
    EXPECT_NEAR(injection.total()[i].g, albedo[i].g * (exactOpen[i].g - before[i].g + after[i].g),
                options.shadowTolerance * albedo[i].g * (exactOpen[i].g - before[i].g + after[i].g) + 1e-15);
}

// The bounds select() culls by hold: at points anywhere within the region's sphere (facing its
// normal, or tilted off it), no light gives more than its bound.
TEST(ManyLightsTest, UpperBoundsHoldOverTheRegion) {
  const std::vector<Light> lights = mixedLights(60, 21);
  const DirectLighting lighting(lights, 1, 0.01);
  Pcg32 rng(4, 4);
  int positive = 0;
  for (int k = 0; k < 300; ++k) {
    const Vec3 centre{-10 + 20 * rng.nextDouble(), 2 * rng.nextDouble(), -10 + 20 * rng.nextDouble()};
    const double radius = 0.5 * rng.nextDouble();
    const Vec3 n = normalize(Vec3{rng.nextDouble() - 0.5, 1, rng.nextDouble() - 0.5});
    for (std::size_t l = 0; l < lights.size(); ++l) {
      const Rgb bound = lighting.upperBound(l, centre, radius, n);
      for (int j = 0; j < 8; ++j) {
        const Vec3 offset{rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, rng.nextDouble() - 0.5};
        const Vec3 x = centre + normalize(offset) * (radius * rng.nextDouble());
        const Rgb e = unshadowedIrradiance(lights[l], x, n, 1);
        positive += e.maxComponent() > 0;
        for (int c = 0; c < 3; ++c) EXPECT_LE(e[c], bound[c] * (1 + 1e-12)) << "light " << l << " region " << k;
      }
    }
  }
  EXPECT_GT(positive, 1000);
}

// A region's selection (as each patch makes one) keeps the bound at its points, and drops lights:
// 200 downlights over a cluttered floor, regions the size of elements.
TEST(ManyLightsTest, SelectionKeepsTheBoundAndDropsFarLights) {
  const World world = clutteredFloor();
  std::vector<Light> lights;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 10; ++j) lights.push_back(downlight({-10 + (i + 0.5), 2.8, -10 + 2 * (j + 0.5)}, Rgb{1, 0.9, 0.8}, 75, 15));
  for (double tolerance : {0.01, 0.1}) {
    const DirectLighting lighting(lights, 1, tolerance);
    LightSelection selection;
    std::size_t dropped = 0, regions = 0;
    Pcg32 rng(8, 8);
    for (int k = 0; k < 100; ++k) {
      const Vec3 centre{-9 + 18 * rng.nextDouble(), 0, -9 + 18 * rng.nextDouble()};
      const double radius = 0.3;
      lighting.select(centre, radius, {0, 1, 0}, selection);
      dropped += selection.dropped.size();
      ++regions;
      for (int j = 0; j < 10; ++j) {
        const Vec3 x = centre + Vec3{(rng.nextDouble() - 0.5) * 0.4, 0, (rng.nextDouble() - 0.5) * 0.4};
        const Rgb exact = everyLight(lights, x, {0, 1, 0}, *world.caster, world.epsilon);
        const Rgb unoccluded = lighting.unoccluded(x, {0, 1, 0});
        const Rgb got = lighting.irradiance(x, {0, 1, 0}, *world.caster, world.epsilon, selection);
        for (int c = 0; c < 3; ++c)
          EXPECT_LE(std::fabs(got[c] - exact[c]), tolerance * unoccluded[c] * (1 + 1e-9) + 1e-15) << "τ " << tolerance << " region " << k;
      }
    }
    // The weakest few of the ~150 lights reaching each region at τ = 0.01 (spots keep their full
    // intensity to the cone's soft edge, so the far ones still carry a share), over ten at 0.1.
    EXPECT_GE(dropped, (tolerance < 0.05 ? 1 : 10) * regions) << "τ " << tolerance << ": " << dropped << " dropped";
  }
}

// A lobed, tilted luminaire distribution (not rotationally symmetric), as an LM-63-2002 file
// every 5° in γ and 30° in C, read by the IES reader.
std::shared_ptr<const Photometry> lobedPhotometry() {
  std::ostringstream o;
  o.precision(17);
  o << "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 37 13 1 2 0 0 0\n1 1 10\n";
  for (int v = 0; v < 37; ++v) o << v * 5 << " ";
  o << "\n";
  for (int h = 0; h < 13; ++h) o << h * 30 << " ";
  o << "\n";
  for (int h = 0; h < 13; ++h) {
    for (int v = 0; v < 37; ++v) {
      const double g = v * 5 * kPi / 180, c = h * 30 * kPi / 180;
      o << (v * 5 > 95 ? 0.0 : 800 * std::pow(std::fmax(std::cos(g), 0.0), 2) * (1 + 0.6 * std::sin(g) * std::cos(c)) + 5) << " ";
    }
    o << "\n";
  }
  Result<Photometry> p = parseIes(o.str(), "lobed.ies");
  EXPECT_TRUE(p.ok()) << p.error().message;
  return std::make_shared<const Photometry>(std::move(*p));
}

// Far-field luminaires: the precomputed evaluation is lights.cpp's unshadowedIrradiance, their
// bounds hold over regions, and the bound on the estimate holds under them, aimed and turned.
TEST(ManyLightsTest, LuminairesAreEvaluatedBoundedAndWithinTheTolerance) {
  const std::shared_ptr<const Photometry> photometry = lobedPhotometry();
  std::vector<Light> lights;
  Pcg32 rng(12, 12);
  for (int k = 0; k < 80; ++k) {
    Light l;
    l.kind = LightKind::Luminaire;
    l.photometry = photometry;
    l.position = {-10 + 20 * rng.nextDouble(), 2.5 + 0.5 * rng.nextDouble(), -10 + 20 * rng.nextDouble()};
    l.direction = normalize(Vec3{0.4 * (rng.nextDouble() - 0.5), -1, 0.4 * (rng.nextDouble() - 0.5)});
    l.rotationDegrees = 360 * rng.nextDouble();
    l.intensity = Rgb{1, 0.9, 0.8};  // colour: W/sr = candela × this / 683
    lights.push_back(l);
  }
  const World world = clutteredFloor();
  const double tolerance = 0.02;
  const DirectLighting lighting(lights, 1, tolerance);
  int lit = 0;
  for (int k = 0; k < 150; ++k) {
    const Vec3 centre{-9.5 + 19 * rng.nextDouble(), 0, -9.5 + 19 * rng.nextDouble()};
    const double radius = 0.4 * rng.nextDouble();
    for (std::size_t l = 0; l < lights.size(); ++l) {
      const Rgb bound = lighting.upperBound(l, centre, radius, {0, 1, 0});
      for (int j = 0; j < 3; ++j) {
        const Vec3 x = centre + Vec3{(rng.nextDouble() - 0.5) * radius, 0, (rng.nextDouble() - 0.5) * radius};
        const Rgb expected = unshadowedIrradiance(lights[l], x, {0, 1, 0}, 1);
        const Rgb got = lighting.unoccluded(l, x, {0, 1, 0});
        lit += expected.g > 0;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(got[c], expected[c], 1e-12 * expected[c]);
          EXPECT_LE(expected[c], bound[c]) << "light " << l << " region " << k;
        }
      }
    }
    LightSelection selection;
    lighting.select(centre, radius, {0, 1, 0}, selection);
    const Vec3 x = centre + Vec3{0.3 * radius, 0, -0.2 * radius};
    const Rgb exact = everyLight(lights, x, {0, 1, 0}, *world.caster, world.epsilon);
    const Rgb unoccluded = lighting.unoccluded(x, {0, 1, 0});
    const Rgb got = lighting.irradiance(x, {0, 1, 0}, *world.caster, world.epsilon, selection);
    for (int c = 0; c < 3; ++c) EXPECT_LE(std::fabs(got[c] - exact[c]), tolerance * unoccluded[c] * (1 + 1e-9) + 1e-15) << "region " << k;
  }
  EXPECT_GT(lit, 10000);
}

}  // namespace
}  // namespace lambert
