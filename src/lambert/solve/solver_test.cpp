#include <gtest/gtest.h>

#include <cmath>

#include "lambert/flat/form_factors.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/solve/energy.h"
#include "lambert/light/emission.h"
#include "lambert/solve/problem.h"
#include "lambert/solve/solver.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

constexpr SolverKind kAllSolvers[] = {SolverKind::Direct, SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Shooting};

struct Solved {
  Mesh mesh;
  RadiosityProblem problem;
};

Solved setUp(const Scene& scene, double maxEdge) {
  Solved s;
  s.mesh = subdivideScene(scene, maxEdge);
  auto caster = makeEmbreeRayCaster(s.mesh);
  FormFactorOptions options;
  options.showProgress = false;
  auto F = std::make_shared<DenseTransport>(std::make_shared<FormFactorMatrix>(computeFormFactors(s.mesh, *caster, options)));
  s.problem = makeRadiosityProblem(s.mesh, emittedRadiosity(scene, s.mesh), patchAlbedo(scene, s.mesh), F);
  return s;
}

std::vector<Rgb> solveWith(SolverKind kind, const RadiosityProblem& problem, SolverOptions options = {}) {
  std::vector<Rgb> radiosity;
  SolverReport report = makeSolver(kind, options)->solve(problem, radiosity);
  EXPECT_TRUE(report.converged) << solverName(kind);
  EXPECT_EQ(report.solver, solverName(kind));
  EXPECT_LT(report.residual, 1e-5) << solverName(kind);
  return radiosity;
}

double maxRelativeDifference(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  double scale = 0, worst = 0;
  for (const Rgb& v : b) scale = std::fmax(scale, v.maxComponent());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) worst = std::fmax(worst, std::fabs(a[i][c] - b[i][c]));
  return worst / scale;
}

// Furnace: a closed box whose every patch emits E with albedo ρ has B = E / (1 − ρ) everywhere.
TEST(SolverTest, FurnaceGivesEOverOneMinusRho) {
  const Rgb radiance{1, 2, 3};
  Solved s = setUp(testing::closedCube(1, radiance, Rgb::gray(0.5)), 0.3);
  const Rgb expected = radiance * kPi / (1 - 0.5);
  for (SolverKind kind : kAllSolvers) {
    std::vector<Rgb> radiosity = solveWith(kind, s.problem);
    for (std::size_t i = 0; i < radiosity.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_LT(testing::relativeError(radiosity[i][c], expected[c]), 0.005)
            << solverName(kind) << " patch " << i << " channel " << c << ": " << radiosity[i][c];
  }
}

// The Cornell box at the seed's largest mesh: all four solvers reach the same B.
// A closed furnace of near-white faces (ρ = 0.999, as RenderPark's hospital repairs rd = 1):
// Gauss–Seidel's sweeps shrink the error about 0.1% each and reached their 1,000-sweep cap
// unconverged; the sweeps finished by BiCGSTAB converge in a few dozen, to the direct solve.
TEST(SolverTest, GaussSeidelConvergesInANearWhiteFurnace) {
  Solved s = setUp(testing::closedCube(1, Rgb{1, 1, 1}, Rgb::gray(0.999)), 0.3);
  std::vector<Rgb> swept, direct;
  const SolverReport report = makeSolver(SolverKind::GaussSeidel, {})->solve(s.problem, swept);
  makeSolver(SolverKind::Direct, {})->solve(s.problem, direct);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(report.iterations, 200);
  EXPECT_LT(maxRelativeDifference(swept, direct), 1e-5);
  // The gain is what makes it slow: hundreds of times the emitted radiosity.
  EXPECT_GT(direct[0].g, 100 * kPi);
}

TEST(SolverTest, SolversAgreeOnTheCornellBox) {
  Scene scene = cornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 784));
  SolverOptions tight;
  tight.tolerance = 1e-10;
  std::vector<Rgb> direct = solveWith(SolverKind::Direct, s.problem, tight);
  for (SolverKind kind : {SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Shooting})
    EXPECT_LT(maxRelativeDifference(solveWith(kind, s.problem, tight), direct), 1e-4) << solverName(kind);
}

// measureResidual = false leaves the residual unmeasured (NaN) and the solution bit for bit the
// same; measured, it is the residual of B recomputed here from the dense matrix.
TEST(SolverTest, TheResidualIsMeasuredOnlyWhenAskedAndDoesNotChangeTheSolution) {
  const Scene scene = testing::closedCornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 300));
  const FormFactorMatrix& F = *s.problem.transport->matrix();
  for (SolverKind kind : kAllSolvers) {
    SolverOptions options;
    options.maxIterations = 3;  // stopped early: a residual well above rounding
    std::vector<Rgb> measured, unmeasured;
    const SolverReport a = makeSolver(kind, options)->solve(s.problem, measured);
    options.measureResidual = false;
    const SolverReport b = makeSolver(kind, options)->solve(s.problem, unmeasured);
    EXPECT_TRUE(std::isnan(b.residual)) << solverName(kind);
    ASSERT_EQ(measured.size(), unmeasured.size());
    for (std::size_t i = 0; i < measured.size(); ++i) ASSERT_EQ(measured[i], unmeasured[i]) << solverName(kind) << " patch " << i;
    double residual = 0, magnitude = 0;
    for (std::size_t i = 0; i < measured.size(); ++i) {
      Rgb gathered;
      for (std::size_t j = 0; j < measured.size(); ++j) gathered += measured[j] * static_cast<double>(F(i, j));
      const Rgb r = s.problem.emitted[i] + s.problem.albedo[i] * gathered - measured[i];
      for (int c = 0; c < 3; ++c) residual = std::fmax(residual, std::fabs(r[c])), magnitude = std::fmax(magnitude, std::fabs(measured[i][c]));
    }
    EXPECT_NEAR(a.residual, residual / magnitude, 1e-9 + 1e-6 * residual / magnitude) << solverName(kind);
  }
}

// Closed by a black portal, the box loses nothing through openings: what the light emits is
// absorbed by the surfaces (and the portal). A test of F's row sums in an occluded scene too.
TEST(SolverTest, EnergyBalanceOnTheClosedCornellBox) {
  Scene scene = testing::closedCornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 784));
  std::vector<Rgb> radiosity = solveWith(SolverKind::Direct, s.problem);
  EnergyBalance balance = energyBalance(s.problem, radiosity, scene.metresPerUnit);
  // 130 mm × 105 mm emitting π·(17, 12, 4) W/m², in watts of luminance.
  EXPECT_NEAR(balance.emittedWatts, 0.130 * 0.105 * kPi * (0.2126 * 17 + 0.7152 * 12 + 0.0722 * 4), 1e-9);
  EXPECT_LT(testing::relativeError(balance.absorbedWatts, balance.emittedWatts), 0.01)
      << "absorbed " << balance.absorbedWatts << " W of " << balance.emittedWatts << " W";
}

// On the open box the books close exactly: emitted = absorbed + escaped through the front.
TEST(SolverTest, EnergyIsConservedOnTheOpenCornellBox) {
  Scene scene = cornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 304));
  std::vector<Rgb> radiosity = solveWith(SolverKind::Direct, s.problem);
  EnergyBalance balance = energyBalance(s.problem, radiosity, scene.metresPerUnit);
  EXPECT_GT(balance.escapedWatts, 0.1 * balance.emittedWatts);  // the front is open
  EXPECT_LT(testing::relativeError(balance.absorbedWatts + balance.escapedWatts, balance.emittedWatts), 1e-6);
}

TEST(SolverTest, WarmStartFromTheSolutionConvergesAtOnce) {
  Scene scene = cornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 192));
  std::vector<Rgb> solution = solveWith(SolverKind::Direct, s.problem);
  for (SolverKind kind : {SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Shooting}) {
    std::vector<Rgb> radiosity = solution;
    SolverReport report = makeSolver(kind)->solve(s.problem, radiosity);
    EXPECT_TRUE(report.converged);
    EXPECT_LE(report.iterations, 1) << solverName(kind);
    EXPECT_LT(maxRelativeDifference(radiosity, solution), 1e-6);
  }
}

// A warm start from a stale solution (the light was dimmed) converges to the cold solve.
TEST(SolverTest, WarmStartFromAStaleSolutionConverges) {
  Scene scene = cornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 192));
  std::vector<Rgb> stale = solveWith(SolverKind::Direct, s.problem);
  for (Rgb& e : s.problem.emitted) e *= 0.25;
  std::vector<Rgb> cold = solveWith(SolverKind::Direct, s.problem);
  for (SolverKind kind : {SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Shooting}) {
    std::vector<Rgb> radiosity = stale;
    SolverOptions tight;
    tight.tolerance = 1e-10;
    SolverReport report = makeSolver(kind, tight)->solve(s.problem, radiosity);
    EXPECT_TRUE(report.converged) << solverName(kind);
    EXPECT_LT(maxRelativeDifference(radiosity, cold), 1e-5) << solverName(kind);
  }
}

// Each Gauss–Seidel or Jacobi sweep adds a bounce; stopped early it is darker than converged.
TEST(SolverTest, IterationsApproachTheSolutionFromBelow) {
  Scene scene = cornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 192));
  std::vector<Rgb> converged = solveWith(SolverKind::Direct, s.problem);
  SolverOptions two;
  two.maxIterations = 2;
  std::vector<Rgb> early;
  SolverReport report = makeSolver(SolverKind::Jacobi, two)->solve(s.problem, early);
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(report.iterations, 2);
  double meanDeficit = 0;
  int reflectors = 0;
  for (std::size_t i = 0; i < early.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_LE(early[i][c], converged[i][c] + 1e-9);
    if (s.problem.emitted[i].sum() > 0) continue;
    meanDeficit += 1 - early[i].sum() / converged[i].sum();
    ++reflectors;
  }
  // Two sweeps from E hold E + ρFE + (ρF)²E: the third and later bounces are missing.
  EXPECT_GT(meanDeficit / reflectors, 0.05);
}

// Progressive refinement's ambient term (Cohen et al. 1988): early in shooting, radiosity plus
// ambient is closer to the converged answer than radiosity alone.
TEST(SolverTest, ShootingAmbientTermImprovesEarlyEstimates) {
  Scene scene = cornellBox();
  Solved s = setUp(scene, edgeLengthForPatchCount(scene, 304));
  std::vector<Rgb> converged = solveWith(SolverKind::Direct, s.problem);
  auto errorAfter50Shots = [&](bool ambient) {
    SolverOptions options;
    options.displayAmbient = ambient;
    options.progressEvery = 50;
    double error = -1;
    options.onProgress = [&](int shot, const std::vector<Rgb>& display) {
      if (shot != 50) return;
      error = 0;
      for (std::size_t i = 0; i < display.size(); ++i)
        error += std::fabs(display[i].sum() - converged[i].sum()) * s.problem.area[i];
    };
    std::vector<Rgb> radiosity;
    makeSolver(SolverKind::Shooting, options)->solve(s.problem, radiosity);
    return error;
  };
  double withAmbient = errorAfter50Shots(true), without = errorAfter50Shots(false);
  ASSERT_GT(without, 0) << "progress callback never ran";
  EXPECT_LT(withAmbient, 0.5 * without);
}

TEST(SolverTest, AmbientOfUniformUnshotIsItsInfiniteReflection) {
  RadiosityProblem problem;
  problem.emitted.assign(4, Rgb{});
  problem.albedo.assign(4, Rgb::gray(0.5));
  problem.area = {1, 1, 1, 1};
  std::vector<Rgb> unshot(4, Rgb{1, 2, 4});
  Rgb ambient = ambientRadiosity(problem, unshot);
  EXPECT_NEAR(ambient.r, 2, 1e-12);  // 1 / (1 − 0.5)
  EXPECT_NEAR(ambient.g, 4, 1e-12);
  EXPECT_NEAR(ambient.b, 8, 1e-12);
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

// Two patches facing each other whose "form factors" are 2: a transport that makes energy. With
// ρ = 0.9 the iteration diverges (spectral radius 1.8); the fault check must say so and where.
RadiosityProblem energyMakingPair() {
  auto F = std::make_shared<FormFactorMatrix>(2, 2);
  *F << 0, 2, 2, 0;
  RadiosityProblem problem;
  problem.transport = std::make_shared<DenseTransport>(F);
  problem.emitted = {Rgb{1, 1, 1}, Rgb{}};
  problem.albedo = {Rgb{0.9, 0.9, 0.9}, Rgb{0.9, 0.9, 0.9}};
  problem.area = {1, 3};
  return problem;
}

TEST(SolutionFaultTest, ADivergedSolveIsFoundAndTheBrightestElementNamed) {
  RadiosityProblem problem = energyMakingPair();
  std::vector<Rgb> radiosity;
  SolverOptions options;
  options.maxIterations = 50;
  makeSolver(SolverKind::Jacobi, options)->solve(problem, radiosity);
  std::optional<SolutionFault> fault = findSolutionFault(problem, radiosity);
  ASSERT_TRUE(fault);
  EXPECT_EQ(fault->element, 1u);  // the larger patch holds more of the power
  EXPECT_NE(fault->what.find("diverged"), std::string::npos) << fault->what;

  // The same pair with physical form factors (0.2) converges and has no fault.
  auto F = std::make_shared<FormFactorMatrix>(2, 2);
  *F << 0, 0.2f, 0.2f, 0;
  problem.transport = std::make_shared<DenseTransport>(F);
  radiosity.clear();
  makeSolver(SolverKind::Jacobi, options)->solve(problem, radiosity);
  EXPECT_FALSE(findSolutionFault(problem, radiosity));
}

TEST(SolutionFaultTest, ANonFiniteRadiosityIsFoundWhereItIs) {
  RadiosityProblem problem = energyMakingPair();
  std::vector<Rgb> radiosity = {Rgb{1, 1, 1}, Rgb{0.5, std::nan(""), 0.5}};
  std::optional<SolutionFault> fault = findSolutionFault(problem, radiosity);
  ASSERT_TRUE(fault);
  EXPECT_EQ(fault->element, 1u);
  EXPECT_EQ(fault->what, "is not finite");
  radiosity[1].g = INFINITY;
  EXPECT_TRUE(findSolutionFault(problem, radiosity));
}

}  // namespace
}  // namespace lambert
