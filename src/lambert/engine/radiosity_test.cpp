#include <gtest/gtest.h>

#include <cmath>

#include "lambert/engine/radiosity.h"
#include "lambert/formfactor/table.h"
#include "lambert/render/solution_image.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

RadiosityOptions uniformOptions(std::size_t patches, SolverKind solver, double tolerance) {
  RadiosityOptions options;
  options.meshing = MeshStrategy::Uniform;
  options.uniform.targetPatches = patches;
  options.formFactors.showProgress = false;
  options.solver = solver;
  options.tolerance = tolerance;
  options.maxIterations = 100000;
  return options;
}

std::unique_ptr<Radiosity> makeEngine(const Scene& scene, const RadiosityOptions& options) {
  auto engine = Radiosity::create(scene, options);
  EXPECT_TRUE(engine.ok()) << engine.error().message;
  return engine.ok() ? std::move(*engine) : nullptr;
}

std::vector<Light> lightsAt(const Scene& scene, double seconds) {
  std::vector<Light> lights;
  for (const Light& l : scene.lights) lights.push_back(lightAtTime(l, seconds));
  return lights;
}

SolveCallReport solved(Radiosity& engine, const SolveBudget& budget = {}) {
  Result<SolveCallReport> report = engine.solve(budget);
  EXPECT_TRUE(report.ok()) << report.error().message;
  return report.ok() ? *report : SolveCallReport{};
}

// The reference: the same scene and mesh, lights injected once, solved by LU from scratch.
std::vector<Rgb> coldSolve(const Scene& scene, std::size_t patches, const std::vector<Light>& lights) {
  std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(patches, SolverKind::Direct, 1e-7));
  engine->setLights(lights);
  solved(*engine);
  return engine->solution().radiosity();
}

// Relative to the brightest patch: how far a solution is from another.
double relativeError(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    scale = std::fmax(scale, b[i].maxComponent());
    for (int c = 0; c < 3; ++c) worst = std::fmax(worst, std::fabs(a[i][c] - b[i][c]));
  }
  return worst / scale;
}

double statNumber(const Stats& stats, const std::string& key) {
  const Stats::Entry* entry = stats.find(key);
  if (!entry) return NAN;
  if (const auto* i = std::get_if<std::int64_t>(&entry->value)) return static_cast<double>(*i);
  return std::get<double>(entry->value);
}

TEST(RadiosityTest, EachFrameConvergesToTheColdSolve) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(400, SolverKind::Shooting, 1e-8));
  for (double t : {0.0, 0.4, 1.3}) {
    engine->setLights(lightsAt(scene, t));
    SolveCallReport report = solved(*engine);
    EXPECT_EQ(report.lightsInjected, 2);
    EXPECT_TRUE(report.converged);
    EXPECT_LT(report.unshotFraction, 1e-8);
    EXPECT_LT(relativeError(engine->solution().radiosity(), coldSolve(scene, 400, lightsAt(scene, t))), 1e-5) << "t = " << t;
  }
}

// Gathering solvers warm-start from the last frame too, and need fewer sweeps for it.
TEST(RadiosityTest, GatheringSolversWarmStartFromTheLastFrame) {
  Scene scene = cornellBoxWithSpots();
  const std::vector<Rgb> reference = coldSolve(scene, 300, lightsAt(scene, 0.05));
  for (SolverKind solver : {SolverKind::GaussSeidel, SolverKind::Jacobi}) {
    std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(300, solver, 1e-9));
    engine->setLights(lightsAt(scene, 0));
    SolveCallReport cold = solved(*engine);
    engine->setLights(lightsAt(scene, 0.05));
    SolveCallReport warm = solved(*engine);
    EXPECT_TRUE(warm.converged);
    EXPECT_LT(warm.iterations, cold.iterations) << solverName(solver);
    EXPECT_LT(relativeError(engine->solution().radiosity(), reference), 1e-6) << solverName(solver);
  }
}

TEST(RadiosityTest, UnchangedLightsAreNotReinjected) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(200, SolverKind::Shooting, 1e-4));
  engine->setLights(lightsAt(scene, 0));
  EXPECT_EQ(solved(*engine).lightsInjected, 2);
  SolveCallReport again = solved(*engine);
  EXPECT_EQ(again.lightsInjected, 0);
  EXPECT_EQ(again.iterations, 0);
  std::vector<Light> oneMoved = lightsAt(scene, 0);
  oneMoved[1] = lightAtTime(scene.lights[1], 0.2);
  engine->setLights(oneMoved);
  EXPECT_EQ(solved(*engine).lightsInjected, 1);
  engine->setLights({oneMoved[0]});  // a light removed: the rest are traced afresh
  EXPECT_EQ(solved(*engine).lightsInjected, 1);
  engine->setLights({});
  solved(*engine);
  for (const Rgb& injected : engine->solution().injected()) EXPECT_EQ(injected.maxComponent(), 0);
}

// With a small shot budget per frame the solution lags a moving light, and catches up within
// 1% of the converged answer a few frames after the light stops.
TEST(RadiosityTest, BudgetedFramesCatchUpAfterTheLightStops) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(400, SolverKind::Shooting, 1e-9));
  const SolveBudget budget{.maxShots = 40};
  for (int frame = 0; frame < 30; ++frame) {
    engine->setLights(lightsAt(scene, frame / 30.0));
    EXPECT_EQ(solved(*engine, budget).iterations, 40);
  }
  const std::vector<Rgb> converged = coldSolve(scene, 400, lightsAt(scene, 29 / 30.0));
  double lagging = relativeError(engine->solution().radiosity(), converged);
  int frames = 0;
  while (relativeError(engine->solution().radiosity(), converged) > 0.01 && frames < 100) {
    solved(*engine, budget);
    ++frames;
  }
  EXPECT_LT(relativeError(engine->solution().radiosity(), converged), 0.01);
  EXPECT_LT(frames, 100);
  EXPECT_GT(lagging, relativeError(engine->solution().radiosity(), converged));
}

TEST(RadiosityTest, BudgetsBelongToTheirSolvers) {
  EXPECT_FALSE(checkSolveBudget(SolverKind::Direct, {.maxShots = 10}).ok());
  EXPECT_FALSE(checkSolveBudget(SolverKind::Direct, {.maxMilliseconds = 5}).ok());
  EXPECT_TRUE(checkSolveBudget(SolverKind::Direct, {}).ok());
  Status shotsForGs = checkSolveBudget(SolverKind::GaussSeidel, {.maxShots = 10});
  ASSERT_FALSE(shotsForGs.ok());
  EXPECT_NE(shotsForGs.error().message.find("shoot"), std::string::npos) << shotsForGs.error().message;
  EXPECT_FALSE(checkSolveBudget(SolverKind::Shooting, {.maxSweeps = 3}).ok());
  EXPECT_FALSE(checkSolveBudget(SolverKind::Jacobi, {.maxSweeps = -1}).ok());
  EXPECT_TRUE(checkSolveBudget(SolverKind::Jacobi, {.maxSweeps = 3, .maxMilliseconds = 5}).ok());

  Scene scene = cornellBox();
  std::unique_ptr<Radiosity> gs = makeEngine(scene, uniformOptions(200, SolverKind::GaussSeidel, 1e-12));
  EXPECT_FALSE(gs->solve({.maxShots = 5}).ok());
  SolveCallReport two = solved(*gs, {.maxSweeps = 2});
  EXPECT_EQ(two.iterations, 2);
  EXPECT_FALSE(two.converged);
  SolveCallReport timed = solved(*gs, {.maxMilliseconds = 1e-6});  // one sweep, then the clock
  EXPECT_EQ(timed.iterations, 1);
  EXPECT_FALSE(timed.converged);
  // A time budget stops the shooter at its first look at the clock, after 32 shots.
  std::unique_ptr<Radiosity> shoot = makeEngine(scene, uniformOptions(200, SolverKind::Shooting, 1e-12));
  SolveCallReport brief = solved(*shoot, {.maxMilliseconds = 1e-6});
  EXPECT_EQ(brief.iterations, 32);
  EXPECT_FALSE(brief.converged);
}

// Every solver with every mesh strategy reaches the same solution.
TEST(RadiosityTest, EverySolverWorksWithEveryMeshStrategy) {
  Scene scene = cornellBoxWithSpots();
  for (MeshStrategy strategy : {MeshStrategy::Uniform, MeshStrategy::Adaptive}) {
    std::vector<Rgb> first;
    for (SolverKind solver : {SolverKind::Direct, SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Shooting}) {
      RadiosityOptions options = uniformOptions(300, solver, 1e-9);
      options.meshing = strategy;
      options.adaptive.quadtree = {200, 1};
      std::unique_ptr<Radiosity> engine = makeEngine(scene, options);
      SolveCallReport report = solved(*engine);
      EXPECT_TRUE(report.converged) << solverName(solver);
      if (first.empty())
        first = engine->solution().radiosity();
      else
        EXPECT_LT(relativeError(engine->solution().radiosity(), first), 1e-6) << solverName(solver);
    }
  }
}

TEST(RadiosityTest, TheViewHoldsOneConsistentSolution) {
  Scene scene = cornellBoxWithSpots();
  for (MeshStrategy strategy : {MeshStrategy::Uniform, MeshStrategy::Adaptive}) {
    RadiosityOptions options = uniformOptions(300, SolverKind::GaussSeidel, 1e-9);
    options.meshing = strategy;
    options.adaptive.quadtree = {200, 2};
    std::unique_ptr<Radiosity> engine = makeEngine(scene, options);
    solved(*engine);
    const SolutionView& view = engine->solution();
    const std::size_t n = view.mesh().numPatches();
    ASSERT_EQ(view.radiosity().size(), n);
    ASSERT_EQ(view.injected().size(), n);
    ASSERT_EQ(view.emitted().size(), n);
    ASSERT_EQ(view.albedo().size(), n);
    ASSERT_EQ(view.problem().size(), n);
    EXPECT_EQ(view.lights(), scene.lights);
    double lit = 0;
    std::vector<Rgb> indirect = view.indirectRadiosity();
    for (std::size_t i = 0; i < n; ++i) {
      Rgb total = indirect[i] + view.injected()[i];
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(total[c], view.radiosity()[i][c], 1e-12);
        EXPECT_NEAR(view.problem().emitted[i][c], view.emitted()[i][c] + view.injected()[i][c], 1e-12);
        EXPECT_GE(indirect[i][c], -1e-9);
      }
      lit += view.injected()[i].sum();
    }
    EXPECT_GT(lit, 0);  // the spots inject light somewhere
    std::vector<Rgb> radiance = view.vertexRadiance(), values = view.vertexValues(view.radiosity());
    ASSERT_EQ(radiance.size(), view.vertexMesh().numVertices());
    for (std::size_t v = 0; v < radiance.size(); ++v) EXPECT_NEAR(radiance[v].r, values[v].r / kPi, 1e-12);
    ASSERT_EQ(view.vertexMeshAlbedo().size(), view.vertexMesh().numPatches());
    if (strategy == MeshStrategy::Uniform)
      EXPECT_EQ(&view.vertexMesh(), &view.mesh());
    else
      EXPECT_GT(view.vertexMesh().numPatches(), n);  // the quad-tree's finest level
  }
}

// Stats describe the solve the view holds: its lights' power, and every solve counted.
TEST(RadiosityTest, StatsDescribeTheCurrentSolution) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(200, SolverKind::Shooting, 1e-6));
  for (int frame = 0; frame < 3; ++frame) {
    engine->setLights(lightsAt(scene, frame / 10.0));
    solved(*engine);
  }
  Stats stats = engine->stats();
  EXPECT_EQ(statNumber(stats, "solves"), 3);
  EXPECT_EQ(statNumber(stats, "lights"), 2);
  EXPECT_GT(statNumber(stats, "emitted_watts"), 0.01);  // the spots' injected power
  EXPECT_NEAR(statNumber(stats, "absorbed_watts") + statNumber(stats, "escaped_watts"), statNumber(stats, "emitted_watts"),
              1e-3 * statNumber(stats, "emitted_watts"));
  EXPECT_LT(statNumber(stats, "residual"), 1e-4);
}

// The engine never moves: handing its unique_ptr around (into a growing vector, out of scope of
// the scene it was made from) leaves its solution and every reference into it valid.
TEST(RadiosityTest, AMovedEngineRendersTheSameImage) {
  std::vector<std::unique_ptr<Radiosity>> engines;
  SolutionImageOptions image;
  image.width = 48;
  image.height = 40;
  Image before;
  const SolutionView* view = nullptr;
  {
    Scene scene = cornellBoxWithSpots();
    std::unique_ptr<Radiosity> engine = makeEngine(scene, uniformOptions(200, SolverKind::GaussSeidel, 1e-7));
    solved(*engine);
    view = &engine->solution();
    before = renderSolution(*view, image);
    engines.push_back(std::move(engine));
  }
  for (int k = 0; k < 16; ++k) engines.push_back(makeEngine(testing::closedCube(), uniformOptions(12, SolverKind::GaussSeidel, 1e-7)));
  std::unique_ptr<Radiosity> moved = std::move(engines.front());
  engines.clear();
  EXPECT_EQ(&moved->solution(), view);
  Image after = renderSolution(moved->solution(), image);
  ASSERT_EQ(after.pixels.size(), before.pixels.size());
  double lit = 0;
  for (std::size_t p = 0; p < after.pixels.size(); ++p) {
    EXPECT_EQ(after.pixels[p].r, before.pixels[p].r);
    EXPECT_EQ(after.pixels[p].g, before.pixels[p].g);
    lit += after.pixels[p].sum();
  }
  EXPECT_GT(lit, 0);
}

TEST(RadiosityTest, ImpossibleCombinationsAreRefusedWithAReason) {
  RadiosityOptions options = uniformOptions(100, SolverKind::GaussSeidel, 1e-7);
  options.meshing = MeshStrategy::Adaptive;
  options.formFactors.method = FormFactorMethod::HemisphereRays;
  auto rows = Radiosity::create(cornellBox(), options);
  ASSERT_FALSE(rows.ok());
  EXPECT_NE(rows.error().message.find("hemisphere"), std::string::npos) << rows.error().message;
  options.formFactors.method = FormFactorMethod::AreaMonteCarlo;
  options.adaptive.passesPerSolve = 0;
  EXPECT_FALSE(Radiosity::create(cornellBox(), options).ok());
  options = uniformOptions(100, SolverKind::GaussSeidel, 0);
  EXPECT_FALSE(Radiosity::create(cornellBox(), options).ok());
}

// The flat methods' rows. Two plates face each other across a gap 1/40 of their size inside the
// furnace: seed 000's point estimate (cos cos / π r² × A_j between the centres) makes the facing
// patches' rows sum far above 1/ρ, and every solver diverges on them. formfactor/table.h's
// boundRowSums scales each such row to sum 1, so no solver can diverge: every element stays
// below E / (1 − 0.95) (the maximum principle, ρS ≤ 0.95 for the rows left as measured).
TEST(RadiosityTest, FlatRowsAboveOneAreBoundedSoNoSolverDiverges) {
  Scene scene = testing::closedCube(1, Rgb::gray(1), Rgb::gray(0.5));
  scene.materials.push_back({"two-sided", Rgb::gray(0.5), true});
  scene.surfaces.push_back({"lower", {{0.3, 0.5, 0.3}, {0.3, 0.5, 0.7}, {0.7, 0.5, 0.7}, {0.7, 0.5, 0.3}}, 1, Rgb::gray(1)});
  scene.surfaces.push_back({"upper", {{0.3, 0.51, 0.3}, {0.7, 0.51, 0.3}, {0.7, 0.51, 0.7}, {0.3, 0.51, 0.7}}, 1, Rgb::gray(1)});
  addTwins(scene);
  for (SolverKind solver : {SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Direct}) {
    RadiosityOptions options;
    options.meshing = MeshStrategy::Uniform;
    options.uniform.targetPatches = 300;
    options.formFactors.method = FormFactorMethod::PointToPoint;
    options.formFactors.showProgress = false;
    options.solver = solver;
    options.maxIterations = 10000;
    auto engine = Radiosity::create(scene, options);
    ASSERT_TRUE(engine.ok()) << engine.error().message;
    auto report = (*engine)->solve({});
    ASSERT_TRUE(report.ok()) << report.error().message;
    EXPECT_GT(std::get<std::int64_t>((*engine)->stats().find("rows_bounded")->value), 0);
    const double bound = kPi / (1 - kRowContraction);
    const SolutionView view = (*engine)->solution();
    for (std::size_t i = 0; i < view.mesh().numPatches(); ++i) {
      ASSERT_TRUE(std::isfinite(view.radiosity()[i].g));
      ASSERT_LE(view.radiosity()[i].g, bound * (1 + 1e-4)) << "patch " << i;
    }
  }
}

}  // namespace
}  // namespace lambert
