// What the scenes users bring (Blender exports, RenderPark's scenes) showed that the Cornell box did
// not, each built from its geometry with an exact expectation: the default method's outputs on
// curved surfaces, on two-sided sheets, and in narrow cavities.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "lambert/core/sampling.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/design/illuminance.h"
#include "lambert/io/vertices.h"
#include "lambert/load/scene_file.h"
#include "lambert/mesh/mesh.h"
#include "lambert/reference/reference.h"
#include "tests/support/engines.h"
#include "tests/support/files.h"
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

// The six faces of the box [lo, hi], each an n × n grid of quads over shared vertices, normals
// outward (inward: a room).
std::vector<Surface> gridBox(const Vec3& lo, const Vec3& hi, int n, int material, bool inward) {
  std::vector<Surface> faces;
  const Vec3 size = hi - lo;
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {0, 1}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Surface s{"face", {}, material, {}};
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          double c[3];
          c[axis] = side ? hi[axis] : lo[axis];
          c[u] = lo[u] + size[u] * i / n;
          c[v] = lo[v] + size[v] * j / n;
          s.vertices.push_back({c[0], c[1], c[2]});
        }
      // Counter-clockwise seen from +axis with (u, v) in order; reversed for the −axis side.
      const bool towardPlus = (side == 1) != inward;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
          std::vector<std::uint32_t> quad{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          if (!towardPlus) std::reverse(quad.begin() + 1, quad.end());
          s.faces.push_back(quad);
        }
      faces.push_back(std::move(s));
    }
  return faces;
}

// A closed two-sided box in a lit room: no light reaches its inside (its faces' twins), and its
// outside must not depend on its inside being there (the issue's invariant): the room solved with
// the box one-sided shows the box's outside alike. Clusters hold both shells, and receiving
// through them, the inside showed a fifth of the room's light and the outside lost its share.
TEST(RealGeometryTest, TheInsideOfAClosedTwoSidedBoxIsDarkAndItsOutsideAsIfOneSided) {
  const auto solve = [](bool twoSided) {
    Scene scene = testing::sceneOf(gridBox({0, 0, 0}, {6, 3, 5}, 6, 0, true));
    scene.materials.push_back({"box", Rgb::gray(0.7), twoSided});
    for (Surface& s : gridBox({2, 0.5, 2}, {3, 1.5, 3}, 4, 1, false)) scene.surfaces.push_back(std::move(s));
    addTwins(scene);
    scene.lights.push_back(pointLight({4.5, 2.6, 4}, 20));
    auto engine = testing::solved(scene);
    return engine ? vertexSamples(engine->solution()) : std::vector<VertexSample>{};
  };
  const std::vector<VertexSample> twoSided = solve(true), oneSided = solve(false);
  ASSERT_FALSE(twoSided.empty());
  ASSERT_FALSE(oneSided.empty());
  const Vec3 centre{2.5, 1.0, 2.5};
  const auto onBox = [&](const VertexSample& v) {
    const Vec3 d = v.position - centre;
    return std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z))) < 0.5 + 1e-9;
  };
  // Per face of the box (its outward normal), the mean of its outside vertices' radiance.
  const auto outsideMeans = [&](const std::vector<VertexSample>& vertices, int& inside, double& insideLargest) {
    std::vector<double> sum(6, 0.0), count(6, 0.0);
    for (const VertexSample& v : vertices) {
      if (!onBox(v)) continue;
      if (dot(v.normal, v.position - centre) < 0) {
        ++inside;
        insideLargest = std::fmax(insideLargest, v.radiance.maxComponent());
        continue;
      }
      const int axis = std::fabs(v.normal.x) > 0.9 ? 0 : std::fabs(v.normal.y) > 0.9 ? 1 : 2;
      const int face = 2 * axis + ((axis == 0 ? v.normal.x : axis == 1 ? v.normal.y : v.normal.z) > 0);
      sum[face] += v.radiance.r;
      count[face] += 1;
    }
    for (int f = 0; f < 6; ++f) sum[f] = count[f] > 0 ? sum[f] / count[f] : 0;
    return sum;
  };
  int inside = 0, insideOneSided = 0;
  double insideLargest = 0, unused = 0;
  const std::vector<double> two = outsideMeans(twoSided, inside, insideLargest);
  const std::vector<double> one = outsideMeans(oneSided, insideOneSided, unused);
  EXPECT_GT(inside, 100) << "the two-sided box's inside vertices";
  EXPECT_EQ(insideOneSided, 0);
  EXPECT_EQ(insideLargest, 0) << "light inside a closed box";
  // Each face's outside against the path tracer at the same vertices, and the two solves against
  // each other. Both within 5%: the one-sided solve is 1.7–4.0% low on every face (measured
  // 2026-12-07; its clusters lose light around the box, docs/hierarchical.md, "What is left"),
  // the two-sided within 2.1%. Before the first pass's estimate stopped lighting the box's inside
  // (docs/hierarchical.md, "Two-sided rooms"), the two-sided solve was 2.7% below the one-sided.
  Scene referenceScene = testing::sceneOf(gridBox({0, 0, 0}, {6, 3, 5}, 6, 0, true));
  referenceScene.materials.push_back({"box", Rgb::gray(0.7), false});
  for (Surface& s : gridBox({2, 0.5, 2}, {3, 1.5, 3}, 4, 1, false)) referenceScene.surfaces.push_back(std::move(s));
  referenceScene.lights.push_back(pointLight({4.5, 2.6, 4}, 20));
  const ReferenceRenderer reference(referenceScene, subdivideScene(referenceScene, 2), testing::quietReferenceOptions(8192));
  std::vector<double> traced(6, 0.0), count(6, 0.0);
  std::uint64_t stream = 0;
  for (const VertexSample& v : oneSided) {
    if (!onBox(v)) continue;
    const int axis = std::fabs(v.normal.x) > 0.9 ? 0 : std::fabs(v.normal.y) > 0.9 ? 1 : 2;
    const int face = 2 * axis + ((axis == 0 ? v.normal.x : axis == 1 ? v.normal.y : v.normal.z) > 0);
    traced[face] += reference.outgoingRadiance(v.position, v.normal, static_cast<std::uint32_t>(6 + face), stream++).r;
    count[face] += 1;
  }
  for (int f = 0; f < 6; ++f) {
    ASSERT_GT(one[f], 0) << "face " << f;
    const double truth = traced[f] / count[f];
    std::printf("box face %d outside: path tracer %.4f, one-sided %+.1f%%, two-sided %+.1f%%\n", f, truth, 100 * (one[f] / truth - 1), 100 * (two[f] / truth - 1));
    const std::string which = "the outside of face " + std::to_string(f) + " (axis " + std::to_string(f / 2) + (f % 2 ? ", +)" : ", -)");
    EXPECT_NEAR(one[f], truth, 0.05 * truth) << which << ", one-sided";
    EXPECT_NEAR(two[f], truth, 0.05 * truth) << which << ", two-sided";
    EXPECT_NEAR(two[f], one[f], 0.05 * one[f]) << which;
  }
}

// A furnace: a closed room of desks on four legs and seat blocks, every surface emitting E with
// albedo ρ. Every open point then sees surfaces of radiosity E/(1 − ρ) all round, whatever hides
// what, so every element's B is E/(1 − ρ). A link's visibility was the share of rays between
// points uniform on the two elements: the side of a desk's leg sees the floor under its desk
// (near, a large share of its light) and little of the rest (far, behind the other legs), and
// when its eight rays all went to the far floor it got none of the floor's light (B 0.72 of
// E/(1 − ρ) there; the furniture's mean 0.962, the room's 0.975). With points on the source
// uniform in the solid angle it subtends, each pair weighed by the light it carries: 0.994 and
// 0.986. Unclustered: the links between elements are what is measured.
TEST(RealGeometryTest, AFurnishedClosedRoomWhereEverythingEmitsIsAFurnace) {
  constexpr double kRho = 0.5, kEmitted = 1.0;
  std::vector<Surface> surfaces = gridBox({0, 0, 0}, {6, 3, 8}, 1, 0, true);
  const auto box = [&](const Vec3& lo, const Vec3& hi) {
    for (Surface& s : gridBox(lo, hi, 1, 0, false)) surfaces.push_back(std::move(s));
  };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      const double x = 1 + 1.6 * i, z = 1 + 1.7 * j;
      box({x, 0.72, z}, {x + 1.2, 0.75, z + 0.6});  // the desk's top
      for (const double dx : {0.0, 1.16})
        for (const double dz : {0.0, 0.56}) box({x + dx, 0, z + dz}, {x + dx + 0.04, 0.72, z + dz + 0.04});
      box({x + 0.3, 0, z + 0.7}, {x + 0.7, 0.45, z + 1.1});  // a seat
    }
  for (Surface& s : surfaces) s.emittedRadiance = Rgb::gray(kEmitted / kPi);
  RadiosityOptions options = testing::quietOptions();
  options.hierarchical.links.clusters = false;
  auto engine = testing::solved(testing::sceneOf(std::move(surfaces), Rgb::gray(kRho)), options);
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  const Mesh& mesh = view.mesh();
  double roomArea = 0, roomSum = 0, furnitureArea = 0, furnitureSum = 0;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    const Patch& p = mesh.patches[i];
    // Faces lying on the floor face down into it: covered, they see nothing.
    if (p.openFraction < 1 || (p.centroid.y < 1e-6 && p.normal.y < -0.9)) continue;
    const double ratio = view.radiosity()[i].g / (kEmitted / (1 - kRho));
    const Vec3 c = p.centroid;
    const bool room = c.x < 1e-6 || c.x > 6 - 1e-6 || c.y < 1e-6 || c.y > 3 - 1e-6 || c.z < 1e-6 || c.z > 8 - 1e-6;
    (room ? roomArea : furnitureArea) += p.area;
    (room ? roomSum : furnitureSum) += p.area * ratio;
  }
  ASSERT_GT(furnitureArea, 20);
  EXPECT_NEAR(furnitureSum / furnitureArea, 1.0, 0.015) << "the furniture's mean B over E/(1 − ρ)";
  EXPECT_NEAR(roomSum / roomArea, 1.0, 0.02) << "the room's";
}

// A closed two-sided sphere (as Blender exports every mesh) lit by an emitting wall 1.5 m away,
// nothing else: what its outside receives is the wall's light on it, Σ over its faces of
// B_wall · F(face → wall) · A by the exact point-to-polygon factor (a convex sphere shades none
// of its own faces from the wall). Its inner twins lie inside a closed object, where no light
// reaches, and its clusters hold both. A cluster link's K was the irradiance over all their
// faces, inner twins included, while the push hands it out over the open ones: the clustered
// solve gave this sphere 54.5% of its light (its upper half 40–55% dark in pictures under a
// lamp); now 96.9%, where the unclustered solve gives 97.3% (at link error 2e-5: 97.2%).
// Among its faces, the clusters' directional push took the light of faces turned toward the wall
// to faces turned away through the bins of their normals' other axes: per element, RMS 22.4% of
// the mean (the faces turned 0.5–0.8 toward the wall −5.1%); with the bins weighed by where the
// light comes from, 13.8% (−2.9%); unclustered, 9.5%.
TEST(RealGeometryTest, AClosedTwoSidedSphereInClustersReceivesTheLightThatFallsOnIt) {
  const double emitted = 10;  // the wall's B, W/m²
  const std::vector<Vec3> wallCorners{{0, 0, 0}, {0, 0, -4}, {0, 3, -4}, {0, 3, 0}};
  Surface wall{"wall", wallCorners, 1, Rgb::gray(emitted / kPi)};
  Scene scene = testing::sceneOf({wall, uvSphere({2, 1.5, -2}, 0.5, 24, 12, 0)});
  scene.materials[0].twoSided = true;
  scene.materials.push_back({"black", Rgb::gray(0)});
  addTwins(scene);
  auto engine = testing::solved(scene);
  ASSERT_TRUE(engine);
  const SolutionView solution = engine->solution();
  const Mesh& mesh = solution.mesh();
  const double rho = 0.5;
  // And per band of the faces' turn toward the wall (cos of the angle between the normal and −x;
  // the bands' light is far from even): the element values (what flat shading draws) in each.
  const double bandEdges[] = {-0.2, 0.2, 0.5, 0.8, 1.0};
  std::array<double, 4> bandSolved{}, bandExact{};
  double solved = 0, exact = 0, squaredError = 0, totalArea = 0;
  for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    if (scene.surfaces[patch.surface].name != std::string("sphere")) continue;  // the outside, not its twin
    const double received = solution.radiosity()[p].r / rho * patch.area;
    double falling = 0;
    const PatchCorners corners = mesh.corners(p);
    const int n = 4;  // n × n points a face: the factor turns at the wall's horizon, which crosses faces
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const Vec3 x = sampleConvexPolygon(corners, (i + 0.5) / n, (j + 0.5) / n);
        falling += emitted * pointToPolygonFormFactor(x, patch.normal, wallCorners, {1, 0, 0}) * patch.area / (n * n);
      }
    solved += received;
    exact += falling;
    squaredError += (received - falling) * (received - falling) / patch.area;
    totalArea += patch.area;
    for (int b = 0; b < 4; ++b)
      if (-patch.normal.x >= bandEdges[b] && -patch.normal.x < bandEdges[b + 1] + 1e-12) bandSolved[b] += received, bandExact[b] += falling;
  }
  std::printf("the sphere's outside receives %.4f W, the wall's light on it %.4f W (%+.1f%%)\n", solved, exact, 100 * (solved / exact - 1));
  const double elementRms = std::sqrt(squaredError / totalArea) / (exact / totalArea);
  std::printf("per element, RMS %.1f%% of the mean irradiance\n", 100 * elementRms);
  EXPECT_NEAR(solved / exact, 1, 0.05);
  EXPECT_LT(elementRms, 0.17);
  // The faces at the terminator (the first band) are left out: their light is small and turns
  // fast, and the unclustered solve is 24% low there too (element links to a wall at their horizon).
  for (int b = 0; b < 4; ++b) {
    std::printf("faces turned %.1f to %.1f toward the wall: %+.1f%%\n", bandEdges[b], bandEdges[b + 1], 100 * (bandSolved[b] / bandExact[b] - 1));
    if (b > 0) {
      EXPECT_NEAR(bandSolved[b] / bandExact[b], 1, 0.045) << "band " << b;
    }
  }
}

// A 6 × 6 m floor given as 40 long triangles fanned from one corner (as some exporters write a
// polygon), under a point lamp 1 m over it and nothing else: every point's radiance is the lamp's
// direct light, ρ/π · I cosθ / r², exactly. What a user sees is the vertex values interpolated
// over the triangles drawn (Gouraud, a glb's vertex colours): at 20,000 points of the floor, that
// against the closed form. Split four ways, a sliver's leaves stayed slivers, and where the lamp's
// light varied along them the bound on their power (small, for their area) left them long: RMS
// 7.0%, worst 42.6% (light and dark wedges from the fan's apex), where the same floor as two
// triangles gave 0.87% and 4.2%. Halved across their length and judged over their extent: 1.3%
// and 7.0%.
TEST(RealGeometryTest, AFloorOfFannedSliversShowsTheLampsLightAsAFloorOfTwoTrianglesDoes) {
  const Vec3 lamp{4, 1, 3};
  const double intensity = 10, rho = 0.5, side = 6;
  const auto interpolatedError = [&](bool fan) {
    Surface floor{"floor", {{0, 0, 0}}, 0, {}};
    if (fan) {
      for (int k = 0; k <= 20; ++k) floor.vertices.push_back({side, 0, side * k / 20});
      for (int k = 1; k <= 20; ++k) floor.vertices.push_back({side - side * k / 20, 0, side});
      for (std::uint32_t k = 1; k + 1 < floor.vertices.size(); ++k) floor.faces.push_back({0, k + 1, k});
    } else {
      floor.vertices.insert(floor.vertices.end(), {{side, 0, 0}, {side, 0, side}, {0, 0, side}});
      floor.faces = {{0, 2, 1}, {0, 3, 2}};
    }
    Scene scene = testing::sceneOf({floor});
    scene.lights.push_back(pointLight(lamp, intensity));
    auto engine = testing::solved(scene);
    if (!engine) return std::pair{1.0, 1.0};
    const SolutionView solution = engine->solution();
    const Mesh& mesh = solution.vertexMesh();
    const std::vector<Rgb> radiance = solution.vertexRadiance();
    double squares = 0, worst = 0;
    int found = 0;
    const int n = 140;  // n × n stratified points
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = side * (i + 0.37) / n, z = side * (j + 0.61) / n;
        double value = -1;
        for (const Patch& p : mesh.patches)
          for (std::uint32_t k = 1; k + 1 < p.numCorners && value < 0; ++k) {
            const Vec3 &a = mesh.positions[p.vertices[0]], &b = mesh.positions[p.vertices[k]], &c = mesh.positions[p.vertices[k + 1]];
            const double det = (b.z - c.z) * (a.x - c.x) + (c.x - b.x) * (a.z - c.z);
            const double wa = ((b.z - c.z) * (x - c.x) + (c.x - b.x) * (z - c.z)) / det;
            const double wb = ((c.z - a.z) * (x - c.x) + (a.x - c.x) * (z - c.z)) / det;
            if (wa < -1e-12 || wb < -1e-12 || wa + wb > 1 + 1e-12) continue;
            value = wa * radiance[p.vertices[0]].r + wb * radiance[p.vertices[k]].r + (1 - wa - wb) * radiance[p.vertices[k + 1]].r;
          }
        if (value < 0) continue;
        const Vec3 toLamp = lamp - Vec3{x, 0, z};
        const double exact = rho / kPi * intensity * (lamp.y / length(toLamp)) / lengthSquared(toLamp);
        const double relative = value / exact - 1;
        squares += relative * relative;
        worst = std::fmax(worst, std::fabs(relative));
        ++found;
      }
    EXPECT_EQ(found, n * n) << "every point lies on a triangle drawn";
    return std::pair{std::sqrt(squares / std::max(found, 1)), worst};
  };
  const auto [fanRms, fanWorst] = interpolatedError(true);
  const auto [twoRms, twoWorst] = interpolatedError(false);
  std::printf("interpolated against the closed form: fan RMS %.2f%%, worst %.1f%%; two triangles RMS %.2f%%, worst %.1f%%\n",
              100 * fanRms, 100 * fanWorst, 100 * twoRms, 100 * twoWorst);
  EXPECT_LT(twoRms, 0.015);
  EXPECT_LT(fanRms, 0.02);
  EXPECT_LT(fanWorst, 0.12);
}

// A small two-sided sheet (10 cm, 8 × 8 faces) between a large red emitter 3 m above and a blue one
// 3 m below, nothing else: each side sees one emitter only, so its top shows no blue and its bottom
// no red, exactly, in its vertex values and in the solution's own elements (whose radiosity lights
// everything else). Both sides lie in the clusters the sheet's light arrives through.
TEST(RealGeometryTest, EachSideOfAnOpenSheetShowsOnlyWhatItFaces) {
  Scene scene = testing::sceneOf({}, Rgb::gray(0.5));
  scene.materials[0].twoSided = true;
  scene.materials.push_back({"emitter", Rgb{}, false});
  Surface sheet{"sheet", {}, 0, {}};
  const int n = 8;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) sheet.vertices.push_back({0.45 + 0.1 * i / n, 0, 0.45 + 0.1 * j / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
      sheet.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});  // facing +y
    }
  scene.surfaces.push_back(sheet);
  scene.surfaces.push_back({"red", {{-1, 3, -1}, {2, 3, -1}, {2, 3, 2}, {-1, 3, 2}}, 1, Rgb{1, 0, 0}});      // facing −y
  scene.surfaces.push_back({"blue", {{-1, -3, -1}, {-1, -3, 2}, {2, -3, 2}, {2, -3, -1}}, 1, Rgb{0, 0, 1}});  // facing +y
  ASSERT_GT(surfaceNormal(scene.surfaces[0]).y, 0.99);
  ASSERT_LT(surfaceNormal(scene.surfaces[1]).y, -0.99);
  ASSERT_GT(surfaceNormal(scene.surfaces[2]).y, 0.99);
  addTwins(scene);
  auto engine = testing::solved(scene);
  ASSERT_TRUE(engine);
  int top = 0, bottom = 0;
  for (const VertexSample& v : vertexSamples(engine->solution())) {
    if (std::fabs(v.position.y) > 1e-9) continue;
    const bool up = v.normal.y > 0;
    const double seen = up ? v.radiance.r : v.radiance.b, other = up ? v.radiance.b : v.radiance.r;
    EXPECT_GT(seen, 0) << (up ? "top" : "bottom") << " at (" << v.position.x << ", " << v.position.z << ")";
    EXPECT_LT(other, 1e-3 * seen) << (up ? "top" : "bottom") << " at (" << v.position.x << ", " << v.position.z << ")";
    ++(up ? top : bottom);
  }
  EXPECT_GT(top, 50);
  EXPECT_GT(bottom, 50);
  // The solution's own elements too: their radiosity is what lights everything else.
  const SolutionView view = engine->solution();
  int elements = 0;
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const std::uint32_t surface = view.mesh().patches[i].surface;
    if (surface != 0 && surface != 3) continue;  // the sheet (0) and its twin (3)
    const Rgb& b = view.radiosity()[i];
    const double seen = surface == 0 ? b.r : b.b, other = surface == 0 ? b.b : b.r;
    EXPECT_GT(seen, 0) << "element " << i << " of surface " << surface;
    EXPECT_LT(other, 1e-3 * seen) << "element " << i << " of surface " << surface;
    ++elements;
  }
  EXPECT_GT(elements, 2 * n * n - 1);
}

// Luminaires as RenderPark's classroom has them: thin emitting strips facing down, each inside a
// black housing (its top and sides face up and out), a 4 × 4 grid of them 3 m over a 20 m floor,
// nothing else. The floor's light is the strips' alone, L = ρ L_e Σ F(x → strip) at every floor
// vertex, F the exact point-to-polygon factor. Seen from most of the floor a luminaire is a far
// cluster; with its mean radiosity (the strip's power spread over the housing too) times the
// area it shows downward, the floor's vertices were 62% off (relative RMSE). With that fixed they
// were still 12% off, with or without the housings: a cluster of floor pieces and the luminaires
// over them, seen level from another, showed nothing toward the other's centre and their link was
// dropped as empty. Now 2.3%.
TEST(RealGeometryTest, FarLuminaireClustersShowTheFloorTheirEmittingFacesOnly) {
  Scene scene = testing::sceneOf({}, Rgb::gray(0.5));
  scene.materials.push_back({"housing", Rgb{}, false});
  Surface floor{"floor", {}, 0, {}};
  const int n = 10;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) floor.vertices.push_back({-10 + 20.0 * i / n, 0, -10 + 20.0 * j / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
      floor.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});  // facing +y
    }
  scene.surfaces.push_back(floor);
  const double y = 3, w = 0.02, l = 0.6, hw = 0.1, top = y + 0.1;  // a 4 cm × 1.2 m strip in a 20 × 10 cm housing
  std::vector<std::vector<Vec3>> strips;
  for (const double cx : {-6.0, -2.0, 2.0, 6.0})
    for (const double cz : {-6.0, -2.0, 2.0, 6.0}) {
      strips.push_back({{cx - w, y, cz - l}, {cx + w, y, cz - l}, {cx + w, y, cz + l}, {cx - w, y, cz + l}});
      scene.surfaces.push_back({"strip", strips.back(), 1, Rgb::gray(50)});
      scene.surfaces.push_back({"top", {{cx - hw, top, cz - l}, {cx - hw, top, cz + l}, {cx + hw, top, cz + l}, {cx + hw, top, cz - l}}, 1, {}});
      scene.surfaces.push_back({"left", {{cx - hw, y, cz - l}, {cx - hw, y, cz + l}, {cx - hw, top, cz + l}, {cx - hw, top, cz - l}}, 1, {}});
      scene.surfaces.push_back({"right", {{cx + hw, y, cz - l}, {cx + hw, top, cz - l}, {cx + hw, top, cz + l}, {cx + hw, y, cz + l}}, 1, {}});
    }
  ASSERT_LT(surfaceNormal(scene.surfaces[1]).y, -0.99);
  ASSERT_GT(surfaceNormal(scene.surfaces[2]).y, 0.99);
  ASSERT_LT(surfaceNormal(scene.surfaces[3]).x, -0.99);
  ASSERT_GT(surfaceNormal(scene.surfaces[4]).x, 0.99);
  auto engine = testing::solved(scene);
  ASSERT_TRUE(engine);
  double squared = 0, expectedSum = 0;
  int floorVertices = 0;
  for (const VertexSample& v : vertexSamples(engine->solution())) {
    if (std::fabs(v.position.y) > 1e-9 || v.normal.y < 0.99) continue;
    double expected = 0;
    for (const auto& strip : strips) expected += 0.5 * 50 * pointToPolygonFormFactor(v.position, v.normal, strip, {0, -1, 0});
    squared += (v.radiance.r - expected) * (v.radiance.r - expected);
    expectedSum += expected;
    ++floorVertices;
  }
  ASSERT_GE(floorVertices, (n + 1) * (n + 1));
  const double relativeRmse = std::sqrt(squared / floorVertices) / (expectedSum / floorVertices);
  EXPECT_LT(relativeRmse, 0.05) << "the floor's vertices against the strips' exact light";
}

// A lamp panel hung 10 cm under the ceiling of a closed 5 × 3 × 4 m room (Blender's emissive plane:
// both faces emit), the meter (SolutionView::pointIrradiance) against the path tracer at points in
// the cavity and in the room. Between the panel's top and the ceiling the light bounces twice
// (E ≈ 2 F L_e π there). Three mechanisms made the cavity 29% dark over the panel and its top 38%:
// the bound scaled a ceiling leaf's own link to the panel (K ≈ 0.94) with the room its ancestors
// see through the open part of theirs (K ≈ 0.6); the panel's top linked to whole ceiling
// elements whose mean radiosity is mostly the dim ceiling around the cavity (a link hands its
// receiver the source's mean: sources are now split where their leaves differ, link_estimator.h);
// and walls linked to ceiling elements half behind the panel saw their mean, the bright half
// included (element links now weigh their rays by the source leaves' radiosity, links.cpp).
TEST(RealGeometryTest, ALampPanelHungUnderACeilingLightsItsCavityAndTheRoom) {
  Scene scene = testing::sceneOf({}, Rgb::gray(0.75));
  scene.materials.push_back({"floor", Rgb::gray(0.4), false});
  scene.materials.push_back({"panel", Rgb::gray(0.8), true});
  const double x0 = -2.5, x1 = 2.5, y1 = 3, z0 = -2, z1 = 2, panelY = 2.9;
  scene.surfaces = {{"ceiling", {{x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}}, 0, {}},
                    {"floor", {{x0, 0, z0}, {x0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}}, 1, {}},
                    {"west", {{x0, 0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, 0, z1}}, 0, {}},
                    {"east", {{x1, 0, z0}, {x1, 0, z1}, {x1, y1, z1}, {x1, y1, z0}}, 0, {}},
                    {"north", {{x0, 0, z0}, {x1, 0, z0}, {x1, y1, z0}, {x0, y1, z0}}, 0, {}},
                    {"south", {{x0, 0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, 0, z1}}, 0, {}},
                    {"panel", {{-0.6, panelY, -0.3}, {0.6, panelY, -0.3}, {0.6, panelY, 0.3}, {-0.6, panelY, 0.3}}, 2, Rgb::gray(10)}};
  addTwins(scene);
  for (std::size_t s = 0; s < 6; ++s) ASSERT_GT(dot(surfaceNormal(scene.surfaces[s]), Vec3{0, 1.5, 0} - scene.surfaces[s].vertices[0]), 0) << s;  // inward
  ASSERT_LT(surfaceNormal(scene.surfaces[6]).y, -0.99);  // the panel faces down, its twin (7) up
  ASSERT_EQ(scene.surfaces.size(), 8u);
  auto engine = testing::solved(scene);
  ASSERT_TRUE(engine);
  struct Probe {
    const char* what;
    SurfacePoint at;
    double meterTolerance, gatherTolerance;  // 0: the point gather is not held there
  };
  const std::vector<Probe> probes = {{"ceiling over the panel", {{0, y1, 0}, {0, -1, 0}, 0}, 0.08, 0.12},
                                     {"ceiling over the panel's edge", {{0.55, y1, 0.25}, {0, -1, 0}, 0}, 0.05, 0.05},
                                     {"panel's top", {{0, panelY, 0}, {0, 1, 0}, 7}, 0.13, 0.13},
                                     {"ceiling beside the panel", {{0.8, y1, 0}, {0, -1, 0}, 0}, 0.05, 0.1},
                                     {"floor under the panel", {{0, 0, 0}, {0, 1, 0}, 1}, 0.05, 0},
                                     {"floor", {{1.5, 0, 1}, {0, 1, 0}, 1}, 0.05, 0},
                                     {"wall", {{x0, 1.5, 0}, {1, 0, 0}, 2}, 0.05, 0},
                                     {"wall at the cavity's height", {{x0, panelY, 0}, {1, 0, 0}, 2}, 0.05, 0.08}};
  std::vector<SurfacePoint> points;
  std::vector<CalculationPoint> meterPoints;
  for (const Probe& p : probes) {
    points.push_back(p.at);
    meterPoints.push_back({p.at.point, p.at.normal});
  }
  const Result<std::vector<PointIrradiance>> metered = IlluminanceMeter(engine->solution()).measure(meterPoints);
  ASSERT_TRUE(metered.ok()) << metered.error().message;
  const Result<std::vector<Rgb>> gathered = engine->solution().pointIrradiance(points);
  ASSERT_TRUE(gathered.ok()) << gathered.error().message;
  const ReferenceRenderer tracer(scene, subdivideScene(scene, 10.0), testing::quietReferenceOptions(16384));
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const SurfacePoint& p = probes[i].at;
    const double traced = tracer.irradianceAt(p.point, p.normal, p.surface, i).g;
    const double meter = (*metered)[i].total().g, gather = (*gathered)[i].g;
    std::printf("%-30s traced %8.3f  meter %8.3f (%+5.1f%%)  point gather %8.3f (%+5.1f%%)\n", probes[i].what, traced, meter,
                100 * (meter / traced - 1), gather, 100 * (gather / traced - 1));
    EXPECT_LT(std::fabs(meter / traced - 1), probes[i].meterTolerance) << probes[i].what;
    if (probes[i].gatherTolerance > 0) {
      EXPECT_LT(std::fabs(gather / traced - 1), probes[i].gatherTolerance) << probes[i].what;
    }
  }
}

// A sphere under a lamp hung 1 cm below the ceiling (two-sided, as MGF's materials are): the ceiling
// is bright only over the lamp, which hides just that part from the sphere. Its top vertex
// gathered the ceiling's elements through a link into the sphere's cluster, at their mean and with
// that link's visibility, and showed 1.40 times the path tracer's light where the meter at the
// same point read it within 3% (the smooth picture's sphere tops 1.8 times the flat one's). The
// vertex now resolves such a source's visibility and opens it (final_gather.cpp, variesBehind):
// +12 to +24%, what is left being the ceiling's leaves across the lamp's edge, bright over their
// whole extent in the solve though the lamp hides their bright half. The figure moves with the
// leaves: +12% while spurious splits (pairs of the spheres' faces opened one by one, links.cpp
// mayFace) cut the whole ceiling to the smallest elements, +24% and +20% with them at link errors
// 1e-4 and 5e-5; +20% without them at the default.
TEST(RealGeometryTest, ASphereTopUnderALampHungAtTheCeilingShowsWhatItSees) {
  // An MGF file as one is written: a 4 × 4 × 3 m room, two touching spheres (64 segments), a lamp
  // 0.8 m square 1 cm under the ceiling; every material two-sided, as MGF's are by default.
  const std::filesystem::path dir = testing::scratchDirectory("real-geometry", "sphere-under-lamp");
  std::ofstream(dir / "spheres.mgf") << R"(m white =
	c
	rd .7
m grey =
	c
	rd .5
m lamp =
	c
	ed 40
v f1 =
	p 0 0 0
v f2 =
	p 4 0 0
v f3 =
	p 4 4 0
v f4 =
	p 0 4 0
v c1 =
	p 0 0 3
v c2 =
	p 4 0 3
v c3 =
	p 4 4 3
v c4 =
	p 0 4 3
m white
f f1 f2 f3 f4
f c4 c3 c2 c1
f f1 c1 c2 f2
f f2 c2 c3 f3
f f3 c3 c4 f4
f f4 c4 c1 f1
m grey
v s1 =
	p 1.5 2 0.5
v s2 =
	p 2.5 2 0.5
sph s1 0.5
sph s2 0.5
m lamp
v l1 =
	p 1.6 1.6 2.99
v l2 =
	p 2.4 1.6 2.99
v l3 =
	p 2.4 2.4 2.99
v l4 =
	p 1.6 2.4 2.99
f l1 l2 l3 l4
)";
  LoadOptions load;
  load.mgfDivisions = 64;
  const Result<Scene> scene = loadScene((dir / "spheres.mgf").string(), load);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto engine = testing::solved(*scene);
  ASSERT_TRUE(engine);
  const Vec3 top{1.5, 1, -2};  // the first sphere's top, in lambert's y-up frame (MGF (x, y, z) → (x, z, −y))
  double vertex = -1;
  for (const VertexSample& v : vertexSamples(engine->solution()))
    if (length(v.position - top) < 1e-6 && v.normal.y > 0.999) vertex = v.radiance.g / (0.5 / kPi);  // E = π L / ρ
  ASSERT_GE(vertex, 0) << "the sphere's top vertex";
  const std::vector<CalculationPoint> at = {{top, {0, 1, 0}}};
  const Result<std::vector<PointIrradiance>> metered = IlluminanceMeter(engine->solution()).measure(at);
  ASSERT_TRUE(metered.ok()) << metered.error().message;
  std::uint32_t sphere = 0;
  while (sphere < scene->surfaces.size() && std::fabs(length(scene->surfaces[sphere].vertices[0] - Vec3{1.5, 0.5, -2}) - 0.5) > 1e-6) ++sphere;
  ASSERT_LT(sphere, scene->surfaces.size());
  const ReferenceRenderer tracer(*scene, subdivideScene(*scene, 10.0), testing::quietReferenceOptions(16384));
  const double traced = tracer.irradianceAt(top, {0, 1, 0}, sphere, 1).g, meter = (*metered)[0].total().g;
  std::printf("sphere's top: traced %.5f, vertex %.5f (%+.1f%%), meter %.5f (%+.1f%%)\n", traced, vertex, 100 * (vertex / traced - 1),
              meter, 100 * (meter / traced - 1));
  EXPECT_LT(std::fabs(meter / traced - 1), 0.06);
  EXPECT_LT(std::fabs(vertex / traced - 1), 0.25);
}

// Tables under far luminaires: a receiving cluster holds a table's top (facing the lamps) and
// its underside (facing the black floor), and a link's K is the mean irradiance over both. Handed
// to every face alike, the tops got part of the lamps' light and the undersides the rest
// (RenderPark's classroom: desk tops 30% dark in the solve, the room's reflected light 11%
// short). The push now hands each face the light that fell on faces facing its way
// (hierarchical/transport.h, "directional push"). Everything but the tops is black or nearly
// (a ceiling of ρ 0.02), so the tops' radiosity is ρ × the strips' direct light, in closed form,
// and the light the point gather (the lightmaps' texels) finds at the ceiling is that radiosity
// integrated over the tops.
TEST(RealGeometryTest, TableTopsUnderFarLuminairesGetTheLightThatFallsOnThemNotOnTheirUndersides) {
  const double rho = 0.8, emitted = 40;
  Scene scene = testing::sceneOf({}, Rgb::gray(rho));
  scene.materials.push_back({"black", Rgb{}, false});
  scene.materials.push_back({"dim", Rgb::gray(0.02), false});
  const auto quad = [&](const char* name, std::vector<Vec3> corners, int material, const Vec3& outward, Rgb emission = {}) {
    Surface face{name, std::move(corners), material, emission};
    if (dot(surfaceNormal(face), outward) < 0) std::reverse(face.vertices.begin(), face.vertices.end());
    scene.surfaces.push_back(std::move(face));
  };
  const double half = 8, ceilingY = 3.2, lampY = 3.0, topY = 0.75;
  quad("floor", {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}}, 1, {0, 1, 0});
  quad("ceiling", {{-half, ceilingY, -half}, {half, ceilingY, -half}, {half, ceilingY, half}, {-half, ceilingY, half}}, 2, {0, -1, 0});
  std::vector<std::vector<Vec3>> strips, tops;
  for (const double cx : {-4.5, -1.5, 1.5, 4.5})
    for (const double cz : {-4.5, -1.5, 1.5, 4.5}) {
      // A 1.2 × 0.7 m table top 3 cm thick at 0.75 m, its top and underside reflecting, its rim black...
      const double x0 = cx - 0.6, x1 = cx + 0.6, z0 = cz - 0.35, z1 = cz + 0.35, y0 = topY - 0.03;
      tops.push_back({{x0, topY, z0}, {x1, topY, z0}, {x1, topY, z1}, {x0, topY, z1}});
      quad("top", tops.back(), 0, {0, 1, 0});
      quad("underside", {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}}, 0, {0, -1, 0});
      quad("rim", {{x0, y0, z0}, {x1, y0, z0}, {x1, topY, z0}, {x0, topY, z0}}, 1, {0, 0, -1});
      quad("rim", {{x0, y0, z1}, {x1, y0, z1}, {x1, topY, z1}, {x0, topY, z1}}, 1, {0, 0, 1});
      quad("rim", {{x0, y0, z0}, {x0, y0, z1}, {x0, topY, z1}, {x0, topY, z0}}, 1, {-1, 0, 0});
      quad("rim", {{x1, y0, z0}, {x1, y0, z1}, {x1, topY, z1}, {x1, topY, z0}}, 1, {1, 0, 0});
      // ...and over it, at 3 m, a 6 cm × 1.2 m strip emitting downward.
      strips.push_back({{cx - 0.03, lampY, cz - 0.6}, {cx + 0.03, lampY, cz - 0.6}, {cx + 0.03, lampY, cz + 0.6}, {cx - 0.03, lampY, cz + 0.6}});
      quad("strip", strips.back(), 1, {0, -1, 0}, Rgb::gray(emitted));
    }
  auto engine = testing::solved(scene);
  ASSERT_TRUE(engine);
  const SolutionView& solution = engine->solution();
  // The tops' radiosity in closed form, at midpoints of a 24 × 14 grid on each: nothing stands
  // between a top and the strips.
  const Vec3 up{0, 1, 0};
  const auto topRadiosity = [&](const Vec3& y) {
    double e = 0;
    for (const auto& strip : strips) e += emitted * kPi * pointToPolygonFormFactor(y, up, strip, {0, -1, 0});
    return rho * e;
  };
  struct Sample {
    Vec3 at;
    double radiosity, area;
  };
  std::vector<Sample> samples;
  const int nx = 24, nz = 14;
  for (const auto& top : tops)
    for (int i = 0; i < nx; ++i)
      for (int k = 0; k < nz; ++k) {
        const Vec3 y{top[0].x + 1.2 * (i + 0.5) / nx, topY, top[0].z + 0.7 * (k + 0.5) / nz};
        samples.push_back({y, topRadiosity(y), 1.2 * 0.7 / (nx * nz)});
      }
  double exactPower = 0, solvedPower = 0;
  for (const Sample& s : samples) exactPower += s.radiosity * s.area;
  const Mesh& mesh = solution.mesh();
  for (std::size_t p = 0; p < mesh.numPatches(); ++p)
    if (scene.surfaces[mesh.patches[p].surface].name == std::string("top")) solvedPower += solution.radiosity()[p].g * mesh.patches[p].area;
  std::printf("tables' tops: solved power %.4f W, closed form %.4f W (%+.1f%%)\n", solvedPower, exactPower, 100 * (solvedPower / exactPower - 1));
  EXPECT_NEAR(solvedPower / exactPower, 1, 0.05) << "the tops' radiosity in the solve (each link's K is a Monte Carlo estimate)";
  // The ceiling: the point gather against the tops' closed-form radiosity integrated over them,
  // with the strips' shadows by rays.
  std::vector<SurfacePoint> points;
  for (const double x : {-3.0, 0.0, 3.0})
    for (const double z : {-3.0, 0.0, 2.0}) points.push_back({{x, ceilingY, z}, {0, -1, 0}, 1});
  const Result<std::vector<Rgb>> gathered = solution.pointIrradiance(points);
  ASSERT_TRUE(gathered.ok()) << gathered.error().message;
  const RayCaster& caster = solution.caster();
  const double epsilon = rayEpsilon(mesh);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 x = points[i].point;
    double exact = 0;
    for (const Sample& s : samples) {
      const Vec3 d = s.at - x;
      if (caster.occluded(Ray{x + points[i].normal * epsilon, d - points[i].normal * (2 * epsilon), 0, 1})) continue;
      exact += s.radiosity * pointToPointKernel(x, points[i].normal, s.at, up) * s.area;
    }
    std::printf("ceiling at (%4.1f, %4.1f): point gather %.5f, closed form %.5f (%+.1f%%)\n", x.x, x.z, (*gathered)[i].g, exact,
                100 * ((*gathered)[i].g / exact - 1));
    EXPECT_NEAR((*gathered)[i].g / exact, 1, 0.06) << "the ceiling at (" << x.x << ", " << x.z << ")";
  }
}

// The sun through a skylight onto a floor, everything else black: a floor vertex in the sun reads
// ρ E⊥ cos θ / π, one in the shadow 0, in closed form. The light's edges split the leaves they
// cross (hierarchical/light_edges.h), judged at sample points; the vertices on a larger leaf's
// edge take the value interpolated along it (T-junction continuity), so a sun edge that crossed
// a leaf between its samples, unsplit, left a vertex in full sun at half or three quarters of
// it (a Blender-style room with a window: 99% of its vertices' error). The edges' midpoints are
// sampled too now.
TEST(RealGeometryTest, FloorVerticesInTheSunThroughASkylightShowTheSun) {
  Scene scene = testing::sceneOf({}, Rgb::gray(0.5));
  scene.materials.push_back({"black", Rgb{}, false});
  const double half = 3, roofY = 3, h0 = -0.7, h1 = 0.9;  // the skylight: x and z in [h0, h1]
  const auto quad = [&](const char* name, std::vector<Vec3> corners, int material, const Vec3& outward) {
    Surface face{name, std::move(corners), material, {}};
    if (dot(surfaceNormal(face), outward) < 0) std::reverse(face.vertices.begin(), face.vertices.end());
    scene.surfaces.push_back(std::move(face));
  };
  quad("floor", {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}}, 0, {0, 1, 0});
  // The roof around the skylight, black, facing the sun: its back, toward the floor, is opaque too.
  quad("roof", {{-half, roofY, -half}, {half, roofY, -half}, {half, roofY, h0}, {-half, roofY, h0}}, 1, {0, 1, 0});
  quad("roof", {{-half, roofY, h1}, {half, roofY, h1}, {half, roofY, half}, {-half, roofY, half}}, 1, {0, 1, 0});
  quad("roof", {{-half, roofY, h0}, {h0, roofY, h0}, {h0, roofY, h1}, {-half, roofY, h1}}, 1, {0, 1, 0});
  quad("roof", {{h1, roofY, h0}, {half, roofY, h0}, {half, roofY, h1}, {h1, roofY, h1}}, 1, {0, 1, 0});
  Light sun;
  sun.kind = LightKind::Directional;
  sun.direction = normalize(Vec3{0.31, -1, 0.17});  // the way the light travels: its edges cross the floor's leaves aslant
  sun.irradiance = Rgb::gray(100);
  scene.lights.push_back(sun);
  auto engine = testing::solved(scene);
  ASSERT_TRUE(engine);
  const RayCaster& caster = engine->solution().caster();
  const double epsilon = rayEpsilon(engine->solution().mesh());
  const double full = 0.5 * 100 * dot(Vec3{0, 1, 0}, -sun.direction) / kPi;
  int inSun = 0, wrong = 0;
  double worst = 0;
  for (const VertexSample& v : vertexSamples(engine->solution())) {
    if (std::fabs(v.position.y) > 1e-9 || v.normal.y < 0.99) continue;
    // Lit where the ray toward the sun, and the rays from points 1 cm around, all get out: the
    // vertices by an edge of the sun patch are left out.
    bool lit = true, shadowed = true;
    for (const Vec3& d : {Vec3{0, 0, 0}, Vec3{0.01, 0, 0}, Vec3{-0.01, 0, 0}, Vec3{0, 0, 0.01}, Vec3{0, 0, -0.01}}) {
      const bool open = !caster.occluded(Ray{v.position + d + Vec3{0, epsilon, 0}, -sun.direction * 10, 0, 1});
      lit = lit && open;
      shadowed = shadowed && !open;
    }
    if (!lit) continue;
    ++inSun;
    const double error = std::fabs(v.radiance.g / full - 1);
    worst = std::fmax(worst, error);
    wrong += error > 0.05;
  }
  std::printf("floor vertices in the sun: %d, off by more than 5%%: %d, the worst %.1f%%\n", inSun, wrong, 100 * worst);
  ASSERT_GT(inSun, 20);
  EXPECT_EQ(wrong, 0) << "floor vertices in full sun that do not show it";
}

}  // namespace
}  // namespace lambert
