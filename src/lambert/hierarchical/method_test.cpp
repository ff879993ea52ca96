// Hierarchical radiosity with clustering through the engine (hierarchical/method.h):
// closed forms (furnace, Howell's two-patch factors), energy balance, refinement behaviour,
// agreement with the flat method, clustering's link counts and crack-free vertex values.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <string>

#include "lambert/core/parallel.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/method.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/vertex_radiosity.h"
#include "lambert/reference/reference.h"
#include "lambert/render/rasterizer.h"
#include "lambert/render/solution_image.h"
#include "lambert/scene/builtin.h"
#include "lambert/solve/energy.h"
#include "lambert/hierarchical/transport.h"
#include "lambert/solve/solver.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

using testing::closedCornellBox;
using testing::closedCube;
using testing::relativeError;
using testing::solved;
using testing::sceneOf;

RadiosityOptions hierarchicalOptions(double linkError, SolverKind solver = SolverKind::GaussSeidel) {
  RadiosityOptions options = testing::quietOptions();
  options.hierarchical.links.linkError = linkError;
  options.solver = solver;
  options.tolerance = 1e-6;
  options.maxIterations = 10000;
  return options;
}

// A spot at `position` toward `toward` (normalised here), I in W/sr, its cone and falloff in degrees.
Light spotLight(const Vec3& position, const Vec3& toward, double intensity, double coneDegrees, double falloffDegrees) {
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = position;
  spot.direction = normalize(toward);
  spot.intensity = Rgb::gray(intensity);
  spot.coneAngleDegrees = coneDegrees;
  spot.falloffDegrees = falloffDegrees;
  return spot;
}

// Area-weighted mean of B over the elements of one surface.
Rgb surfaceMean(const SolutionView& view, std::uint32_t surface) {
  Rgb sum;
  double area = 0;
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const Patch& p = view.mesh().patches[i];
    if (p.surface != surface) continue;
    sum += view.radiosity()[i] * p.area;
    area += p.area;
  }
  return sum / area;
}

// A square's faces as an n×n grid of quads (one surface), counter-clockwise seen from `normal`.
Surface gridSurface(std::string name, Vec3 origin, Vec3 u, Vec3 v, int n, Rgb emittedRadiance = {}) {
  Surface s;
  s.name = std::move(name);
  s.emittedRadiance = emittedRadiance;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.vertices.push_back(origin + u * (double(i) / n) + v * (double(j) / n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
      s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return s;
}

// A closed unit box whose walls are n×n grids facing inward; the floor's centre emits.
Scene gridBox(int n) {
  Scene scene = sceneOf({gridSurface("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, n),
                         gridSurface("ceiling", {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, n),
                         gridSurface("x0", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, n),
                         gridSurface("x1", {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, n),
                         gridSurface("z0", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n),
                         gridSurface("z1", {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, n),
                         gridSurface("lamp", {0.4, 0.999, 0.4}, {0.2, 0, 0}, {0, 0, 0.2}, 2, Rgb::gray(1))});
  return scene;
}

TEST(HierarchicalTest, FurnaceIsUniformAtEmissionOverOneMinusAlbedo) {
  // Every face emits E = π and reflects ρ = 0.5 of what it receives: B = E / (1 − ρ) everywhere,
  // in the mean and in every element. An element whose links sit at different levels of its
  // ancestors takes their mean factors for its own, which the oracle bounds per link: at link
  // error 3e-5 every element is within 1% (measured 0.7%; 2.6% at 1e-3).
  const Scene scene = closedCube(1, Rgb::gray(1), Rgb::gray(0.5));
  auto engine = solved(scene, hierarchicalOptions(3e-5));
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  const double expected = kPi / (1 - 0.5);
  EXPECT_GT(view.mesh().numPatches(), 6u);  // the links split the faces
  double sum = 0, area = 0;
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    ASSERT_LT(relativeError(view.radiosity()[i].g, expected), 0.01) << "element " << i;
    sum += view.radiosity()[i].g * view.mesh().patches[i].area;
    area += view.mesh().patches[i].area;
  }
  EXPECT_LT(relativeError(sum / area, expected), 0.01);
}

// A closed room whose every face is two-sided, as Blender exports them, lit by a two-sided
// panel across its middle: each room face has an outer twin no light reaches (its outer shell,
// geometry/enclosures.h). Every surface reflects ρ = 0.5 and no light escapes, so what leaves
// the surfaces in all is exactly Φ / (1 − ρ), Φ the panel's power from both its sides. The first
// pass's estimate once lit the outer shell like the room side: cluster links drew half their
// source samples from it and kept half their K, and a Blender room lost 37% of its power.
TEST(HierarchicalTest, ATwoSidedClosedRoomLitInClustersKeepsItsPower) {
  const double lampRadiance = 4;
  Scene scene = sceneOf({gridSurface("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 6),
                         gridSurface("ceiling", {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 6),
                         gridSurface("x0", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 6),
                         gridSurface("x1", {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 6),
                         gridSurface("z0", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 6),
                         gridSurface("z1", {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, 6),
                         gridSurface("panel", {0.4, 0.5, 0.4}, {0.2, 0, 0}, {0, 0, 0.2}, 2, Rgb::gray(lampRadiance))});
  scene.materials[0].twoSided = true;
  addTwins(scene);
  const double power = 2 * kPi * lampRadiance * 0.2 * 0.2;  // both sides emit
  for (bool clusters : {true, false}) {
    RadiosityOptions options = testing::quietOptions();
    options.hierarchical.links.clusters = clusters;
    auto engine = solved(scene, options);
    ASSERT_TRUE(engine);
    const SolutionView& view = engine->solution();
    double leaving = 0;
    for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) leaving += view.radiosity()[i].g * view.mesh().patches[i].area;
    std::printf("clusters %d: leaving %.4f W, exact %.4f W\n", clusters, leaving, power / (1 - 0.5));
    EXPECT_LT(relativeError(leaving, power / (1 - 0.5)), 0.03) << (clusters ? "clustered" : "unclustered");
  }
}

// Three 0.4 m blocks on the floor of a 4 × 2.5 × 3 m room, lit by a 1.0 × 0.6 m panel hung 0.3 m
// under the ceiling, from under the panel to the far wall: one cluster link brings the panel's
// light to the blocks, and its visibility is the mean over its receivers'. A vertex of a block's
// top sees the whole panel: taken at that mean, the tops' centres showed 6.1–10.0% less than the
// unclustered solve's, whose element links resolve it (the two-sided Blender room of
// tests/blender_lights_test.py 13–20% less than Cycles). The gather resolves such clusters'
// visibility at the vertices where they bring most (final_gather.cpp, resolveClusters): now
// 2.3–3.1% less.
TEST(HierarchicalTest, BlocksLitThroughOneClusterLinkShowThePanelAtTheirTopsVertices) {
  std::vector<Surface> surfaces = {gridSurface("floor", {-2, 0, -1.5}, {0, 0, 3}, {4, 0, 0}, 12),
                                   gridSurface("ceiling", {-2, 2.5, -1.5}, {4, 0, 0}, {0, 0, 3}, 12),
                                   gridSurface("x0", {-2, 0, -1.5}, {0, 2.5, 0}, {0, 0, 3}, 12),
                                   gridSurface("x1", {2, 0, -1.5}, {0, 0, 3}, {0, 2.5, 0}, 12),
                                   gridSurface("z0", {-2, 0, -1.5}, {4, 0, 0}, {0, 2.5, 0}, 12),
                                   gridSurface("z1", {-2, 0, 1.5}, {0, 2.5, 0}, {4, 0, 0}, 12),
                                   gridSurface("panel", {-1.5, 2.2, -0.1}, {1, 0, 0}, {0, 0, 0.6}, 1, Rgb::gray(20))};
  const double blockX[3] = {-1.2, -0.2, 0.8};
  std::uint32_t tops[3];
  for (int b = 0; b < 3; ++b) {
    const double x = blockX[b];
    tops[b] = static_cast<std::uint32_t>(surfaces.size());
    surfaces.push_back(gridSurface("top", {x - 0.2, 0.4, -0.2}, {0, 0, 0.4}, {0.4, 0, 0}, 4));
    surfaces.push_back(gridSurface("+x", {x + 0.2, 0, -0.2}, {0, 0.4, 0}, {0, 0, 0.4}, 4));
    surfaces.push_back(gridSurface("-x", {x - 0.2, 0, -0.2}, {0, 0, 0.4}, {0, 0.4, 0}, 4));
    surfaces.push_back(gridSurface("+z", {x - 0.2, 0, 0.2}, {0.4, 0, 0}, {0, 0.4, 0}, 4));
    surfaces.push_back(gridSurface("-z", {x - 0.2, 0, -0.2}, {0, 0.4, 0}, {0.4, 0, 0}, 4));
  }
  const Scene scene = sceneOf(std::move(surfaces), Rgb::gray(0.7));
  double top[2][3];
  for (const bool clusters : {true, false}) {
    RadiosityOptions options = hierarchicalOptions(LinkOptions{}.linkError);
    options.hierarchical.links.clusters = clusters;
    auto engine = solved(scene, options);
    ASSERT_TRUE(engine);
    const SolutionView view = engine->solution();
    const std::vector<Rgb> radiosity = view.vertexValues(VertexQuantity::Radiosity);
    for (int b = 0; b < 3; ++b) {
      top[clusters][b] = -1;
      for (std::size_t v = 0; v < view.mesh().numVertices(); ++v)
        if (view.mesh().vertexSurface[v] == tops[b] && length(view.mesh().positions[v] - Vec3{blockX[b], 0.4, 0}) < 1e-9)
          top[clusters][b] = radiosity[v].g;
      ASSERT_GT(top[clusters][b], 0) << "no vertex at the centre of block " << b << "'s top";
    }
  }
  for (int b = 0; b < 3; ++b) {
    std::printf("block %d's top: %.4f clustered, %.4f unclustered (%+.1f%%)\n", b, top[1][b], top[0][b], 100 * (top[1][b] / top[0][b] - 1));
    EXPECT_LT(relativeError(top[1][b], top[0][b]), 0.045) << "block " << b;
  }
}

TEST(HierarchicalTest, HowellTwoPatchFactorsThroughTheSolver) {
  // Square a emits E = π (L_e = 1) and is black, so its radiosity is E everywhere; square b
  // reflects ρ = 0.5 of what it receives: its mean radiosity is exactly ρ F_ba E.
  struct Case {
    Scene scene;
    double formFactor;
  };
  Case cases[] = {{testing::parallelSquares(), 0.19982}, {testing::perpendicularSquares(), 0.20004}};
  for (Case& c : cases) {
    c.scene.materials.push_back({"black", Rgb::gray(0)});
    c.scene.surfaces[0].material = 1;
    c.scene.surfaces[0].emittedRadiance = Rgb::gray(1);
    auto engine = solved(c.scene, hierarchicalOptions(1e-4));
    ASSERT_TRUE(engine);
    const double expected = 0.5 * c.formFactor * kPi;
    EXPECT_LT(relativeError(surfaceMean(engine->solution(), 1).g, expected), 0.01) << c.scene.surfaces[1].name;
  }
}

TEST(HierarchicalTest, ClosedCornellBoxAbsorbsWhatItEmits) {
  // A closed box absorbs all it emits (the black portal absorbs what an open box lets out), so
  // the power absorbed, Σ A (1 − ρ) H over the solution's gathered irradiance, must be the power
  // emitted: a solve that stopped a bounce short, or links that lose or double light, fail.
  // Within 1% at the default link error (measured 0.29% short; the flat method with 3000
  // patches loses 0.5%). Nothing escapes: what leaves the surfaces arrives at them.
  auto engine = solved(closedCornellBox(), hierarchicalOptions(2e-4));
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  EnergyBalance balance = energyBalance(radiosityProblem(view), view.radiosity(), view.scene().metresPerUnit);
  // 130 mm × 105 mm emitting π·(17 + 12 + 4) W/m² (the scene's lamp).
  EXPECT_NEAR(balance.emittedWatts, 0.130 * 0.105 * kPi * (0.2126 * 17 + 0.7152 * 12 + 0.0722 * 4), 1e-9);  // in watts of luminance
  std::printf("absorbed %.4f, escaped %.4f of the emitted power\n", balance.absorbedWatts / balance.emittedWatts,
              balance.escapedWatts / balance.emittedWatts);
  EXPECT_LT(relativeError(balance.absorbedWatts, balance.emittedWatts), 0.01);
  EXPECT_LT(std::fabs(balance.escapedWatts / balance.emittedWatts), 0.01);
}

TEST(HierarchicalTest, EmitterOverAPlateAbsorbsAndLetsOutTheClosedForm) {
  // An open scene whose absorbed and escaped power are known in closed form (tests/support/
  // scenes.h): a black emitter over a grey plate. The plate's share is 83% of what is absorbed,
  // the light it sends back to the emitter 17% (ρ = 0.5): a solve without that second bounce,
  // an emitter whose absorption is not counted, or escaped power counted twice, all miss by more
  // than 10%. Both within 2% at link error 1e-4 (the Howell test's setting, where the plate's
  // mean is within 1%; the second term is the first's 1/5 and rides on the same links).
  const testing::EnergyBalanceWatts exact = testing::emitterOverPlateBalance(0.5);
  auto engine = solved(testing::emitterOverPlate(0.5), hierarchicalOptions(1e-4));
  ASSERT_TRUE(engine);
  const Stats stats = engine->stats();
  const auto watts = [&](const char* key) { return std::get<double>(stats.find(key)->value); };
  std::printf("absorbed %.5f W (exact %.5f), escaped %.5f W (exact %.5f)\n", watts("absorbed_watts"), exact.absorbed,
              watts("escaped_watts"), exact.escaped);
  EXPECT_LT(relativeError(watts("emitted_watts"), exact.emitted), 1e-9);
  EXPECT_LT(relativeError(watts("absorbed_watts"), exact.absorbed), 0.02);
  EXPECT_LT(relativeError(watts("escaped_watts"), exact.escaped), 0.02 * exact.absorbed / exact.escaped);
}

TEST(HierarchicalTest, FinalGatherGivesTheExactPointIrradianceAtEveryVertex) {
  // A black square emitting E = π (L_e = 1) above a grey one, one element each (the minimum
  // area forbids splitting): the receiver's element value is ρ·F·E with F its mean factor, but
  // at a vertex the final gather must give ρ·F(x)·E with F(x) the exact point-to-polygon factor
  // there: 0.1385 at a corner against a mean of 0.1998, so interpolating would miss by 44%.
  Scene scene = testing::parallelSquares();
  scene.materials.push_back({"black", Rgb::gray(0)});
  scene.surfaces[1].material = 1;
  scene.surfaces[1].emittedRadiance = Rgb::gray(1);
  RadiosityOptions options = hierarchicalOptions(1e-4);
  options.hierarchical.links.minElementArea = 10;
  auto engine = solved(scene, options);
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  ASSERT_EQ(view.mesh().numPatches(), 2u);
  const Mesh& mesh = view.vertexMesh();
  const std::vector<Vec3> top = scene.surfaces[1].vertices;
  const std::vector<Rgb> radiosity = view.vertexValues(VertexQuantity::Radiosity);
  const std::vector<Rgb> irradiance = view.vertexValues(VertexQuantity::Irradiance);
  std::size_t checked = 0;
  for (std::uint32_t v = 0; v < mesh.numVertices(); ++v) {
    if (mesh.vertexSurface[v] != 0) continue;
    const double pointFactor = pointToPolygonFormFactor(mesh.positions[v], {0, 0, 1}, top, {0, 0, -1});
    EXPECT_LT(relativeError(irradiance[v].g, kPi * pointFactor), 2e-3) << "vertex " << v;
    EXPECT_LT(relativeError(radiosity[v].g, 0.5 * kPi * pointFactor), 2e-3) << "vertex " << v;
    ++checked;
  }
  EXPECT_EQ(checked, 4u);
  EXPECT_LT(relativeError(view.radiosity()[0].g, 0.5 * kPi * 0.19982), 0.01);  // the element keeps its mean
}

TEST(HierarchicalTest, AVertexSeesTheLampThroughAGapThatItsElementsRaysMissed) {
  // A unit floor (one element: the minimum area forbids splitting), a black lamp of L_e = 1 one
  // above it, and a black plate half way up covering x < 0.9: of the rays between the floor and
  // the lamp only those crossing the gap get through, too few for the link's 8 to find any
  // (the link is judged occluded). Yet the floor's vertices at x = 1 see the lamp's strip
  // x > 0.8 through the gap. The gather must find that light at those vertices and none at
  // x = 0: dropping the occluded link gave them nothing, and counting the share of the lamp's
  // area in view instead of weighting the rays by the kernel gave them 60% too little.
  Scene scene = testing::parallelSquares();
  scene.materials.push_back({"black", Rgb::gray(0)});
  scene.surfaces[1].material = 1;
  scene.surfaces[1].emittedRadiance = Rgb::gray(1);
  scene.surfaces.push_back({"plate", {{-0.5, -0.5, 0.5}, {0.9, -0.5, 0.5}, {0.9, 1.5, 0.5}, {-0.5, 1.5, 0.5}}, 1, {}});
  RadiosityOptions options = hierarchicalOptions(1e-4);
  options.hierarchical.links.minElementArea = 10;
  options.hierarchical.links.clusters = false;
  auto engine = solved(scene, options);
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  const Mesh& mesh = view.vertexMesh();
  const std::vector<Vec3> strip = {{0.8, 0, 1}, {0.8, 1, 1}, {1, 1, 1}, {1, 0, 1}};
  const std::vector<Rgb> irradiance = view.vertexValues(VertexQuantity::Irradiance);
  std::size_t lit = 0, dark = 0;
  for (std::uint32_t v = 0; v < mesh.numVertices(); ++v) {
    if (mesh.vertexSurface[v] != 0) continue;
    if (mesh.positions[v].x > 0.5) {
      // Exactly the strip is in view: π·L_e·F(x → strip) = 0.126 W/m² at (1, 0) and (1, 1);
      // measured 13% and 7% off (32 rays each: the first 8 disagree).
      const double expected = kPi * pointToPolygonFormFactor(mesh.positions[v], {0, 0, 1}, strip, {0, 0, -1});
      EXPECT_LT(relativeError(irradiance[v].g, expected), 0.25) << "vertex " << v << " gathers " << irradiance[v].g << " expected " << expected;
      ++lit;
    } else {
      EXPECT_LT(irradiance[v].g, 1e-6) << "vertex " << v;
      ++dark;
    }
  }
  EXPECT_EQ(lit, 2u);
  EXPECT_EQ(dark, 2u);
}

TEST(HierarchicalTest, FinalGatherOpensASourceSeenFromCloseBy) {
  // A wall meeting a floor; the wall is split once into four elements of radiosity 0, 1, 3 and
  // 8 W/m², and the floor links to it as one element (their mean, 3 W/m²). Every floor vertex is
  // closer to the wall than twice its bounding radius, so the gather must take the children:
  // the irradiance is exactly Σ_c B_c F(x → c). The wall's mean is 8% off or more at each.
  const Scene scene = testing::perpendicularSquares();
  ElementHierarchy hierarchy(scene);
  std::uint32_t floor = kNoNode, wall = kNoNode;
  for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
    const HierarchyNode& n = hierarchy.node(i);
    if (!n.isCluster() && hierarchy.node(n.parent).isCluster()) (n.surface == 0 ? floor : wall) = i;
  }
  ASSERT_TRUE(floor != kNoNode && wall != kNoNode);
  hierarchy.split(wall);
  hierarchy.numberLeaves();
  const ElementHierarchy::LeafMesh leaves = hierarchy.leaves(scene);
  Links links;
  links.start.assign(hierarchy.nodes().size() + 1, 0);
  for (std::size_t i = floor + 1; i < links.start.size(); ++i) links.start[i] = 1;
  links.source = {wall};
  links.formFactor = {0.2f};
  links.uncertainty = {0.01f};
  links.receiverSide = {1};  // every ray got through
  auto caster = makeEmbreeRayCaster(leaves.mesh);
  const FinalGather gather(hierarchy, leaves, links, *caster, rayEpsilon(leaves.mesh), 1e-4, 8, 1);
  std::vector<Rgb> mean(hierarchy.nodes().size());
  const double childRadiosity[] = {0, 1, 3, 8};
  const std::span<const std::uint32_t> kids = hierarchy.children(wall);
  ASSERT_EQ(kids.size(), 4u);
  for (std::size_t c = 0; c < 4; ++c) mean[kids[c]] = Rgb::gray(childRadiosity[c]);
  mean[wall] = Rgb::gray(3);
  const std::vector<Rgb> irradiance = gather.irradiance(mean);
  std::size_t checked = 0;
  double meanMisses = INFINITY;
  for (std::uint32_t v = 0; v < leaves.mesh.numVertices(); ++v) {
    if (leaves.mesh.vertexSurface[v] != 0) continue;
    const VertexSite& site = gather.sites()[v];
    double expected = 0;
    for (std::size_t c = 0; c < 4; ++c) {
      const HierarchyNode& child = hierarchy.node(kids[c]);
      expected += childRadiosity[c] * pointToPolygonFormFactor(site.point, site.normal, child.polygon(), child.normal);
    }
    const HierarchyNode& w = hierarchy.node(wall);
    const double fromMean = 3 * pointToPolygonFormFactor(site.point, site.normal, w.polygon(), w.normal);
    meanMisses = std::fmin(meanMisses, relativeError(fromMean, expected));
    EXPECT_LT(relativeError(irradiance[v].g, expected), 1e-6) << "vertex " << v;
    ++checked;
  }
  EXPECT_EQ(checked, 4u);
  EXPECT_GT(meanMisses, 0.05);  // the test tells the two apart
}

TEST(HierarchicalTest, FinalGatherOpensLongThinSourcesOnlyWhereTheyVary) {
  // A luminaire's 1.2 m lamp strip (2 cm wide, uniform 10 W/m², facing down) between two
  // reflector strips flaring up from it (4 cm × √2 wide, radiosity rising along their length),
  // 5 cm above a floor, each split four levels into slivers 7.5 cm × 1–3.5 mm. Every sliver's
  // bounding sphere is long for its area, so the sphere rule alone takes every floor vertex
  // down to the leaves of all three (with visibility rays to each). The strip is uniform and
  // nothing occludes it, and the reflectors vary only along their length: the gather must stay
  // within 0.5% of the exact Σ_leaves B·F(x → leaf) with far fewer sources.
  const double h = 0.05;
  Scene scene = sceneOf({gridSurface("floor", {-0.7, 0, -0.05}, {0, 0, 0.1}, {1.4, 0, 0}, 4),
                         gridSurface("strip", {-0.6, h, -0.01}, {1.2, 0, 0}, {0, 0, 0.02}, 1),
                         gridSurface("reflector+", {-0.6, h, 0.03}, {1.2, 0, 0}, {0, 0.04, 0.04}, 1),
                         gridSurface("reflector-", {-0.6, h + 0.04, -0.07}, {1.2, 0, 0}, {0, -0.04, 0.04}, 1)});
  ElementHierarchy hierarchy(scene);
  std::vector<std::uint32_t> floorFaces, sources;
  for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
    const HierarchyNode& n = hierarchy.node(i);
    if (n.isCluster() || !hierarchy.node(n.parent).isCluster()) continue;
    (n.surface == 0 ? floorFaces : sources).push_back(i);
  }
  ASSERT_EQ(floorFaces.size(), 16u);
  ASSERT_EQ(sources.size(), 3u);
  std::vector<std::uint32_t> level = sources;
  for (int depth = 0; depth < 4; ++depth) {
    std::vector<std::uint32_t> next;
    for (std::uint32_t e : level) {
      hierarchy.split(e);
      for (std::uint32_t c : hierarchy.children(e)) next.push_back(c);
    }
    level = std::move(next);
  }
  hierarchy.numberLeaves();
  const ElementHierarchy::LeafMesh leaves = hierarchy.leaves(scene);
  // Each floor face gathers from the three strips; the links say some rays were blocked, so
  // the gather casts its own.
  Links links;
  links.start.assign(hierarchy.nodes().size() + 1, 0);
  for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
    const bool receiver = std::find(floorFaces.begin(), floorFaces.end(), i) != floorFaces.end();
    links.start[i + 1] = links.start[i] + (receiver ? 3 : 0);
    if (!receiver) continue;
    for (std::uint32_t s : sources) {
      links.source.push_back(s);
      links.formFactor.push_back(0.1f);
      links.uncertainty.push_back(0.1f);
      links.receiverSide.push_back(0);
      links.facing.push_back({});
    }
  }
  // Leaf radiosities, then every node's area-weighted mean (what HierarchicalTransport::pull gives).
  std::vector<Rgb> mean(hierarchy.nodes().size());
  for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
    const HierarchyNode& n = hierarchy.node(i);
    if (n.isLeaf() && !n.isCluster() && n.surface == 1) mean[i] = Rgb::gray(10);
    if (n.isLeaf() && !n.isCluster() && n.surface >= 2) mean[i] = Rgb::gray(0.2 + 0.6 * (n.centre.x + 0.6) / 1.2);
  }
  for (std::size_t i = hierarchy.nodes().size(); i-- > 0;) {
    const std::uint32_t n = static_cast<std::uint32_t>(i);
    if (hierarchy.node(n).isLeaf()) continue;
    Rgb sum;
    double area = 0;
    for (std::uint32_t c : hierarchy.children(n)) {
      sum += mean[c] * hierarchy.node(c).area;
      area += hierarchy.node(c).area;
    }
    mean[n] = area > 0 ? sum / area : Rgb{};
  }
  auto caster = makeEmbreeRayCaster(leaves.mesh);
  const FinalGather gather(hierarchy, leaves, links, *caster, rayEpsilon(leaves.mesh), 1e-4, 8, 1);
  FinalGatherCounts counts;
  const std::vector<Rgb> irradiance = gather.irradiance(mean, &counts);
  std::size_t checked = 0;
  for (std::uint32_t v = 0; v < leaves.mesh.numVertices(); ++v) {
    if (leaves.mesh.vertexSurface[v] != 0) continue;
    const VertexSite& site = gather.sites()[v];
    double exact = 0;  // nothing stands between the floor and the strips' fronts
    for (std::uint32_t l : hierarchy.leafNodes()) {
      const HierarchyNode& n = hierarchy.node(l);
      if (n.surface != 0) exact += mean[l].g * pointToPolygonFormFactor(site.point, site.normal, n.polygon(), n.normal);
    }
    ASSERT_GT(exact, 0);
    EXPECT_LT(relativeError(irradiance[v].g, exact), 5e-3) << "floor vertex " << v;
    ++checked;
  }
  EXPECT_EQ(checked, 25u);
  // The sphere rule alone gathers 168 sources per floor vertex and casts 1337 rays there
  // (measured); this gather 44 and 343.
  ASSERT_EQ(counts.vertices, leaves.mesh.numVertices());
  const double floorVertices = 25, perFloorVertex = static_cast<double>(counts.sourcesGathered) / floorVertices;
  std::printf("per floor vertex: %.1f sources gathered, %.1f opened, %.1f visibility rays\n", perFloorVertex,
              static_cast<double>(counts.sourcesOpened) / floorVertices, static_cast<double>(counts.visibilityRays) / floorVertices);
  EXPECT_LT(perFloorVertex, 80);
  EXPECT_LT(static_cast<double>(counts.visibilityRays) / floorVertices, 640);
}

TEST(HierarchicalTest, PartlyCoveredLeavesShowTheLightOfTheirOpenPart) {
  // A link's factor is a mean over its receiver, where the part under a block gets nothing;
  // what it gathers falls on the open part. A floor leaf straddling a block's base must show
  // (B / open fraction) the floor's light next to the block, never more than the brightest
  // open floor leaf. Pushed as a plain mean, such leaves showed up to 30 times as much.
  auto engine = solved(cornellBox(), hierarchicalOptions(2e-4));
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  double brightestOpen = 0;
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const Patch& p = view.mesh().patches[i];
    if (p.surface == 0 && p.openFraction == 1) brightestOpen = std::fmax(brightestOpen, view.radiosity()[i].maxComponent());
  }
  std::size_t straddling = 0;
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const Patch& p = view.mesh().patches[i];
    if (p.surface != 0 || p.openFraction == 1 || p.openFraction == 0) continue;
    ++straddling;
    EXPECT_LE(view.radiosity()[i].maxComponent() / p.openFraction, 1.05 * brightestOpen)
        << "floor leaf " << i << ", open fraction " << p.openFraction;
  }
  EXPECT_GT(straddling, 20u);
}

TEST(HierarchicalTest, JacobiAndGaussSeidelReachTheSameSolution) {
  auto gs = solved(testing::closedCornellBox(), hierarchicalOptions(1e-3, SolverKind::GaussSeidel));
  auto jacobi = solved(testing::closedCornellBox(), hierarchicalOptions(1e-3, SolverKind::Jacobi));
  ASSERT_TRUE(gs && jacobi);
  const auto& a = gs->solution().radiosity();
  const auto& b = jacobi->solution().radiosity();
  ASSERT_EQ(a.size(), b.size());
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    scale = std::fmax(scale, a[i].maxComponent());
    worst = std::fmax(worst, std::fabs(a[i].g - b[i].g));
  }
  EXPECT_LT(worst / scale, 1e-4);
}

// Exact form factors between axis-aligned rectangles (Ehlert & Smith 1993, from Howell's
// catalogue by form-factor algebra): A_1 F_12 = Σ_{ijkl} (−1)^{i+j+k+l} G(…) over the rectangles'
// corner coordinates. Parallel rectangles c apart, x and y along the planes:
//   G = 1/2π [x √(y²+c²) atan(x/√(y²+c²)) + y √(x²+c²) atan(y/√(x²+c²)) − c²/2 ln(x²+y²+c²)];
// perpendicular ones, x along their planes' common line and y, η the distances from it:
//   G = 1/2π [x r atan(x/r) − ¼ (r² − x²) ln(r² + x²)],  r² = y² + η².
// (Both give Howell's unit squares, 0.199825 and 0.200044.)
double parallelG(double x, double y, double c) {
  const double ry = std::sqrt(y * y + c * c), rx = std::sqrt(x * x + c * c), s = x * x + y * y + c * c;
  double g = 0;
  if (ry > 0) g += x * ry * std::atan(x / ry);
  if (rx > 0) g += y * rx * std::atan(y / rx);
  if (s > 0) g -= c * c / 2 * std::log(s);
  return g / (2 * kPi);
}
double perpendicularG(double x, double y, double eta) {
  const double r2 = y * y + eta * eta, s = r2 + x * x;
  double g = 0;
  if (r2 > 0) g += x * std::sqrt(r2) * std::atan(x / std::sqrt(r2));
  if (s > 0) g -= 0.25 * (r2 - x * x) * std::log(s);
  return g / (2 * kPi);
}

// A cell of an axis-aligned closed box: the plane axis = at, spanning [lo, hi] along the other two
// axes (in increasing axis order).
struct BoxCell {
  int axis;
  double at;
  double lo[2], hi[2];
  std::uint32_t surface;
  double area() const { return (hi[0] - lo[0]) * (hi[1] - lo[1]); }
};

// A_a F_ab between cells of a box's different faces (each sees the other whole from inside).
double exchangeArea(const BoxCell& a, const BoxCell& b) {
  const auto other = [](int axis, int k) { return k == 0 ? (axis == 0 ? 1 : 0) : (axis == 2 ? 1 : 2); };
  double sum = 0;
  if (a.axis == b.axis) {
    const double c = std::fabs(a.at - b.at);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k)
          for (int l = 0; l < 2; ++l) {
            const double x = (i ? a.hi[0] : a.lo[0]) - (k ? b.hi[0] : b.lo[0]), y = (j ? a.hi[1] : a.lo[1]) - (l ? b.hi[1] : b.lo[1]);
            sum += ((i + j + k + l) % 2 ? -1 : 1) * parallelG(x, y, c);
          }
    return sum;
  }
  // The common line runs along the third axis t, at a's plane coordinate in b and b's in a.
  const int t = 3 - a.axis - b.axis;
  const int aT = other(a.axis, 0) == t ? 0 : 1, bT = other(b.axis, 0) == t ? 0 : 1;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k)
        for (int l = 0; l < 2; ++l) {
          const double x = (i ? a.hi[aT] : a.lo[aT]) - (k ? b.hi[bT] : b.lo[bT]);
          const double y = std::fabs((j ? a.hi[1 - aT] : a.lo[1 - aT]) - b.at), eta = std::fabs((l ? b.hi[1 - bT] : b.lo[1 - bT]) - a.at);
          sum += ((i + j + k + l) % 2 ? -1 : 1) * perpendicularG(x, y, eta);
        }
  return std::fabs(sum);
}

// The unit box of LinkErrorRoom, each face cut into n × n cells (n a multiple of 5, so that the
// lamp's square [0.4, 0.6]² in the ceiling is whole cells), solved by Galerkin's method with
// the exact factors above (piecewise-constant B; nothing is occluded in an empty box, so the
// only error is the piecewise-constant approximation, O(1/n²) in a surface's mean): per surface,
// the area-weighted mean radiosity.
std::vector<double> exactBoxSurfaceMeans(int n, const std::vector<double>& albedo, double lampExitance) {
  // Surfaces in LinkErrorRoom's order: floor, ceiling, x0, x1, z0, z1, lamp.
  std::vector<BoxCell> cells;
  const int faceAxis[6] = {1, 1, 0, 0, 2, 2};
  const double faceAt[6] = {0, 1, 0, 1, 0, 1};
  for (std::uint32_t f = 0; f < 6; ++f)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        BoxCell cell{faceAxis[f], faceAt[f], {double(i) / n, double(j) / n}, {double(i + 1) / n, double(j + 1) / n}, f};
        const double cx = (i + 0.5) / n, cz = (j + 0.5) / n;
        if (f == 1 && cx > 0.4 && cx < 0.6 && cz > 0.4 && cz < 0.6) cell.surface = 6;
        cells.push_back(cell);
      }
  const std::size_t m = cells.size();
  std::vector<double> F(m * m, 0.0);  // F[i m + j] = F_ij, reciprocity exact: A_i F_ij = A_j F_ji
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j) {
      if (cells[i].axis == cells[j].axis && cells[i].at == cells[j].at) continue;
      const double exchange = exchangeArea(cells[i], cells[j]);
      F[i * m + j] = exchange / cells[i].area();
      F[j * m + i] = exchange / cells[j].area();
    }
  std::vector<double> B(m, 0.0);
  for (int sweep = 0; sweep < 200; ++sweep)  // Gauss–Seidel; ρ ≤ 0.8, so 200 sweeps reach 1e-15
    for (std::size_t i = 0; i < m; ++i) {
      double gathered = 0;
      for (std::size_t j = 0; j < m; ++j) gathered += F[i * m + j] * B[j];
      B[i] = (cells[i].surface == 6 ? lampExitance : 0) + albedo[cells[i].surface] * gathered;
    }
  std::vector<double> sum(7, 0.0), area(7, 0.0);
  for (std::size_t i = 0; i < m; ++i) sum[cells[i].surface] += B[i] * cells[i].area(), area[cells[i].surface] += cells[i].area();
  for (std::size_t s = 0; s < 7; ++s) sum[s] /= area[s];
  return sum;
}

// A closed unit box, each face of different albedo, 5 × 5 faces each, with a lamp of one face
// (L_e = 1) in the middle of the ceiling.
Scene linkErrorRoom(const std::vector<double>& albedo) {
  Surface ceiling = gridSurface("ceiling", {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 5);
  ceiling.faces.erase(ceiling.faces.begin() + 2 * 5 + 2);  // the lamp's place
  Scene scene = sceneOf({gridSurface("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 5), ceiling,
                         gridSurface("x0", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 5), gridSurface("x1", {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 5),
                         gridSurface("z0", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 5), gridSurface("z1", {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, 5),
                         gridSurface("lamp", {0.4, 1, 0.4}, {0.2, 0, 0}, {0, 0, 0.2}, 1, Rgb::gray(1))});
  scene.materials.clear();
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    scene.materials.push_back({scene.surfaces[s].name, Rgb::gray(albedo[s])});
    scene.surfaces[s].material = static_cast<int>(s);
  }
  return scene;
}

// A vertex beside a room's edge sees the adjacent surface's strip along the edge with about half
// its hemisphere, and that strip is far darker than the leaf it lies in. Gathered with the leaves'
// means, the Cornell box's ceiling and back-wall vertices within 2 units of their shared edge were
// 16.9% too bright on average against the path tracer traced at the same sites (up to +80% at
// single vertices); with each close leaf's radiosity interpolated from its corners
// (FinalGather::coupleNearField) they measure −2.9%, about the box's 1.5–2.5% darkness away from
// its edges (docs/hierarchical.md), and must stay within 5%.
TEST(HierarchicalTest, TheGatherMatchesThePathTracerAlongTheCornellBoxsCeilingEdge) {
  const Scene scene = cornellBox();
  auto engine = solved(scene, hierarchicalOptions(LinkOptions{}.linkError));
  ASSERT_TRUE(engine);
  const SolutionView view = engine->solution();
  const Mesh& mesh = view.vertexMesh();
  const std::vector<Rgb> radiance = view.vertexRadiance();
  const double diagonal = sceneDiagonal(scene);
  const std::vector<VertexSite> sites = vertexSites(mesh, 1e-4 * diagonal);
  std::vector<std::size_t> edge;
  for (std::size_t v = 0; v < mesh.numVertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    const bool ceiling = mesh.vertexSurface[v] == 1 && p.z > 559.2 - 2, backWall = mesh.vertexSurface[v] == 2 && p.y > 548.8 - 2;
    if ((ceiling || backWall) && p.x > 20 && p.x < 530) edge.push_back(v);
  }
  ASSERT_GE(edge.size(), 20u);
  ReferenceOptions traceOptions;
  traceOptions.vertexSamples = 4096;
  traceOptions.showProgress = false;
  const ReferenceRenderer tracer(scene, subdivideScene(scene, 2 * diagonal), traceOptions);
  const auto luminance = [](const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  std::vector<double> traced(edge.size());
  parallelFor(0, edge.size(), [&](std::size_t i) {
    const std::size_t v = edge[i];
    traced[i] = luminance(tracer.outgoingRadiance(sites[v].point, sites[v].normal, mesh.vertexSurface[v], v));
  });
  double bias = 0;
  for (std::size_t i = 0; i < edge.size(); ++i) bias += (luminance(radiance[edge[i]]) - traced[i]) / traced[i] / edge.size();
  std::printf("%zu vertices along the ceiling's edge with the back wall: %+.2f%% against the path tracer\n", edge.size(), 100 * bias);
  EXPECT_LT(std::fabs(bias), 0.05);
}

// The coupled corners' radiosities solve B = e + ρ (E_far + W B + E_direct): two vertices that
// see each other's corner, against the 2 × 2 system solved in closed form.
TEST(HierarchicalTest, CoupledNearFieldCornersSolveTheirLinearSystem) {
  NearFieldWeights near;
  near.start = {0, 1, 2};
  near.corner = {1, 0};
  near.weight = {0.45f, 0.3f};
  near.meanPart = {Rgb::gray(0.2), Rgb::gray(0.1)};
  const std::vector<Rgb> gathered = {Rgb::gray(1.0), Rgb::gray(0.6)};
  const std::vector<Rgb> emitted = {Rgb::gray(0.0), Rgb::gray(0.05)}, albedo = {Rgb::gray(0.8), Rgb::gray(0.5)};
  const std::vector<Rgb> direct = {Rgb::gray(0.3), Rgb::gray(0.0)};
  NearFieldCoupling coupling;
  const std::vector<Rgb> e = FinalGather::coupleNearField(gathered, near, emitted, albedo, direct, &coupling);
  // B0 = ρ0 (f0 + d0 + w01 B1), B1 = e1 + ρ1 (f1 + d1 + w10 B0), f = gathered − meanPart.
  const double f0 = 0.8, f1 = 0.5, a0 = 0.8 * (f0 + 0.3), a1 = 0.05 + 0.5 * f1, c0 = 0.8 * 0.45, c1 = 0.5 * 0.3;
  const double b0 = (a0 + c0 * a1) / (1 - c0 * c1), b1 = a1 + c1 * b0;
  EXPECT_NEAR(e[0].g, f0 + 0.45 * b1, 1e-6);
  EXPECT_NEAR(e[1].g, f1 + 0.3 * b0, 1e-6);
  EXPECT_GT(coupling.iterations, 1);
  EXPECT_LT(coupling.iterations, 30);
  EXPECT_TRUE(coupling.converged);
  EXPECT_EQ(coupling.rowsScaled, 0u);
}

// Close sources seen through one another (stacked or interpenetrating faces: each vertex here
// sees the next one's corner through three coincident sources, Σ w = 3 × 0.6) make a system
// whose loop gains ρ Σ w = 1.62 a step: iterated as it stands it grew to 10¹⁸ at the step cap
// and was published. Bounded, each row's ρ Σ w is at most (1 + ρ)/2 = 0.95, so no radiosity can
// exceed B₀ / (1 − 0.95), B₀ the largest uncoupled one, and the coupling converges.
TEST(HierarchicalTest, ANearFieldThatDoesNotContractIsBoundedAndConverges) {
  constexpr int kVertices = 3, kStacked = 3;
  NearFieldWeights near;
  near.start.push_back(0);
  for (std::uint32_t v = 0; v < kVertices; ++v) {
    for (int k = 0; k < kStacked; ++k) {
      near.corner.push_back((v + 1) % kVertices);
      near.weight.push_back(0.6f);
    }
    near.start.push_back(static_cast<std::uint32_t>(near.corner.size()));
  }
  near.meanPart.assign(kVertices, Rgb::gray(0.5));
  const std::vector<Rgb> gathered(kVertices, Rgb::gray(1.0)), emitted(kVertices, Rgb{}), albedo(kVertices, Rgb::gray(0.9));
  const std::vector<Rgb> direct = {Rgb::gray(2.0), Rgb{}, Rgb{}};
  NearFieldCoupling coupling;
  const std::vector<Rgb> e = FinalGather::coupleNearField(gathered, near, emitted, albedo, direct, &coupling);
  EXPECT_TRUE(coupling.converged);
  EXPECT_LT(coupling.iterations, kNearFieldMaxIterations);
  EXPECT_EQ(coupling.rowsScaled, static_cast<std::size_t>(kVertices));
  // B ≤ B₀ / (1 − c), c = 0.95 and B₀ = 0.9 × (1 + 2); E = far + Σ w B ≤ 0.5 + (c / ρ) × that.
  const double c = 0.95, largestRadiosity = 0.9 * 3.0 / (1 - c), largestIrradiance = 0.5 + c / 0.9 * largestRadiosity;
  for (const Rgb& x : e) {
    EXPECT_TRUE(std::isfinite(x.g));
    EXPECT_LE(x.g, largestIrradiance);
    EXPECT_GT(x.g, 0.5);  // the coupled light is still there
  }
  // Weights no bound can tame (not finite): the uncoupled gather, and the report says so.
  near.weight[0] = std::numeric_limits<float>::infinity();
  const std::vector<Rgb> fallback = FinalGather::coupleNearField(gathered, near, emitted, albedo, direct, &coupling);
  EXPECT_FALSE(coupling.converged);
  for (int v = 0; v < kVertices; ++v) EXPECT_EQ(fallback[v].g, gathered[v].g);
}

// A pocket of near-white faces (RenderPark's hospital repairs its rd = 1 materials to 0.999):
// a ring of vertices each seeing its two neighbours' corners over its whole hemisphere, loop gain
// ρ Σ w = 0.999, lit at one vertex. Jacobi steps shrink the error 0.1% each (13,800 for 10⁻⁶; at
// their 1,000-step cap the hospital's vertices were shown uncoupled); the coupling converges in
// a few hundred iterations at most, to the dense LU solution of the same system.
TEST(HierarchicalTest, ANearWhitePocketOfCornersConvergesToTheDirectSolution) {
  constexpr int kVertices = 200;
  constexpr double kAlbedo = 0.999;
  NearFieldWeights near;
  near.start.push_back(0);
  for (int v = 0; v < kVertices; ++v) {
    for (int side : {kVertices - 1, 1}) {
      near.corner.push_back(static_cast<std::uint32_t>((v + side) % kVertices));
      near.weight.push_back(0.5f);
    }
    near.start.push_back(static_cast<std::uint32_t>(near.corner.size()));
  }
  near.meanPart.assign(kVertices, Rgb::gray(0.1));
  const std::vector<Rgb> gathered(kVertices, Rgb::gray(0.1)), emitted(kVertices, Rgb{}), albedo(kVertices, Rgb::gray(kAlbedo));
  std::vector<Rgb> direct(kVertices, Rgb{});
  direct[0] = Rgb::gray(1.0);
  NearFieldCoupling coupling;
  const std::vector<Rgb> e = FinalGather::coupleNearField(gathered, near, emitted, albedo, direct, &coupling);
  EXPECT_TRUE(coupling.converged);
  EXPECT_LT(coupling.iterations, 300);
  EXPECT_EQ(coupling.rowsScaled, 0u);
  // B = ρ (direct + W B): (I − ρ W) B = ρ direct; E = W B (far = gathered − meanPart = 0).
  Eigen::MatrixXd system = Eigen::MatrixXd::Identity(kVertices, kVertices);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(kVertices);
  rhs[0] = kAlbedo * 1.0;
  for (int v = 0; v < kVertices; ++v)
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) system(v, near.corner[k]) -= kAlbedo * near.weight[k];
  const Eigen::VectorXd b = system.partialPivLu().solve(rhs);
  for (int v = 0; v < kVertices; ++v) {
    const double exact = 0.5 * (b[(v + kVertices - 1) % kVertices] + b[(v + 1) % kVertices]);
    EXPECT_NEAR(e[v].g, exact, 1e-4 * exact) << "vertex " << v;
  }
  // The light went round: the far side of the ring holds 2.4% of the lit vertex neighbour's.
  EXPECT_GT(e[kVertices / 2].g, 0.01 * e[1].g);
}

TEST(HierarchicalTest, TheMethodConvergesToTheExactSolutionWithAndWithoutClusters) {
  // The reference: the room solved with exact form factors (no estimate, no occlusion) on 10 × 10
  // cells a face. Its own error is measured here as a third of its distance from the 5 × 5
  // solution (Richardson: the error falls as 1/n²): 0.09% of the mean radiosity, far below the
  // differences the test resolves. (The flat method's 3000 patches agree with it within 0.1%.)
  const std::vector<double> albedo = {0.7, 0.8, 0.6, 0.3, 0.5, 0.75, 0.0};
  const std::vector<double> exact = exactBoxSurfaceMeans(10, albedo, kPi), coarse = exactBoxSurfaceMeans(5, albedo, kPi);
  const Scene scene = linkErrorRoom(albedo);
  double scale = 0, referenceError = 0;
  for (std::uint32_t s = 0; s < 6; ++s) scale += exact[s] / 6;
  for (std::uint32_t s = 0; s < 6; ++s) referenceError = std::fmax(referenceError, std::fabs(exact[s] - coarse[s]) / 3 / scale);
  std::printf("reference: mean radiosity %.5f W/m², its own error %.3g%% of it\n", scale, 100 * referenceError);
  ASSERT_LT(referenceError, 2e-3);
  // Every surface's mean against it, as a fraction of the mean radiosity.
  const auto worstSurface = [&](const RadiosityOptions& options, std::size_t& links) {
    auto engine = solved(scene, options);
    EXPECT_TRUE(engine);
    if (!engine) return double(INFINITY);
    double worst = 0;
    std::string where;
    for (std::uint32_t s = 0; s < 6; ++s) {
      const double error = std::fabs(surfaceMean(engine->solution(), s).g - exact[s]) / scale;
      if (error > worst) worst = error, where = scene.surfaces[s].name;
    }
    links = static_cast<std::size_t>(std::get<std::int64_t>(engine->stats().find("links")->value));
    std::printf("link error %g, %s, %d visibility rays: worst surface (%s) %.2f%% of the mean radiosity off, %zu links\n",
                options.hierarchical.links.linkError, options.hierarchical.links.clusters ? "clusters" : "no clusters",
                options.hierarchical.links.visibilityRays, where.c_str(), 100 * worst, links);
    return worst;
  };
  // Starting from every pair of faces (no clusters), each tenth of the link error must make more
  // links, and every surface must be within 0.5% (measured 0.15–0.19%: already at 1e-2 the method
  // is as close as the reference can tell, so no further gain is resolvable).
  std::size_t lastLinks = 0;
  for (double linkError : {1e-2, 1e-3, 1e-4}) {
    RadiosityOptions options = hierarchicalOptions(linkError);
    options.hierarchical.links.clusters = false;
    std::size_t links = 0;
    const double worst = worstSurface(options, links);
    EXPECT_LT(worst, 0.005) << "link error " << linkError;
    EXPECT_GT(links, lastLinks) << "link error " << linkError;
    lastLinks = links;
  }
  // With clusters (the default), a cluster link's K is a Monte Carlo estimate over its 8 sample
  // pairs, judged by a transfer estimated from sample pairs of its own (hierarchical/links.cpp,
  // judgedTransfer). Judged by the centres' transfer alone, close links carrying 20 times the
  // link error were kept, and their estimates, skewed low, left the surfaces 1.5–10% dark and
  // one seed in ten 41% bright. Every seed must come within 2.5% on every surface (measured
  // 1.3–1.8%: what is left is the clusters' one irradiance per receiver and one radiosity per
  // source, docs/hierarchical.md), and 64 sample pairs must not move any surface by more
  // than 1%: the result no longer hangs on rare samples.
  RadiosityOptions clustered = hierarchicalOptions(1e-4);
  std::size_t links = 0;
  for (std::uint64_t seed : {1, 2, 3}) {
    clustered.hierarchical.links.seed = seed;
    EXPECT_LT(worstSurface(clustered, links), 0.025) << "seed " << seed;
  }
  clustered.hierarchical.links.seed = 1;
  auto eight = solved(scene, clustered);
  clustered.hierarchical.links.visibilityRays = 64;
  auto sixtyFour = solved(scene, clustered);
  ASSERT_TRUE(eight && sixtyFour);
  for (std::uint32_t s = 0; s < 6; ++s)
    EXPECT_LT(std::fabs(surfaceMean(eight->solution(), s).g - surfaceMean(sixtyFour->solution(), s).g) / scale, 0.01)
        << scene.surfaces[s].name;
}

TEST(HierarchicalTest, ClusteringStartsFromLinearlyManyLinksAndAgreesWithoutClusters) {
  // 6 × 12² + 4 faces: without clusters the refinement starts from every ordered pair of faces.
  const Scene scene = gridBox(12);
  RadiosityOptions clustered = hierarchicalOptions(1e-3);
  RadiosityOptions unclustered = clustered;
  unclustered.hierarchical.links.clusters = false;
  auto a = solved(scene, clustered);
  auto b = solved(scene, unclustered);
  ASSERT_TRUE(a && b);
  auto number = [](const Radiosity& e, const char* key) {
    const Stats stats = e.stats();
    const Stats::Value& value = stats.find(key)->value;
    return std::holds_alternative<double>(value) ? std::get<double>(value) : static_cast<double>(std::get<std::int64_t>(value));
  };
  const double faces = number(*a, "faces");
  EXPECT_EQ(faces, 6 * 144 + 4);
  EXPECT_EQ(number(*b, "initial_links"), faces * (faces - 1));
  // Clustered: the links made (estimated on the way down) grow with the faces, not their square.
  EXPECT_LT(number(*a, "links_estimated"), 80 * faces);
  EXPECT_LT(number(*a, "links_estimated"), 0.1 * number(*b, "links_estimated"));
  EXPECT_GT(number(*a, "cluster_links"), 0);
  // The power absorbed agrees within 2% (measured 1.7%) and every surface within 5% (measured
  // up to 4.2%, a wall's; the ceiling 3.2%, which was 24% bright while the cluster kernel was
  // the centres' point-to-point transfer).
  std::printf("absorbed: clustered %.5f W, unclustered %.5f W\n", number(*a, "absorbed_watts"), number(*b, "absorbed_watts"));
  EXPECT_LT(relativeError(number(*a, "absorbed_watts"), number(*b, "absorbed_watts")), 0.02);
  for (std::uint32_t s = 0; s < 6; ++s) {
    const double with = surfaceMean(a->solution(), s).g, without = surfaceMean(b->solution(), s).g;
    EXPECT_LT(relativeError(with, without), 0.05) << scene.surfaces[s].name;
    std::printf("%s: clustered %.5f, unclustered %.5f\n", scene.surfaces[s].name.c_str(), with, without);
  }
}

// A column of `facets` long quads (a finely divided MGF cylinder), radius r about the vertical
// line through (x, z), from the floor (y = 0) to the ceiling (y = 1), facing out.
Surface column(double x, double z, double r, int facets) {
  Surface s;
  s.name = "column";
  for (int i = 0; i < facets; ++i) {
    const double a = 2 * kPi * i / facets;
    s.vertices.push_back({x + r * std::cos(a), 0, z + r * std::sin(a)});
    s.vertices.push_back({x + r * std::cos(a), 1, z + r * std::sin(a)});
  }
  for (int i = 0; i < facets; ++i) {
    const auto j = static_cast<std::uint32_t>((i + 1) % facets);
    const auto k = static_cast<std::uint32_t>(i);
    s.faces.push_back({2 * k, 2 * k + 1, 2 * j + 1, 2 * j});
  }
  return s;
}

TEST(HierarchicalTest, EveryNodesBoxHoldsItsFacesAndClustersBoxesAreTight) {
  // Links are admitted by the nodes' boxes: a box that missed a face would let a cluster link
  // reach through it, one much too large would refuse links the column test needs.
  Scene scene = gridBox(3);
  scene.surfaces.push_back(column(0.25, 0.25, 0.03, 16));
  const ElementHierarchy hierarchy(scene);
  for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
    const HierarchyNode& node = hierarchy.node(i);
    Vec3 lo, hi;
    node.box(lo, hi);
    // The corners of every face under the node, and their bounds.
    Vec3 facesLo{INFINITY, INFINITY, INFINITY}, facesHi = -facesLo;
    std::vector<std::uint32_t> open{i};
    while (!open.empty()) {
      const HierarchyNode& n = hierarchy.node(open.back());
      const std::uint32_t at = open.back();
      open.pop_back();
      if (n.isCluster()) {
        for (std::uint32_t k : hierarchy.children(at)) open.push_back(k);
        continue;
      }
      for (const Vec3& corner : n.polygon()) {
        facesLo = componentMin(facesLo, corner);
        facesHi = componentMax(facesHi, corner);
        EXPECT_TRUE(corner.x >= lo.x && corner.y >= lo.y && corner.z >= lo.z && corner.x <= hi.x && corner.y <= hi.y &&
                    corner.z <= hi.z)
            << "node " << i;
      }
    }
    EXPECT_LT(length(lo - facesLo) + length(hi - facesHi), 1e-6) << "node " << i;
  }
}

TEST(HierarchicalTest, AColumnLinksToTheFloorAndCeilingThroughItsClusters) {
  // The column's clusters are as tall as the column: their bounding spheres reach through the
  // floor and the ceiling it stands between, and hold most of the room. With the sphere as the
  // plane test no floor or ceiling element could link to them, and refinement opened the column
  // down to its facets, each linked to the floor's and ceiling's elements one by one: measured
  // 3.5 M links estimated and 0.95 M kept; with boxes for the plane test but spheres apart
  // still 1.9 M and 0.38 M; with boxes for both (and a kernel valid close by) 0.6 M and 21 k.
  Scene scene = gridBox(4);
  scene.surfaces.push_back(column(0.25, 0.25, 0.03, 256));
  auto engine = solved(scene, hierarchicalOptions(2e-4));
  ASSERT_TRUE(engine);
  const Stats stats = engine->stats();
  const auto value = [&](const char* key) { return static_cast<double>(std::get<std::int64_t>(stats.find(key)->value)); };
  std::printf("%g faces: %g links estimated, %g kept, %g with a cluster\n", value("faces"), value("links_estimated"), value("links"),
              value("cluster_links"));
  EXPECT_LT(value("links_estimated"), 1e6);
  EXPECT_LT(value("links"), 50e3);
  // Closed: what the lamp emits is absorbed (measured 0.8% short).
  const double emitted = std::get<double>(stats.find("emitted_watts")->value), absorbed = std::get<double>(stats.find("absorbed_watts")->value);
  std::printf("absorbed %.5f W of %.5f W emitted\n", absorbed, emitted);
  EXPECT_LT(relativeError(absorbed, emitted), 0.02);
}

TEST(HierarchicalTest, MirrorImageSurfacesGetMirrorImageLinks) {
  // Two parallel squares, both emitting: the links into one carry what the links into the other
  // do (Σ K over receivers' areas), as reciprocity and the symmetry of the scene demand.
  Scene scene = testing::parallelSquares();
  for (Surface& s : scene.surfaces) s.emittedRadiance = Rgb::gray(1);
  auto engine = solved(scene, hierarchicalOptions(1e-4));
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  const Rgb bottom = surfaceMean(view, 0), top = surfaceMean(view, 1);
  EXPECT_LT(relativeError(top.g, bottom.g), 1e-3);
}

TEST(HierarchicalTest, VertexValuesAreContinuousAcrossTJunctions) {
  // A spot on a coarse floor splits some elements and not their neighbours: every vertex that
  // lies inside a leaf's edge must carry the value interpolated along that edge.
  Scene scene = closedCube(1, {}, Rgb::gray(0.5));
  scene.lights.push_back(spotLight({0.3, 0.9, 0.3}, {0.2, -1, 0.1}, 2, 20, 2));
  auto engine = solved(scene, hierarchicalOptions(1e-3));
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  const Mesh& mesh = view.vertexMesh();
  std::size_t tJunctions = 0;
  // The element values interpolated, and the final gather's radiosity, indirect part and
  // irradiance, each continuous.
  for (const std::vector<Rgb>& values :
       {view.vertexValues(view.radiosity()), view.vertexValues(VertexQuantity::Radiosity),
        view.vertexValues(VertexQuantity::IndirectRadiosity), view.vertexValues(VertexQuantity::Irradiance)})
  for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
    auto corners = mesh.cornerIndices(p);
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const std::uint32_t a = corners[k], b = corners[(k + 1) % corners.size()];
      const Vec3 pa = mesh.positions[a], pb = mesh.positions[b];
      const double edge = length(pb - pa);
      for (std::uint32_t v = 0; v < mesh.numVertices(); ++v) {
        if (v == a || v == b || mesh.vertexSurface[v] != mesh.vertexSurface[a]) continue;
        const Vec3 pv = mesh.positions[v];
        const double t = dot(pv - pa, pb - pa) / (edge * edge);
        if (t <= 1e-9 || t >= 1 - 1e-9 || length(pa + (pb - pa) * t - pv) > 1e-9 * edge) continue;
        ++tJunctions;
        const Rgb expected = values[a] * (1 - t) + values[b] * t;
        ASSERT_NEAR(values[v].g, expected.g, 1e-9 * (1 + expected.g)) << "vertex " << v << " on edge " << a << "-" << b;
      }
    }
  }
  EXPECT_GT(tJunctions, 0u);  // the scene does make T-junctions
}

// Inside the furnace, two square plates face each other across a narrow gap, each plate three
// faces lying exactly on one another (RenderPark's office1/graz.mgf stacks a binder's two-sided
// cover and its lining this way; hospital/hosp.mgf lays drawer fronts on the back twin of a
// cabinet's side panel), and every plate two-sided. With visibility rays that stopped in front of
// the source point, a face between the plates saw all three faces across the gap whole: Σ K ≈ 3,
// and at ρ = 0.5 the solve diverged (without the bound) or the walls came out 6.6% bright (with
// it). A ray run to just behind the source point sees one face of the stack at each point, so
// every leaf gathers its hemisphere once and the furnace's B = E / (1 − ρ) holds.
Scene furnaceWithStackedPlates(int copies) {
  Scene scene = closedCube(1, Rgb::gray(1), Rgb::gray(0.5));
  scene.materials.push_back({"two-sided", Rgb::gray(0.5), true});
  const double lo = 0.5, hi = 0.51;
  for (int c = 0; c < copies; ++c) {
    scene.surfaces.push_back({"lower " + std::to_string(c), {{0.35, lo, 0.35}, {0.35, lo, 0.65}, {0.65, lo, 0.65}, {0.65, lo, 0.35}}, 1, Rgb::gray(1)});
    scene.surfaces.push_back({"upper " + std::to_string(c), {{0.35, hi, 0.35}, {0.65, hi, 0.35}, {0.65, hi, 0.65}, {0.35, hi, 0.65}}, 1, Rgb::gray(1)});
  }
  addTwins(scene);
  return scene;
}

TEST(HierarchicalTest, FacesLyingOnOneAnotherAreSeenOnce) {
  const Scene scene = furnaceWithStackedPlates(3);
  const double furnace = kPi / (1 - 0.5);
  for (SolverKind solver : {SolverKind::GaussSeidel, SolverKind::Jacobi}) {
    auto engine = solved(scene, hierarchicalOptions(2e-4, solver));
    ASSERT_TRUE(engine);
    // Measured 1.24 (3.0 with every face of a stack seen whole).
    EXPECT_LT(std::get<double>(engine->stats().find("largest_row_sum")->value), 1.5);
    const SolutionView& view = engine->solution();
    double sum = 0, area = 0, plateSum = 0, plateArea = 0;
    for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
      const double b = view.radiosity()[i].g, a = view.mesh().patches[i].area;
      ASSERT_TRUE(std::isfinite(b));
      sum += b * a;
      area += a;
      if (view.mesh().patches[i].surface >= 6) plateSum += b * a, plateArea += a;
    }
    // Measured: the mean +0.53% (the walls +6.6% with stacks seen whole), the plates +2.0%.
    EXPECT_LT(relativeError(sum / area, furnace), 0.01);
    EXPECT_LT(relativeError(plateSum / plateArea, furnace), 0.03);
    std::printf("stacked plates (%s): mean %+.2f%%, plates %+.2f%% from the furnace\n", solver == SolverKind::Jacobi ? "jacobi" : "gs",
                100 * (sum / area - furnace) / furnace, 100 * (plateSum / plateArea - furnace) / furnace);
  }
}

// The bound on what a leaf gathers (hierarchical/transport.h), on links made by hand: each of two
// squares gathers from the other with Σ K = 3 (what a leaf near a cluster of faces turned every
// way, or three stacked faces seen whole, can sum to). ρ·3 = 1.5 > 0.95, so each gathers exactly
// its hemisphere and B = E / (1 − ρ); left unbounded, every sweep multiplies B by 1.5.
TEST(HierarchicalTest, TheBoundMakesEverySweepAContraction) {
  ElementHierarchy hierarchy(testing::parallelSquares());
  hierarchy.numberLeaves();
  const std::vector<std::uint32_t>& leaves = hierarchy.leafNodes();
  ASSERT_EQ(leaves.size(), 2u);
  auto links = std::make_shared<Links>();
  links->start.assign(hierarchy.nodes().size() + 1, 0);
  for (std::uint32_t r = 0; r < hierarchy.nodes().size(); ++r) {
    links->start[r + 1] = links->start[r];
    for (int k = 0; k < 2 && (r == leaves[0] || r == leaves[1]); ++k) {
      links->source.push_back(r == leaves[0] ? leaves[1] : leaves[0]);
      links->formFactor.push_back(1.5f);
      links->uncertainty.push_back(0);
      links->receiverSide.push_back(0);
      links->facing.push_back({});
      ++links->start[r + 1];
    }
  }
  const std::vector<double> open(2, 1.0);
  const std::vector<Rgb> albedo(2, Rgb::gray(0.5)), emitted(2, Rgb::gray(1));
  const HierarchicalTransport transport(hierarchy, links, open, albedo);
  EXPECT_DOUBLE_EQ(transport.largestRowSum(), 3.0);
  EXPECT_EQ(transport.rowsScaled(), 2u);
  for (bool inPlace : {false, true}) {
    std::vector<Rgb> radiosity(2);
    for (int sweep = 0; sweep < 200; ++sweep) transport.sweep(emitted, albedo, radiosity, inPlace);
    for (const Rgb& b : radiosity) EXPECT_NEAR(b.g, 1 / (1 - 0.5), 1e-9);
  }
}

// One Gauss–Seidel sweep (hierarchical/transport.h: nodes depth first, each subtree's means brought
// up to date once, when it is finished) against its definition computed the slow way: leaf by
// leaf in the same depth-first order, each leaf's B_l = E_l + ρ_l H_l with H from a whole Jacobi
// gather (a fresh pull of every mean) at the current B. They agree to rounding wherever no link
// joins a node to its own ancestor (the refiner makes none here). The Cornell box's spot splits
// elements, so the depth-first order is not the leaves' numbering: a sweep in the numbering's
// order gives other values.
TEST(HierarchicalTest, AGaussSeidelSweepGathersEachLeafFromTheCurrentMeans) {
  Scene scene = closedCornellBox();
  const Light spot = spotLight({278, 540, 280}, {0.2, -1, 0.1}, 3e4, 30, 5);
  scene.lights.push_back(spot);
  RadiosityOptions options = hierarchicalOptions(2e-3);
  HierarchicalMethod meshing(scene, options);
  std::vector<Rgb> start;
  SolveReport report;
  ASSERT_TRUE(meshing.refine(scene.lights, start, report).ok());
  const ElementHierarchy& hierarchy = meshing.hierarchy();
  const Links& links = meshing.links();
  const Transport& transport = *meshing.transport();
  const std::size_t leaves = transport.size();
  ASSERT_GT(leaves, 500u);
  std::size_t toAncestor = 0;
  for (std::uint32_t r = 0; r < hierarchy.nodes().size(); ++r)
    for (std::uint32_t k = links.start[r]; k < links.start[r + 1]; ++k)
      for (std::uint32_t a = hierarchy.node(r).parent; a != kNoNode; a = hierarchy.node(a).parent) toAncestor += a == links.source[k];
  ASSERT_EQ(toAncestor, 0u);
  // The leaves depth first, children in order.
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> open{0};
  while (!open.empty()) {
    const std::uint32_t i = open.back();
    open.pop_back();
    if (hierarchy.node(i).isLeaf()) order.push_back(hierarchy.node(i).leaf);
    const auto children = hierarchy.children(i);
    for (std::size_t c = children.size(); c-- > 0;) open.push_back(children[c]);
  }
  ASSERT_EQ(order.size(), leaves);
  ASSERT_FALSE(std::is_sorted(order.begin(), order.end()));
  // A system with light everywhere: E the spot's first reflection plus a faint glow, B a guess
  // unlike the solution.
  const Mesh& mesh = meshing.elements();
  std::vector<Rgb> emitted(leaves), albedo = patchAlbedo(scene, mesh), guess(leaves);
  const std::vector<Rgb> direct = injectedRadiosity(mesh, albedo, patchIrradiance(mesh, meshing.caster(), spot, scene.metresPerUnit));
  for (std::size_t l = 0; l < leaves; ++l) {
    emitted[l] = direct[l] + Rgb::gray(0.01 * static_cast<double>(l % 7));
    guess[l] = Rgb{0.3, 0.2, 0.1} * static_cast<double>(l % 5);
  }
  std::vector<Rgb> expected = guess, irradiance;
  double change = 0, magnitude = 0;
  for (std::uint32_t l : order) {
    transport.gather(expected, irradiance);
    const Rgb updated = emitted[l] + albedo[l] * irradiance[l];
    for (int c = 0; c < 3; ++c) change = std::fmax(change, std::fabs(updated[c] - expected[l][c])), magnitude = std::fmax(magnitude, updated[c]);
    expected[l] = updated;
  }
  std::vector<Rgb> swept = guess;
  const SweepChange step = transport.sweep(emitted, albedo, swept, /*inPlace=*/true);
  double scale = 0, worst = 0;
  for (std::size_t l = 0; l < leaves; ++l) {
    scale = std::fmax(scale, expected[l].maxComponent());
    for (int c = 0; c < 3; ++c) worst = std::fmax(worst, std::fabs(swept[l][c] - expected[l][c]));
  }
  EXPECT_LT(worst, 1e-12 * scale);
  EXPECT_NEAR(step.change, change, 1e-12 * scale);
  EXPECT_NEAR(step.magnitude, magnitude, 1e-12 * scale);
  // In the leaves' numbering the sweep would gather other values.
  std::vector<Rgb> numbered = guess;
  for (std::size_t l = 0; l < leaves; ++l) {
    transport.gather(numbered, irradiance);
    numbered[l] = emitted[l] + albedo[l] * irradiance[l];
  }
  double apart = 0;
  for (std::size_t l = 0; l < leaves; ++l) apart = std::fmax(apart, std::fabs(numbered[l].g - expected[l].g));
  EXPECT_GT(apart, 1e-6 * scale);
}

// A spot moving over the floor of a closed grey room (ρ = 0.5), re-solved warm each frame over
// the links of the first solve, as an animation does: two Gauss–Seidel sweeps a frame while it
// moves, then frames of two sweeps after it stops.
TEST(HierarchicalTest, AMovingSpotReSolvedWarmEndsWhereAColdSolveDoes) {
  const double rho = 0.5;
  const Scene scene = closedCube(1, {}, Rgb::gray(rho));
  Light spot;
  spot.kind = LightKind::Spot;
  spot.intensity = Rgb::gray(1);
  spot.coneAngleDegrees = 30;
  spot.falloffDegrees = 5;
  auto spotAt = [&](double t) {
    Light moved = spot;
    moved.position = {0.25 + 0.5 * t, 0.9, 0.3 + 0.3 * t};
    moved.direction = normalize(Vec3{0.3 * t, -1, 0.1});
    return moved;
  };
  RadiosityOptions options = hierarchicalOptions(1e-3);
  options.tolerance = 1e-10;
  auto created = Radiosity::create(scene, options);
  ASSERT_TRUE(created.ok()) << created.error().message;
  Radiosity& engine = **created;
  engine.setLights({spotAt(0)});
  ASSERT_TRUE(engine.solve().ok());
  const std::size_t elements = engine.solution().mesh().numPatches();
  const int frames = 6;
  for (int frame = 1; frame <= frames; ++frame) {
    engine.setLights({spotAt(static_cast<double>(frame) / frames)});
    Result<SolveReport> report = engine.solve({.maxSweeps = 2});
    ASSERT_TRUE(report.ok()) << report.error().message;
    EXPECT_EQ(report->lightsInjected, 1);
    EXPECT_EQ(report->iterations, 2);
  }
  ASSERT_EQ(engine.solution().mesh().numPatches(), elements);  // re-solved over the same links
  {
    // Each frame re-injected only the patches the spot's cone reached before or reaches now: the
    // injection and the system's E hold what tracing the spot on every patch gives, to the bit.
    const SolutionView& moved = engine.solution();
    const std::vector<Rgb> traced = injectedRadiosity(
        moved.mesh(), moved.albedo(), patchIrradiance(moved.mesh(), moved.caster(), spotAt(1), scene.metresPerUnit, options.directLight));
    for (std::size_t i = 0; i < elements; ++i) {
      ASSERT_EQ(moved.injected()[i], traced[i]) << "element " << i;
      ASSERT_EQ(radiosityProblem(moved).emitted[i], moved.emitted()[i] + traced[i]) << "element " << i;
    }
  }
  // The cold solve at the final position: the same system (links, and the spot injected where it
  // stopped) solved from B = E by Jacobi sweeps, another solver than the engine's, to 1e-12.
  const SolutionView& view = engine.solution();
  SolverOptions cold;
  cold.tolerance = 1e-12;
  cold.maxIterations = 10000;
  std::vector<Rgb> reference;
  ASSERT_TRUE(makeSolver(SolverKind::Jacobi, cold)->solve(radiosityProblem(view), reference).converged);
  auto distance = [&] {
    double worst = 0, scale = 0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      scale = std::fmax(scale, reference[i].g);
      worst = std::fmax(worst, std::fabs(view.radiosity()[i].g - reference[i].g));
    }
    return worst / scale;
  };
  const double lagging = distance();
  std::printf("when the spot stops: %.3g of the brightest element from the cold solve\n", lagging);
  // Each Gauss–Seidel sweep in a room of ρ = 0.5 cuts the error at least in half: ten frames of
  // two sweeps come within 1e-5.
  int after = 0;
  while (distance() > 1e-5 && after < 10) {
    ASSERT_TRUE(engine.solve({.maxSweeps = 2}).ok());
    ++after;
  }
  std::printf("within 1e-5 of the cold solve %d frames after it stopped\n", after);
  EXPECT_LT(distance(), 1e-5);
  EXPECT_GT(lagging, 1e-5);  // it did lag while moving
  EXPECT_LT(after, 10);
  ASSERT_TRUE(engine.solve().ok());
  EXPECT_LT(distance(), 1e-8);

  // Against physics at the final position: the spot's direct light (evaluated at every vertex)
  // is ρ I cosθ / d² inside its cone's full-intensity part and nothing outside the cone, and
  // each element the inner cone covers wholly was injected ρ times its mean irradiance I Ω / A.
  const Light last = spotAt(1);
  const double inner = (last.coneAngleDegrees - last.falloffDegrees) * kPi / 180, outer = last.coneAngleDegrees * kPi / 180;
  auto angleOffAxis = [&](const Vec3& x) { return std::acos(std::clamp(dot(normalize(x - last.position), last.direction), -1.0, 1.0)); };
  const Mesh& mesh = view.vertexMesh();
  const std::vector<Rgb> total = view.vertexValues(VertexQuantity::Radiosity);
  const std::vector<Rgb> indirect = view.vertexValues(VertexQuantity::IndirectRadiosity);
  // T-junction vertices carry the value interpolated along the edge they lie in (continuity,
  // VertexValuesAreContinuousAcrossTJunctions), not their own: left out here.
  std::vector<char> hanging(mesh.numVertices(), 0);
  for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
    const auto corners = mesh.cornerIndices(p);
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const Vec3 a = mesh.positions[corners[k]], b = mesh.positions[corners[(k + 1) % corners.size()]];
      for (std::uint32_t v = 0; v < mesh.numVertices(); ++v) {
        const double t = dot(mesh.positions[v] - a, b - a) / lengthSquared(b - a);
        if (t > 1e-9 && t < 1 - 1e-9 && length(a + (b - a) * t - mesh.positions[v]) < 1e-9) hanging[v] = 1;
      }
    }
  }
  std::size_t inside = 0, outside = 0;
  for (std::uint32_t v = 0; v < mesh.numVertices(); ++v) {
    const Vec3 x = mesh.positions[v];
    if (hanging[v]) continue;
    const double angle = angleOffAxis(x);
    if (angle > inner && angle < outer) continue;  // the smooth edge
    // The vertex's surface normal: the cube's faces face its centre.
    double n[3] = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis)
      if (x[axis] < 1e-9 || x[axis] > 1 - 1e-9) n[axis] = x[axis] < 0.5 ? 1 : -1;
    const Vec3 normal{n[0], n[1], n[2]};
    if (length(normal) != 1) continue;  // an edge of the room, shared by two faces
    const Vec3 toLight = last.position - x;
    const double direct = angle <= inner ? rho * std::fmax(0.0, dot(normal, normalize(toLight))) / lengthSquared(toLight) : 0;
    // The final gather takes each vertex 1e-4 of the scene's diagonal into its surface: I cosθ/d²
    // moves by at most 3 δ/d of itself over that.
    const double inset = 1e-4 * std::sqrt(3.0);
    EXPECT_NEAR(total[v].g - indirect[v].g, direct, 3 * inset / length(toLight) * direct + 1e-12)
        << "vertex " << v << " at " << x.x << "," << x.y << "," << x.z;
    ++(direct > 0 ? inside : outside);
  }
  EXPECT_GT(inside, 10u);
  EXPECT_GT(outside, 10u);
  std::size_t covered = 0;
  for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
    const PatchCorners c = view.mesh().corners(i);
    const std::vector<Vec3> corners(c.begin(), c.end());
    bool wholly = dot(last.position - view.mesh().patches[i].centroid, view.mesh().patches[i].normal) > 0;
    double lo = INFINITY, hi = 0;
    for (const Vec3& corner : corners) {
      wholly &= angleOffAxis(corner) < inner;
      const Vec3 toLight = last.position - corner;
      const double e = rho * dot(view.mesh().patches[i].normal, normalize(toLight)) / lengthSquared(toLight);
      lo = std::fmin(lo, e), hi = std::fmax(hi, e);
    }
    if (!wholly) continue;
    ++covered;
    const double mean = rho * testing::solidAngle(last.position, corners) / view.mesh().patches[i].area;
    EXPECT_NEAR(view.injected()[i].g, mean, 0.1 * (hi - lo) + 1e-9 * mean) << "element " << i;
  }
  EXPECT_GT(covered, 4u);

  // A new engine made with the spot where it stopped refines its own links around the spot's pool
  // of light: each surface's mean radiosity within 2% of a solve refined 100 times finer (measured
  // 1.3% at most). Its links split the floor where the pool makes its leaves differ (hierarchical/
  // link_estimator.h, sourceVariesTooMuch); before, every wall linked to the whole floor's mean
  // and the three walls the spot does not reach came out alike, 0.0650, against 0.0532, 0.0560 and
  // 0.0576 refined, at any link error. The warm engine's links were refined for the spot's first
  // position (docs/hierarchical.md, "Moving lights"): it is printed, not held to the pool.
  auto fresh = Radiosity::create(scene, options);
  ASSERT_TRUE(fresh.ok());
  (*fresh)->setLights({last});
  ASSERT_TRUE((*fresh)->solve().ok());
  RadiosityOptions fine = options;
  fine.hierarchical.links.linkError = 1e-5;
  auto refined = Radiosity::create(scene, fine);
  ASSERT_TRUE(refined.ok());
  (*refined)->setLights({last});
  ASSERT_TRUE((*refined)->solve().ok());
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const double warm = surfaceMean(view, s).g, coldMean = surfaceMean((*fresh)->solution(), s).g;
    const double fineMean = surfaceMean((*refined)->solution(), s).g;
    std::printf("%s: warm %.5f, fresh engine %.5f, refined %.5f\n", scene.surfaces[s].name.c_str(), warm, coldMean, fineMean);
    EXPECT_LT(relativeError(coldMean, fineMean), 0.02) << scene.surfaces[s].name;
  }
  // And the path tracer on the three walls the spot does not reach (6 × 6 points each, whose
  // light is smooth there): the mean of ρE within 3% (measured +0.8%, +1.5% and +0.1%; the walls that linked to the whole floor were +22%, +16% and +12%).
  Scene lit = scene;
  lit.lights = {last};
  const ReferenceRenderer tracer(lit, subdivideScene(lit, 2.0), testing::quietReferenceOptions(4096));
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const std::string& name = scene.surfaces[s].name;
    if (name != "z0" && name != "x0" && name != "y1") continue;
    const std::vector<Vec3>& c = scene.surfaces[s].vertices;
    const Vec3 normal = surfaceNormal(scene.surfaces[s]);
    double sum = 0;
    const int n = 6;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double u = (i + 0.5) / n, v = (j + 0.5) / n;
        const Vec3 x = lerp(lerp(c[0], c[1], u), lerp(c[3], c[2], u), v);
        sum += rho * tracer.irradianceAt(x, normal, s, static_cast<std::uint64_t>(s * 100 + i * n + j)).g;
      }
    const double traced = sum / (n * n), solved = surfaceMean((*fresh)->solution(), s).g;
    std::printf("%s: traced %.5f, solved %.5f (%+.2f%%)\n", name.c_str(), traced, solved, 100 * (solved / traced - 1));
    EXPECT_LT(relativeError(solved, traced), 0.03) << name;
  }
}

TEST(HierarchicalTest, RefusesSolversThatNeedTheMatrix) {
  for (SolverKind solver : {SolverKind::Direct, SolverKind::Shooting}) {
    auto engine = Radiosity::create(testing::parallelSquares(), hierarchicalOptions(1e-3, solver));
    ASSERT_FALSE(engine.ok());
    EXPECT_NE(engine.error().message.find("gs or jacobi"), std::string::npos);
  }
}

// A 4 × 4 × 2.5 m room with a 1 m² lamp panel hung 10 cm under its ceiling, as a Blender user
// hangs an emissive plane (Blender's planes emit from both sides: the panel's back emits too, or
// only reflects). The ceiling sees the walls past the panel's edge, and from points near it the
// panel hides part of them. Links whose rays were partly blocked measured that visibility once
// for their whole receiver (a ceiling element, or its cluster); taken at every point, the two
// sides of a leaf edge beside the panel differed by up to 35%: steps in a lightmap. Points on
// the ceiling are checked for steps across its edges (2 mm either side, each gathered through
// its own leaf) and against the path tracer at the same points, E = π L / ρ.
// Measured (2-core EPYC), back emitting / back reflecting: largest step 3.3% / 5.3% (24.6% /
// 35.3% with each link's visibility); mean |error| against the tracer 6.6% / 8.0% (6.7% /
// 15.2%), the worst points being those over the panel, in the 10 cm gap above it, whose
// interreflection the default link error resolves only in part (docs/hierarchical.md).
struct HungPanel {
  const char* name;
  double backEmission;  // the panel's back's L_e
  double largestStep, meanError;  // bounds
};
void PrintTo(const HungPanel& panel, std::ostream* out) { *out << panel.name; }

class HungPanelTest : public ::testing::TestWithParam<HungPanel> {};

TEST_P(HungPanelTest, PointsUnderTheCeilingSeePastThePanelWithoutSteps) {
  constexpr int n = 6;
  const HungPanel panel = GetParam();
  Scene scene = sceneOf({gridSurface("floor", {-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, n),
                         gridSurface("ceiling", {-2, 2.5, -2}, {4, 0, 0}, {0, 0, 4}, n),
                         gridSurface("x0", {-2, 0, -2}, {0, 2.5, 0}, {0, 0, 4}, n),
                         gridSurface("x1", {2, 0, -2}, {0, 0, 4}, {0, 2.5, 0}, n),
                         gridSurface("z0", {-2, 0, -2}, {4, 0, 0}, {0, 2.5, 0}, n),
                         gridSurface("z1", {-2, 0, 2}, {0, 2.5, 0}, {4, 0, 0}, n),
                         gridSurface("panel", {-7.0 / 6, 2.4, 1.0 / 6}, {1, 0, 0}, {0, 0, 1}, 1, Rgb::gray(10)),
                         gridSurface("panel back", {-7.0 / 6, 2.401, 1.0 / 6}, {0, 0, 1}, {1, 0, 0}, 1, Rgb::gray(panel.backEmission))},
                        Rgb::gray(0.7));
  auto engine = solved(scene, hierarchicalOptions(LinkOptions{}.linkError));
  ASSERT_TRUE(engine);
  const SolutionView view = engine->solution();
  const auto cell = [](double c) { return static_cast<std::uint32_t>(std::floor((c + 2) / 4 * n)); };
  const auto onCeiling = [&](double x, double z) { return SurfacePoint{{x, 2.5, z}, {0, -1, 0}, 1, cell(z) * n + cell(x)}; };

  std::vector<SurfacePoint> sides;  // pairs across the edges within 1.2 m of the panel
  for (int e = 1; e < n; ++e)
    for (int t = 0; t < 24; ++t) {
      const double across = -2 + 4.0 * e / n, along = -2 + 4 * (t + 0.5) / 24;
      for (const bool alongX : {false, true}) {
        const double x = alongX ? along : across, z = alongX ? across : along;
        if (std::hypot(std::fmax(std::fabs(x + 2.0 / 3) - 0.5, 0.0), std::fmax(std::fabs(z - 2.0 / 3) - 0.5, 0.0)) > 1.2) continue;
        for (const double side : {-0.002, 0.002}) sides.push_back(onCeiling(alongX ? x : x + side, alongX ? z + side : z));
      }
    }
  Result<std::vector<Rgb>> across = view.pointIrradiance(sides);
  ASSERT_TRUE(across.ok()) << across.error().message;
  double step = 0;
  for (std::size_t k = 0; k + 1 < sides.size(); k += 2)
    step = std::fmax(step, std::fabs((*across)[k].g - (*across)[k + 1].g) / std::fmax((*across)[k].g, (*across)[k + 1].g));

  std::vector<SurfacePoint> points;  // a 7 × 7 grid over and around the panel
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) points.push_back(onCeiling(-1.87 + 0.5 * i, -1.37 + 0.5 * j));
  Result<std::vector<Rgb>> gathered = view.pointIrradiance(points);
  ASSERT_TRUE(gathered.ok()) << gathered.error().message;
  ReferenceOptions traceOptions;
  traceOptions.vertexSamples = 4096;
  traceOptions.showProgress = false;
  const ReferenceRenderer tracer(scene, subdivideScene(scene, 2 * sceneDiagonal(scene)), traceOptions);
  std::vector<double> error(points.size());
  parallelFor(0, points.size(), [&](std::size_t k) {
    const double traced = kPi * tracer.outgoingRadiance(points[k].point, points[k].normal, 1, k).g / 0.7;
    error[k] = std::fabs((*gathered)[k].g / traced - 1);
  });
  double mean = 0;
  for (double e : error) mean += e / error.size();
  std::printf("%s: %zu edges, the largest step %.1f%%; %zu points, mean |error| against the path tracer %.1f%%\n", panel.name,
              sides.size() / 2, 100 * step, points.size(), 100 * mean);
  EXPECT_LT(step, panel.largestStep);
  EXPECT_LT(mean, panel.meanError);
}

INSTANTIATE_TEST_SUITE_P(HierarchicalTest, HungPanelTest,
                         ::testing::Values(HungPanel{"back emitting", 10, 0.10, 0.09}, HungPanel{"back reflecting", 0, 0.12, 0.11}),
                         [](const ::testing::TestParamInfo<HungPanel>& info) { return std::string(info.param.backEmission > 0 ? "BackEmits" : "BackReflects"); });

}  // namespace
// A picture reads the vertices it shows, and the method gathers those alone (with their close
// sources' corners, three rings out): from low in a corner of the Cornell box the camera sees
// the tall block's foot and the walls beside it, a minority of the vertices, many of them where
// the view cuts the mesh. At every vertex it shows, the value is the gather at every vertex's,
// and so is the picture.
TEST(HierarchicalTest, APictureGathersTheVerticesItShowsAsAGatherAtEveryVertexDoes) {
  Scene scene = cornellBox();
  scene.camera = {{420, 60, 40}, {340, 40, 420}, {0, 1, 0}, 30};
  auto engine = solved(scene, hierarchicalOptions(2e-4));
  ASSERT_TRUE(engine);
  const SolutionView& view = engine->solution();
  const Mesh& mesh = view.vertexMesh();
  SolutionImageOptions image;
  image.width = image.height = 96;
  image.lighting = Lighting::Radiosity;
  const RenderOptions raster{image.width, image.height, image.shading, image.supersample};
  const std::vector<std::uint8_t> seen = visiblePatches(scene.camera, mesh, raster);
  std::vector<std::uint8_t> needed(mesh.numVertices(), 0);
  for (std::size_t i = 0; i < seen.size(); ++i)
    if (seen[i])
      for (std::uint32_t v : mesh.cornerIndices(i)) needed[v] = 1;
  const auto shown = static_cast<std::size_t>(std::count(needed.begin(), needed.end(), 1));
  ASSERT_GT(shown, 100u);
  ASSERT_LT(shown, mesh.numVertices() / 2);

  const Image picture = renderSolution(view, image);
  const auto gathered = static_cast<std::size_t>(testing::statCount(engine->stats(), "gather_vertices"));
  EXPECT_LT(gathered, mesh.numVertices() / 2);  // measured: 299 of 3,104, the rings included
  const std::vector<Rgb> some = view.vertexValues(VertexQuantity::Radiosity, needed);
  const std::vector<Rgb> every = view.vertexValues(VertexQuantity::Radiosity);
  double mean = 0, worst = 0;
  for (std::size_t v = 0; v < every.size(); ++v) mean += needed[v] ? every[v].g / static_cast<double>(shown) : 0;
  for (std::size_t v = 0; v < every.size(); ++v)
    if (needed[v]) worst = std::max(worst, std::fabs(some[v].g - every[v].g) / mean);
  // Measured 1.4e-5 of the mean; without the rings (every corner outside the vertices shown at
  // the elements' interpolated radiosity), 1.7e-2, and the picture 70 times this bound.
  EXPECT_LT(worst, 1e-4);
  const Image whole = renderVertexRadiosity(scene.camera, mesh, every, raster);
  double pictureMean = 0, pictureWorst = 0;
  for (const Rgb& p : whole.pixels) pictureMean += p.g / static_cast<double>(whole.pixels.size());
  for (std::size_t p = 0; p < whole.pixels.size(); ++p) pictureWorst = std::max(pictureWorst, std::fabs(picture.pixels[p].g - whole.pixels[p].g));
  EXPECT_LT(pictureWorst, 1e-4 * pictureMean);
  std::printf("%zu of %zu vertices shown, %zu gathered; largest difference %.1e of the mean\n", shown, mesh.numVertices(), gathered,
              worst);
}

}  // namespace lambert
