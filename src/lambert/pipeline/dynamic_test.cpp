#include <gtest/gtest.h>

#include <cmath>

#include "lambert/pipeline/dynamic.h"
#include "lambert/solve/problem.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

struct Fixture {
  Scene scene = cornellBoxWithSpots();
  Mesh mesh;
  std::unique_ptr<RayCaster> caster;
  RadiosityProblem problem;

  explicit Fixture(std::size_t patches) {
    mesh = subdivideScene(scene, edgeLengthForPatchCount(scene, patches));
    caster = makeEmbreeRayCaster(mesh);
    FormFactorOptions options;
    options.showProgress = false;
    problem = makeRadiosityProblem(scene, mesh, std::make_shared<FormFactorMatrix>(computeFormFactors(mesh, *caster, options)));
  }

  std::vector<Light> lightsAt(double seconds) const {
    std::vector<Light> lights;
    for (const Light& l : scene.lights) lights.push_back(lightAtTime(l, seconds));
    return lights;
  }

  // The reference: inject the lights and solve from scratch with LU.
  std::vector<Rgb> coldSolve(const std::vector<Light>& lights) const {
    RadiosityProblem p = problem;
    for (const Light& light : lights) {
      auto injected = injectedRadiosity(mesh, p.albedo, patchIrradiance(mesh, *caster, light, scene.metresPerUnit));
      for (std::size_t i = 0; i < injected.size(); ++i) p.emitted[i] += injected[i];
    }
    std::vector<Rgb> radiosity;
    makeSolver(SolverKind::Direct)->solve(p, radiosity);
    return radiosity;
  }
};

// Relative to the brightest patch: how far a dynamic state is from the converged one.
double relativeError(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    scale = std::fmax(scale, b[i].maxComponent());
    for (int c = 0; c < 3; ++c) worst = std::fmax(worst, std::fabs(a[i][c] - b[i][c]));
  }
  return worst / scale;
}

TEST(DynamicTest, EachFrameConvergesToTheColdSolve) {
  Fixture f(400);
  DynamicOptions options;
  options.tolerance = 1e-8;
  DynamicRadiosity dynamic(f.mesh, *f.caster, f.problem, f.scene.metresPerUnit, options);
  for (double t : {0.0, 0.4, 1.3}) {
    FrameReport report = dynamic.update(f.lightsAt(t));
    EXPECT_EQ(report.lightsUpdated, 2);
    EXPECT_LT(report.unshotFraction, 1e-8);
    EXPECT_LT(relativeError(dynamic.radiosity(), f.coldSolve(f.lightsAt(t))), 1e-5) << "t = " << t;
  }
}

TEST(DynamicTest, UnchangedLightsAreNotReinjected) {
  Fixture f(200);
  DynamicRadiosity dynamic(f.mesh, *f.caster, f.problem, f.scene.metresPerUnit);
  EXPECT_EQ(dynamic.update(f.lightsAt(0)).lightsUpdated, 2);
  FrameReport again = dynamic.update(f.lightsAt(0));
  EXPECT_EQ(again.lightsUpdated, 0);
  EXPECT_EQ(again.shots, 0);
  std::vector<Light> oneMoved = f.lightsAt(0);
  oneMoved[1] = lightAtTime(f.scene.lights[1], 0.2);
  EXPECT_EQ(dynamic.update(oneMoved).lightsUpdated, 1);
}

// With a small shot budget per frame the solution lags a moving light, and catches up within
// 1% of the converged answer a few frames after the light stops.
TEST(DynamicTest, BudgetedFramesCatchUpAfterTheLightStops) {
  Fixture f(400);
  DynamicOptions options;
  options.shotsPerFrame = 40;
  options.tolerance = 1e-9;
  DynamicRadiosity dynamic(f.mesh, *f.caster, f.problem, f.scene.metresPerUnit, options);
  for (int frame = 0; frame < 30; ++frame) dynamic.update(f.lightsAt(frame / 30.0));
  const std::vector<Light> stopped = f.lightsAt(29 / 30.0);
  const std::vector<Rgb> converged = f.coldSolve(stopped);
  double lagging = relativeError(dynamic.radiosity(), converged);
  int frames = 0;
  while (relativeError(dynamic.radiosity(), converged) > 0.01 && frames < 100) {
    dynamic.update(stopped);
    ++frames;
  }
  EXPECT_LT(relativeError(dynamic.radiosity(), converged), 0.01);
  EXPECT_LT(frames, 100);
  EXPECT_GT(lagging, relativeError(dynamic.radiosity(), converged));
}

TEST(DynamicTest, IndirectIsTotalLessInjected) {
  Fixture f(200);
  DynamicOptions options;
  options.tolerance = 1e-9;
  DynamicRadiosity dynamic(f.mesh, *f.caster, f.problem, f.scene.metresPerUnit, options);
  dynamic.update(f.lightsAt(0));
  std::vector<Rgb> indirect = dynamic.indirectRadiosity();
  double lit = 0;
  for (std::size_t i = 0; i < indirect.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_GE(indirect[i][c], -1e-9);
    lit += (dynamic.radiosity()[i] - indirect[i]).sum();
  }
  EXPECT_GT(lit, 0);  // the spots inject light somewhere
}

}  // namespace
}  // namespace lambert
