// What the scenes users bring (Blender exports, RenderPark's scenes) showed that the Cornell box did
// not, each built from its geometry with an exact expectation: the default method's outputs on
// curved surfaces, on two-sided sheets, and in narrow cavities.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "lambert/io/vertices.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

// A UV sphere as Blender makes it: one smooth surface of triangles over shared vertices, `segments`
// round, `rings` from pole to pole, counter-clockwise seen from outside.
Surface uvSphere(const Vec3& centre, double radius, int segments, int rings, int material) {
  Surface s{"sphere", {}, material, {}};
  s.vertices.push_back(centre + Vec3{0, radius, 0});
  for (int ring = 1; ring < rings; ++ring)
    for (int seg = 0; seg < segments; ++seg) {
      const double theta = kPi * ring / rings, phi = 2 * kPi * seg / segments;
      s.vertices.push_back(centre + Vec3{std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)} * radius);
    }
  s.vertices.push_back(centre - Vec3{0, radius, 0});
  const auto at = [&](int ring, int seg) -> std::uint32_t {
    if (ring == 0) return 0;
    if (ring == rings) return static_cast<std::uint32_t>(s.vertices.size() - 1);
    return static_cast<std::uint32_t>(1 + (ring - 1) * segments + seg % segments);
  };
  for (int ring = 0; ring < rings; ++ring)
    for (int seg = 0; seg < segments; ++seg) {
      const std::uint32_t a = at(ring, seg), b = at(ring, seg + 1), c = at(ring + 1, seg + 1), d = at(ring + 1, seg);
      if (ring > 0) s.faces.push_back({a, d, b});
      if (ring + 1 < rings) s.faces.push_back({b, d, c});
    }
  return s;
}

Light pointLight(const Vec3& position, double wattsPerSteradian) {
  Light light;
  light.name = "lamp";
  light.kind = LightKind::Point;
  light.position = position;
  light.intensity = Rgb::gray(wattsPerSteradian);
  return light;
}

// A lit sphere alone: nothing else in the scene and a convex surface, so every point's light is the
// lamp's direct light, L = ρ/π · I cosθ / r², exactly. Every vertex of the sphere's own mesh was
// black before vertex sites stayed on a face: moved toward the mean of their faces' centroids, they
// lay inside the sphere, behind every face. Both ways round: one-sided, and two-sided (its twin, the
// inside, lies on it).
TEST(RealGeometryTest, SphereVerticesShowTheLampsDirectLight) {
  for (const bool twoSided : {false, true}) {
    Scene scene = testing::sceneOf({uvSphere({0, 0, 0}, 1.0, 24, 12, 0)});
    scene.materials[0].twoSided = twoSided;
    addTwins(scene);
    const Vec3 lamp{0, 3, 0};
    const double intensity = 8, rho = 0.5;
    scene.lights.push_back(pointLight(lamp, intensity));
    auto engine = testing::solved(scene);
    ASSERT_TRUE(engine);
    int lit = 0;
    for (const VertexSample& v : vertexSamples(engine->solution())) {
      if (std::fabs(length(v.position) - 1) > 1e-9 || dot(v.position, v.normal) <= 0) continue;  // the sphere's own outside vertices
      const Vec3 toLamp = lamp - v.position;
      const double cosine = dot(normalize(toLamp), v.normal);
      if (cosine < 0.3) continue;  // near the terminator the faceted sphere shades itself
      const double expected = rho / kPi * intensity * cosine / lengthSquared(toLamp);
      EXPECT_NEAR(v.radiance.r, expected, 0.01 * expected) << (twoSided ? "two-sided" : "one-sided") << " vertex at (" << v.position.x
                                                         << ", " << v.position.y << ", " << v.position.z << ")";
      ++lit;
    }
    EXPECT_GE(lit, 60) << "the sphere's lit cap";
  }
}

}  // namespace
}  // namespace lambert
