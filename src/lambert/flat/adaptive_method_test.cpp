#include <gtest/gtest.h>

#include <cmath>

#include "lambert/flat/adaptive_method.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/solve/energy.h"
#include "lambert/solve/solver.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

Scene floorMetre() {
  return testing::sceneOf({{"floor", {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, 0, {}}});
}

Light downwardSpot(Vec3 position, Vec3 direction) {
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = position;
  spot.direction = normalize(direction);
  spot.intensity = {1, 1, 1};
  spot.coneAngleDegrees = 25;
  spot.falloffDegrees = 5;
  return spot;
}

RadiosityOptions adaptiveOptions(QuadtreeOptions quadtree, double gradientThreshold) {
  RadiosityOptions options = testing::quietOptions();
  options.meshing = MeshStrategy::Adaptive;
  options.adaptive.quadtree = quadtree;
  options.adaptive.gradientThreshold = gradientThreshold;
  // One refine-and-solve pass per solve(): these tests watch what each pass does.
  options.adaptive.passesPerSolve = 1;
  return options;
}

RadiosityOptions geometricOnly() { return adaptiveOptions({0.25, 3}, 0); }

// A square cell of the floor y = 0, corner (x0, z0), facing up.
PatchCorners floorCell(double x0, double z0, double size) {
  PatchCorners c;
  c.count = 4;
  c.points = {Vec3{x0, 0, z0}, Vec3{x0, 0, z0 + size}, Vec3{x0 + size, 0, z0 + size}, Vec3{x0 + size, 0, z0}};
  return c;
}

// Whether a node has been split, at any depth below it.
bool isRefined(const AdaptiveMesh& mesh, std::uint32_t id) { return !mesh.node(id).active && mesh.node(id).firstChild >= 0; }

// Cells are split exactly where the cone's edge crosses them: every split cell straddles it, and
// no active cell above the deepest level does.
TEST(AdaptiveTest, RefinesExactlyAlongTheSpotsEdge) {
  Scene scene = floorMetre();
  auto adaptive = AdaptiveMethod::create(scene, geometricOnly());
  ASSERT_TRUE(adaptive.ok()) << adaptive.error().message;
  AdaptiveMethod& a = **adaptive;
  Light spot = downwardSpot({0.45, 0.6, 0.55}, {0.1, -1, 0});
  std::vector<Rgb> radiosity;
  SolveReport update;
  Result<bool> changed = a.refine({spot}, radiosity, update);
  ASSERT_TRUE(changed) << changed.error().message;
  EXPECT_TRUE(*changed);
  EXPECT_GT(update.refined, 0);
  EXPECT_EQ(radiosity.size(), a.elements().numPatches());  // a warm start for the new cells

  const AdaptiveMesh& mesh = a.mesh();
  int split = 0, coarseUntouched = 0, deepest = 0;
  for (std::uint32_t id = 0; id < mesh.numNodes(); ++id) {
    const QuadNode& n = mesh.node(id);
    bool crosses = AdaptiveMethod::crossesSpotEdge(spot, mesh.nodeMesh().corners(id), mesh.nodeMesh().patches[id].normal);
    if (isRefined(mesh, id)) {
      ++split;
      EXPECT_TRUE(crosses) << "node " << id << " split without the edge crossing it";
    } else if (n.active && n.level < 3) {
      EXPECT_FALSE(crosses) << "node " << id << " crossed by the edge but left coarse";
      coarseUntouched += n.level == 0;
    } else if (n.active) {
      ++deepest;
    }
  }
  EXPECT_GT(split, 4);
  EXPECT_GT(deepest, 16);
  EXPECT_GT(coarseUntouched, 0);  // the middle of the beam and the dark corners stay coarse

  // A cell wholly inside the beam and one wholly outside do not cross; one on the edge does.
  auto quad = floorCell;
  const Vec3 up{0, 1, 0};
  EXPECT_FALSE(AdaptiveMethod::crossesSpotEdge(spot, quad(0.5, 0.5, 0.05), up));
  EXPECT_FALSE(AdaptiveMethod::crossesSpotEdge(spot, quad(0.9, 0.9, 0.05), up));
  double edgeRadius = 0.6 * std::tan(25 * kPi / 180);
  EXPECT_TRUE(AdaptiveMethod::crossesSpotEdge(spot, quad(0.45 + 0.06 + edgeRadius - 0.02, 0.53, 0.04), up));
  // A beam narrower than a cell that lands inside it, all corners dark: still an edge.
  Light narrow = downwardSpot({0.5, 0.3, 0.5}, {0, -1, 0});
  narrow.coneAngleDegrees = 2;
  narrow.falloffDegrees = 1;
  EXPECT_TRUE(AdaptiveMethod::crossesSpotEdge(narrow, quad(0.25, 0.25, 0.5), up));
}

// The master table: a spot moves away and back; the cells it re-activates find their form
// factors in the table, and nothing is computed twice.
TEST(AdaptiveTest, ReactivatedCellsReuseTheirFormFactors) {
  Scene scene = testing::closedCube(1, {}, Rgb::gray(0.5));
  auto created = Radiosity::create(scene, adaptiveOptions({0.34, 2}, 0));
  ASSERT_TRUE(created.ok());
  Radiosity& engine = **created;
  Light here = downwardSpot({0.5, 0.95, 0.5}, {0.3, -1, 0.2});
  Light there = downwardSpot({0.5, 0.95, 0.5}, {-0.4, -1, -0.3});
  auto update = [&](const Light& light) {
    engine.setLights({light});
    Result<SolveReport> report = engine.solve();
    EXPECT_TRUE(report.ok());
    return *report;
  };

  SolveReport first = update(here);
  EXPECT_GT(first.pairsEstimated, 0u);
  const std::int64_t afterFirst = testing::statCount(engine.stats(), "pairs_estimated");
  const std::size_t activeHere = first.elements;

  SolveReport moved = update(there);
  EXPECT_GT(moved.pairsEstimated, 0u);   // new cells: new pairs
  EXPECT_GT(moved.pairsReused, 0u);      // the rest were known
  EXPECT_GT(moved.coarsened, 0);         // the old footprint merged back
  const std::int64_t afterMove = testing::statCount(engine.stats(), "pairs_estimated");
  EXPECT_GT(afterMove, afterFirst);

  SolveReport back = update(here);
  EXPECT_EQ(back.elements, activeHere);
  EXPECT_EQ(back.pairsEstimated, 0u);    // everything found in the table
  EXPECT_EQ(testing::statCount(engine.stats(), "pairs_estimated"), afterMove);
  EXPECT_EQ(back.pairsReused, activeHere * (activeHere - 1) / 2);
  SolveReport still = update(here);
  EXPECT_EQ(still.refined + still.coarsened, 0);
  EXPECT_EQ(still.lightsInjected, 0);    // the same light on the same cells: nothing traced
}

TEST(AdaptiveTest, RefinesAlongShadowEdges) {
  Scene scene = floorMetre();
  scene.surfaces.push_back({"blocker", {{0.4, 0.5, 0.4}, {0.6, 0.5, 0.4}, {0.6, 0.5, 0.6}, {0.4, 0.5, 0.6}}, 0, {}});
  auto adaptive = AdaptiveMethod::create(scene, geometricOnly());
  ASSERT_TRUE(adaptive.ok());
  AdaptiveMethod& a = **adaptive;
  Light point;
  point.kind = LightKind::Point;
  point.position = {0.5, 1.0, 0.5};
  point.intensity = {1, 1, 1};
  std::vector<Rgb> radiosity;
  SolveReport report;
  ASSERT_TRUE(a.refine({point}, radiosity, report));
  // The blocker's shadow on the floor spans 0.3 … 0.7: cells across its edge are split.
  auto cell = floorCell;
  const Vec3 up{0, 1, 0};
  EXPECT_TRUE(a.crossesShadowEdge(point, cell(0.25, 0.45, 0.1), up));
  EXPECT_FALSE(a.crossesShadowEdge(point, cell(0.45, 0.45, 0.1), up));  // wholly in shadow
  EXPECT_FALSE(a.crossesShadowEdge(point, cell(0.05, 0.05, 0.1), up));  // wholly lit
  int deepestOnFloor = 0;
  for (std::uint32_t id : a.mesh().activeNodes())
    deepestOnFloor += a.mesh().node(id).surface == 0 && a.mesh().node(id).level == 3;
  EXPECT_GT(deepestOnFloor, 8);
}

// The radiosity-gradient criterion refines where light changes fast, even without lights.
TEST(AdaptiveTest, GradientCriterionRefinesWhereRadiosityChanges) {
  auto created = Radiosity::create(cornellBox(), adaptiveOptions({120, 2}, 0.5));
  ASSERT_TRUE(created.ok());
  Radiosity& engine = **created;
  SolveReport first = *engine.solve();
  EXPECT_EQ(first.refined, 0);  // no solution yet to judge by
  SolveReport second = *engine.solve();
  EXPECT_GT(second.refined, 0);
  EXPECT_GT(second.elements, first.elements);
}

// Row normalisation divides each row of F by its sum. In a closed room, where rows already sum to one,
// that changes little; through the Cornell box's open front it stops light escaping, so the
// room gets brighter than energy conservation allows. The energy balance shows it: escaped power
// (leaving minus arriving) turns negative, the power the normalised, no longer reciprocal, F makes.
TEST(AdaptiveTest, RowNormalisationAndItsEffectOnEnergy) {
  for (bool closed : {true, false}) {
    Scene scene = closed ? testing::closedCube(1, {}, Rgb::gray(0.5)) : cornellBox();
    if (closed) scene.surfaces[0].emittedRadiance = {1, 1, 1};
    RadiosityOptions options = adaptiveOptions({closed ? 0.25 : 110.0, 0}, 0);
    std::unique_ptr<Radiosity> plainEngine = testing::solved(scene, options, {});
    options.normalizeRows = true;
    std::unique_ptr<Radiosity> normalisedEngine = testing::solved(scene, options, {});
    const SolutionView& plain = plainEngine->solution();
    const SolutionView& normalised = normalisedEngine->solution();
    const FormFactorMatrix& F = *radiosityProblem(normalised).transport->matrix();
    for (Eigen::Index i = 0; i < F.rows(); ++i) EXPECT_NEAR(F.row(i).cast<double>().sum(), 1, 1e-5);

    double plainPower = 0, normalisedPower = 0;
    for (std::size_t k = 0; k < plain.radiosity().size(); ++k) {
      plainPower += plain.radiosity()[k].sum() * radiosityProblem(plain).area[k];
      normalisedPower += normalised.radiosity()[k].sum() * radiosityProblem(normalised).area[k];
    }
    EnergyBalance balance = energyBalance(radiosityProblem(normalised), normalised.radiosity(), scene.metresPerUnit);
    // In a solution the books close whatever F is: emitted = absorbed + escaped (to the solver's
    // 1e-7 tolerance).
    EXPECT_NEAR(balance.absorbedWatts + balance.escapedWatts, balance.emittedWatts, 1e-6 * balance.emittedWatts);
    if (closed) {
      EXPECT_LT(testing::relativeError(normalisedPower, plainPower), 0.01);
      // Rows summed to one already; dividing by sums a little off one breaks reciprocity only a
      // little (measured: 0.09% of the emitted power escapes).
      EXPECT_LT(std::fabs(balance.escapedWatts), 0.01 * balance.emittedWatts);
    } else {
      EXPECT_GT(normalisedPower, 1.2 * plainPower) << "normalising the open box's rows adds the escaping light back";
      // More power arrives at the surfaces than leaves them (measured: −16% of the emitted power).
      EXPECT_LT(balance.escapedWatts, -0.1 * balance.emittedWatts) << "normalised rows make power";
    }
  }
}

TEST(AdaptiveTest, RowMethodsAreRejected) {
  RadiosityOptions options = geometricOnly();
  options.formFactors.method = FormFactorMethod::Hemicube;
  auto adaptive = Radiosity::create(cornellBox(), options);
  ASSERT_FALSE(adaptive.ok());
  EXPECT_NE(adaptive.error().message.find("hemicube"), std::string::npos) << adaptive.error().message;
}

TEST(AdaptiveTest, NonQuadScenesAreRejected) {
  Scene scene = testing::sceneOf({{"triangle", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 0, {}}});
  auto adaptive = Radiosity::create(scene, geometricOnly());
  ASSERT_FALSE(adaptive.ok());
  EXPECT_NE(adaptive.error().message.find("triangle"), std::string::npos);
}

}  // namespace
}  // namespace lambert
