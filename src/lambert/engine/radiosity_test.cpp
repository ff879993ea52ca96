#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "lambert/core/sampling.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/flat/table.h"
#include "lambert/light/sky.h"
#include "lambert/load/scene_file.h"
#include "lambert/render/solution_image.h"
#include "lambert/solve/solver.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

using testing::engineFor;
using testing::solveCall;
using testing::statCount;
using testing::statNumber;

// The flat method to `tolerance`, with sweeps (or shots) enough to reach any of them.
RadiosityOptions uniformOptions(std::size_t patches, SolverKind solver, double tolerance) {
  RadiosityOptions options = testing::uniformOptions(patches, solver);
  options.tolerance = tolerance;
  options.maxIterations = 100000;
  return options;
}

std::vector<Light> lightsAt(const Scene& scene, double seconds) {
  std::vector<Light> lights;
  for (const Light& l : scene.lights) lights.push_back(lightAtTime(l, seconds));
  return lights;
}

// The reference: the same scene and mesh, lights injected once, solved by LU from scratch.
std::vector<Rgb> coldSolve(const Scene& scene, std::size_t patches, const std::vector<Light>& lights) {
  std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(patches, SolverKind::Direct, 1e-7));
  engine->setLights(lights);
  solveCall(*engine);
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

TEST(RadiosityTest, EachFrameConvergesToTheColdSolve) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(400, SolverKind::Shooting, 1e-8));
  for (double t : {0.0, 0.4, 1.3}) {
    engine->setLights(lightsAt(scene, t));
    SolveReport report = solveCall(*engine);
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
    std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(300, solver, 1e-9));
    engine->setLights(lightsAt(scene, 0));
    SolveReport cold = solveCall(*engine);
    engine->setLights(lightsAt(scene, 0.05));
    SolveReport warm = solveCall(*engine);
    EXPECT_TRUE(warm.converged);
    EXPECT_LT(warm.iterations, cold.iterations) << solverName(solver);
    EXPECT_LT(relativeError(engine->solution().radiosity(), reference), 1e-6) << solverName(solver);
  }
}

TEST(RadiosityTest, UnchangedLightsAreNotReinjected) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(200, SolverKind::Shooting, 1e-4));
  engine->setLights(lightsAt(scene, 0));
  EXPECT_EQ(solveCall(*engine).lightsInjected, 2);
  SolveReport again = solveCall(*engine);
  EXPECT_EQ(again.lightsInjected, 0);
  EXPECT_EQ(again.iterations, 0);
  std::vector<Light> oneMoved = lightsAt(scene, 0);
  oneMoved[1] = lightAtTime(scene.lights[1], 0.2);
  engine->setLights(oneMoved);
  EXPECT_EQ(solveCall(*engine).lightsInjected, 1);
  engine->setLights({oneMoved[0]});  // a light removed: the rest are traced afresh
  EXPECT_EQ(solveCall(*engine).lightsInjected, 1);
  engine->setLights({});
  solveCall(*engine);
  for (const Rgb& injected : engine->solution().injected()) EXPECT_EQ(injected.maxComponent(), 0);
}

// With a small shot budget per frame the solution lags a moving light, and catches up within
// 1% of the converged answer a few frames after the light stops.
TEST(RadiosityTest, BudgetedFramesCatchUpAfterTheLightStops) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(400, SolverKind::Shooting, 1e-9));
  const SolveBudget budget{.maxShots = 40};
  for (int frame = 0; frame < 30; ++frame) {
    engine->setLights(lightsAt(scene, frame / 30.0));
    EXPECT_EQ(solveCall(*engine, budget).iterations, 40);
  }
  const std::vector<Rgb> converged = coldSolve(scene, 400, lightsAt(scene, 29 / 30.0));
  double lagging = relativeError(engine->solution().radiosity(), converged);
  int frames = 0;
  while (relativeError(engine->solution().radiosity(), converged) > 0.01 && frames < 100) {
    solveCall(*engine, budget);
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
  std::unique_ptr<Radiosity> gs = engineFor(scene, uniformOptions(200, SolverKind::GaussSeidel, 1e-12));
  EXPECT_FALSE(gs->solve({.maxShots = 5}).ok());
  SolveReport two = solveCall(*gs, {.maxSweeps = 2});
  EXPECT_EQ(two.iterations, 2);
  EXPECT_FALSE(two.converged);
  SolveReport timed = solveCall(*gs, {.maxMilliseconds = 1e-6});  // one sweep, then the clock
  EXPECT_EQ(timed.iterations, 1);
  EXPECT_FALSE(timed.converged);
  // A time budget stops the shooter at its first look at the clock, after 32 shots.
  std::unique_ptr<Radiosity> shoot = engineFor(scene, uniformOptions(200, SolverKind::Shooting, 1e-12));
  SolveReport brief = solveCall(*shoot, {.maxMilliseconds = 1e-6});
  EXPECT_EQ(brief.iterations, 32);
  EXPECT_FALSE(brief.converged);
}

// Every solver with every mesh strategy reaches the same solution; the hierarchical method
// gathers over links (no matrix to factor or shoot from) and refuses direct and shoot, saying so.
TEST(RadiosityTest, EverySolverWorksWithEveryMeshStrategy) {
  Scene scene = cornellBoxWithSpots();
  for (MeshStrategy strategy : {MeshStrategy::Uniform, MeshStrategy::Adaptive, MeshStrategy::Hierarchical}) {
    std::vector<Rgb> first;
    for (SolverKind solver : {SolverKind::Direct, SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Shooting}) {
      RadiosityOptions options = uniformOptions(300, solver, 1e-9);
      options.meshing = strategy;
      options.adaptive.quadtree = {200, 1};
      options.hierarchical.links.linkError = 1e-3;
      if (strategy == MeshStrategy::Hierarchical && (solver == SolverKind::Direct || solver == SolverKind::Shooting)) {
        auto refused = Radiosity::create(scene, options);
        ASSERT_FALSE(refused.ok()) << solverName(solver);
        EXPECT_NE(refused.error().message.find("use the gs or jacobi solver, not '" + solverName(solver) + "'"), std::string::npos)
            << refused.error().message;
        continue;
      }
      std::unique_ptr<Radiosity> engine = engineFor(scene, options);
      ASSERT_TRUE(engine) << solverName(solver);
      SolveReport report = solveCall(*engine);
      EXPECT_TRUE(report.converged) << solverName(solver);
      double lit = 0;
      for (const Rgb& b : engine->solution().radiosity()) lit += b.sum();
      EXPECT_GT(lit, 0) << solverName(solver);
      if (first.empty())
        first = engine->solution().radiosity();
      else
        EXPECT_LT(relativeError(engine->solution().radiosity(), first), 1e-6) << solverName(solver);
    }
  }
}

TEST(RadiosityTest, TheViewHoldsOneConsistentSolution) {
  Scene scene = cornellBoxWithSpots();
  for (MeshStrategy strategy : {MeshStrategy::Uniform, MeshStrategy::Adaptive, MeshStrategy::Hierarchical}) {
    RadiosityOptions options = uniformOptions(300, SolverKind::GaussSeidel, 1e-9);
    options.meshing = strategy;
    options.adaptive.quadtree = {200, 2};
    std::unique_ptr<Radiosity> engine = engineFor(scene, options);
    solveCall(*engine);
    const SolutionView& view = engine->solution();
    const std::size_t n = view.mesh().numPatches();
    ASSERT_EQ(view.radiosity().size(), n);
    ASSERT_EQ(view.injected().size(), n);
    ASSERT_EQ(view.emitted().size(), n);
    ASSERT_EQ(view.albedo().size(), n);
    ASSERT_EQ(radiosityProblem(view).size(), n);
    EXPECT_EQ(view.lights(), scene.lights);
    double lit = 0;
    std::vector<Rgb> indirect = view.indirectRadiosity();
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) EXPECT_GE(indirect[i][c], -1e-9);
      lit += view.injected()[i].sum();
    }
    EXPECT_GT(lit, 0);  // the spots inject light somewhere
    ASSERT_EQ(view.vertexRadiance().size(), view.vertexMesh().numVertices());
    ASSERT_EQ(view.vertexMeshAlbedo().size(), view.vertexMesh().numPatches());
    if (strategy == MeshStrategy::Adaptive)
      EXPECT_GT(view.vertexMesh().numPatches(), n);  // the quad-tree's finest level
    else
      EXPECT_EQ(&view.vertexMesh(), &view.mesh());  // uniform patches, hierarchical leaves
  }
}

// What the view says against the closed form, for every mesh strategy: a point light of intensity
// I = 2 W/sr at height h = 1.2 m over a grey floor (ρ = 0.5) that is the only surface, so no
// light comes back to it. Each element's injected light is ρ times its mean irradiance, I·Ω/A
// with Ω the solid angle it subtends at the light (tests/support/scenes.h); there is no indirect
// light; what the solve holds is the surfaces' emission (none) plus that; and the radiance at a
// vertex at distance d, angle θ is ρ I cosθ / (π d²). Tolerances from what each estimate can
// miss by: the elements' 16 low-discrepancy points average the irradiance to within a tenth of
// its spread over the element; a vertex value interpolated from elements' means (uniform,
// adaptive; the hierarchy's T-junctions) lies within the spread of the field over the elements
// it comes from, as the exact value at the vertex does; the hierarchical final gather evaluates
// the light at the vertex itself, moved 1e-4 of the scene's diagonal δ into its element, where
// I cosθ/d² changes by at most 3δ/d of itself.
TEST(RadiosityTest, TheViewsLightIsTheClosedForm) {
  const double rho = 0.5, intensity = 2, height = 1.2;
  const Vec3 lamp{0.3, height, -0.2};
  Scene scene = testing::sceneOf({{"floor", {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, 0, {}}}, Rgb::gray(rho));
  Light point;
  point.kind = LightKind::Point;
  point.position = lamp;
  point.intensity = Rgb::gray(intensity);
  scene.lights = {point};
  const auto exitance = [&](const Vec3& x) {
    const Vec3 toLight = lamp - x;
    return rho * intensity * toLight.y / std::pow(length(toLight), 3);  // cosθ / d² = h / d³
  };
  // The least and greatest ρ I cosθ/d² over a patch, from a 9 × 9 grid of points over it.
  const auto range = [&](const Mesh& mesh, std::size_t p) {
    const PatchCorners c = mesh.corners(p);
    std::pair<double, double> out{INFINITY, 0};
    for (int a = 0; a <= 8; ++a)
      for (int b = 0; b <= 8; ++b) {
        const double e = exitance(sampleConvexPolygon(c, std::fmin(a / 8.0, 1 - 1e-12), b / 8.0));
        out.first = std::fmin(out.first, e), out.second = std::fmax(out.second, e);
      }
    return out;
  };
  const auto spread = [&](const Mesh& mesh, std::size_t p) {
    const auto [lo, hi] = range(mesh, p);
    return hi - lo;
  };
  for (MeshStrategy strategy : {MeshStrategy::Uniform, MeshStrategy::Adaptive, MeshStrategy::Hierarchical}) {
    RadiosityOptions options = uniformOptions(100, SolverKind::GaussSeidel, 1e-9);
    options.meshing = strategy;
    options.adaptive.quadtree = {0.3, 2};
    options.hierarchical.links.linkError = 1e-4;
    std::unique_ptr<Radiosity> engine = engineFor(scene, options);
    ASSERT_TRUE(engine);
    solveCall(*engine);
    const SolutionView& view = engine->solution();
    const Mesh& mesh = view.mesh();
    ASSERT_GT(mesh.numPatches(), 8u);
    const std::vector<Rgb> indirect = view.indirectRadiosity();
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      const PatchCorners c = mesh.corners(i);
      const double mean = rho * intensity * testing::solidAngle(lamp, std::vector<Vec3>(c.begin(), c.end())) / mesh.patches[i].area;
      const double tolerance = 0.1 * spread(mesh, i) + 1e-9 * mean;
      EXPECT_NEAR(view.injected()[i].g, mean, tolerance) << "element " << i;
      EXPECT_NEAR(indirect[i].g, 0, 1e-9 * mean) << "element " << i;
      EXPECT_EQ(view.emitted()[i].g, 0);
      EXPECT_NEAR(radiosityProblem(view).emitted[i].g, mean, tolerance) << "element " << i;
    }
    // A vertex value interpolated from elements is a weighted mean of the means of the element
    // holding the vertex and of elements touching its corners, all within one such element's
    // size of the vertex: it and the exact value both lie in the field's range over them.
    // Whether a vertex is a T-junction (inside an element's edge) too.
    const Mesh& vertices = view.vertexMesh();
    std::vector<double> reach(vertices.numVertices(), 0);
    std::vector<char> hanging(vertices.numVertices(), 0);
    std::vector<std::pair<double, double>> ranges(mesh.numPatches());
    std::vector<Vec3> lower(mesh.numPatches()), upper(mesh.numPatches());
    for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
      ranges[p] = range(mesh, p);
      const PatchCorners c = mesh.corners(p);
      lower[p] = upper[p] = c[0];
      for (const Vec3& corner : c) lower[p] = componentMin(lower[p], corner), upper[p] = componentMax(upper[p], corner);
      for (std::uint32_t v = 0; v < vertices.numVertices(); ++v) {
        const Vec3 x = vertices.positions[v];
        bool inside = true, onEdge = false;
        for (std::size_t k = 0; k < c.size(); ++k) {
          const Vec3 a = c[k], b = c[(k + 1) % c.size()];
          const double side = dot(cross(b - a, x - a), mesh.patches[p].normal) / length(b - a);
          inside &= side > -1e-9;
          const double t = dot(x - a, b - a) / lengthSquared(b - a);
          onEdge |= std::fabs(side) <= 1e-9 && t > 1e-9 && t < 1 - 1e-9;
        }
        if (!inside) continue;
        reach[v] = std::fmax(reach[v], length(upper[p] - lower[p]));
        if (onEdge) hanging[v] = 1;
      }
    }
    std::vector<double> interpolation(vertices.numVertices(), 0);
    for (std::uint32_t v = 0; v < vertices.numVertices(); ++v) {
      const Vec3 x = vertices.positions[v];
      double lo = INFINITY, hi = 0;
      for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
        const Vec3 gapLow = lower[p] - x, gapHigh = x - upper[p];
        if (std::fmax(gapLow.x, gapHigh.x) > reach[v] || std::fmax(gapLow.z, gapHigh.z) > reach[v]) continue;
        lo = std::fmin(lo, ranges[p].first), hi = std::fmax(hi, ranges[p].second);
      }
      interpolation[v] = hi - lo;
    }
    const std::vector<Rgb> radiance = view.vertexRadiance();
    const double inset = 1e-4 * sceneDiagonal(scene);
    double worst = 0;
    for (std::uint32_t v = 0; v < vertices.numVertices(); ++v) {
      const Vec3 x = vertices.positions[v];
      const double expected = exitance(x) / kPi;
      const double tolerance = strategy == MeshStrategy::Hierarchical && !hanging[v] ? 3 * inset / length(lamp - x) * expected
                                                                                     : interpolation[v] / kPi;
      worst = std::fmax(worst, std::fabs(radiance[v].g - expected) / (tolerance + 1e-12));
      EXPECT_LT(std::fabs(radiance[v].g - expected), tolerance + 1e-12) << "vertex " << v;
    }
    std::printf("strategy %d: %zu elements, worst vertex %.2f of its tolerance\n", static_cast<int>(strategy), mesh.numPatches(), worst);
  }
}

// Stats describe the solve the view holds: its lights' power, and every solve counted.
// A floor alone under a uniform environment of radiance L (light/sky.h; Blender's world colour):
// every point sees the whole sky above it, E = π L, so every element's radiosity is ρ π L and the
// radiance at every vertex ρ L, in each channel, with every mesh strategy; a black box on the
// floor takes its share of the sky, so it cannot be the same there (the comparison can fail).
TEST(RadiosityTest, AnEnvironmentLightsAnOpenFloorWithPiTimesItsRadiance) {
  const double rho = 0.5;
  const Rgb radiance{1, 0.5, 0.25};
  Scene scene = testing::sceneOf({{"floor", {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, 0, {}}}, Rgb::gray(rho));
  Light environment;
  environment.kind = LightKind::Sky;
  environment.sky = std::make_shared<const SkyModel>(*SkyModel::uniformEnvironment(radiance));
  scene.lights = {environment};
  for (MeshStrategy strategy : {MeshStrategy::Uniform, MeshStrategy::Hierarchical}) {
    RadiosityOptions options = uniformOptions(64, SolverKind::GaussSeidel, 1e-9);
    options.meshing = strategy;
    std::unique_ptr<Radiosity> engine = engineFor(scene, options);
    ASSERT_TRUE(engine);
    solveCall(*engine);
    const SolutionView& view = engine->solution();
    for (const Rgb& b : view.radiosity())
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], rho * kPi * radiance[c], 1e-3 * rho * kPi * radiance[c]) << c;
    for (const Rgb& l : view.vertexRadiance())
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(l[c], rho * radiance[c], 1e-3 * rho * radiance[c]) << c;
  }
  Scene boxed = scene;
  for (Surface s : testing::closedCube(0.4).surfaces) {  // 5 cm above the floor's middle (its faces inward: opaque all the same)
    for (Vec3& v : s.vertices) v = v + Vec3{-0.2, 0.05, -0.2};
    boxed.surfaces.push_back(s);
  }
  std::unique_ptr<Radiosity> engine = engineFor(boxed, uniformOptions(64, SolverKind::GaussSeidel, 1e-9));
  ASSERT_TRUE(engine);
  solveCall(*engine);
  double least = INFINITY;
  for (std::size_t i = 0; i < engine->solution().mesh().numPatches(); ++i)
    if (engine->solution().mesh().patches[i].surface == 0) least = std::fmin(least, engine->solution().radiosity()[i].r);
  EXPECT_LT(least, 0.9 * rho * kPi * radiance.r) << "the box's shadow on the floor";
}

// The power figures say what they name. A white point light of I = 2 W/sr (4π·I W) inside a
// closed cube: every watt it sends reaches a wall, so the first reflection injected is ρ·4π·I
// (within the injection's sampling), and the light's own power does not depend on the walls. A
// black cube absorbs it all at once: nothing injected, the light's power the same; the surfaces
// emit nothing in either. A spot's power (its cone's integral, light/lights.h lightLumens) is what
// its injection, sampled over the walls it reaches, finds there.
TEST(RadiosityTest, PowerFiguresNameTheLightsPowerAndItsFirstReflection) {
  for (double albedo : {0.5, 0.0}) {
    Scene scene = testing::closedCube(2, {}, Rgb::gray(albedo));
    Light light;
    light.kind = LightKind::Point;
    light.position = {0.7, 1.2, 0.9};
    light.intensity = Rgb::gray(2);
    scene.lights.push_back(light);
    std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(600, SolverKind::Direct, 1e-7));
    solveCall(*engine);
    const Stats stats = engine->stats();
    EXPECT_NEAR(statNumber(stats, "light_watts"), 4 * kPi * 2, 1e-9 * 4 * kPi * 2);
    EXPECT_NEAR(statNumber(stats, "injected_watts"), albedo * 4 * kPi * 2, 0.01 * 4 * kPi * 2) << "ρ " << albedo;
    EXPECT_EQ(statNumber(stats, "emitted_watts"), 0) << "ρ " << albedo;
  }
  Scene scene = testing::closedCube(2, {}, Rgb::gray(1));
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = {1, 1.9, 1};
  spot.direction = normalize(Vec3{0.2, -1, 0.1});
  spot.coneAngleDegrees = 50;
  spot.falloffDegrees = 20;
  spot.intensity = Rgb::gray(3);
  scene.lights.push_back(spot);
  std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(2400, SolverKind::Direct, 1e-7));
  solveCall(*engine);
  const Stats stats = engine->stats();
  std::printf("spot: %.5f W by its cone, %.5f W found on the walls\n", statNumber(stats, "light_watts"), statNumber(stats, "injected_watts"));
  EXPECT_NEAR(statNumber(stats, "injected_watts") / statNumber(stats, "light_watts"), 1, 0.01);
}

TEST(RadiosityTest, StatsDescribeTheCurrentSolution) {
  Scene scene = cornellBoxWithSpots();
  std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(200, SolverKind::Shooting, 1e-6));
  for (int frame = 0; frame < 3; ++frame) {
    engine->setLights(lightsAt(scene, frame / 10.0));
    solveCall(*engine);
  }
  Stats stats = engine->stats();
  EXPECT_EQ(statNumber(stats, "solves"), 3);
  EXPECT_EQ(statNumber(stats, "lights"), 2);
  EXPECT_GT(statNumber(stats, "injected_watts"), 0.01);  // the spots' first reflection
  EXPECT_LT(statNumber(stats, "residual"), 1e-4);
  // The power figures are the last frame's: an engine made with the last frame's lights and
  // solved once reports the same (the injection to the bit, the solve to its tolerance), and the
  // first frame's lights report other figures.
  auto powerOf = [&](double seconds) {
    std::unique_ptr<Radiosity> once = engineFor(scene, uniformOptions(200, SolverKind::Shooting, 1e-6));
    once->setLights(lightsAt(scene, seconds));
    solveCall(*once);
    return once->stats();
  };
  const Stats last = powerOf(2 / 10.0), first = powerOf(0);
  for (const char* key : {"emitted_watts", "injected_watts", "absorbed_watts", "escaped_watts"})
    EXPECT_NEAR(statNumber(stats, key), statNumber(last, key), 1e-4 * statNumber(last, "absorbed_watts")) << key;
  EXPECT_GT(std::fabs(statNumber(first, "absorbed_watts") - statNumber(last, "absorbed_watts")), 1e-2 * statNumber(last, "absorbed_watts"));
}

// A scene with no light and nothing emitting is black whatever the links, and is not refined
// (a 264k-face interior took 25 s, 621 MiB and 42 MB of link cache for its black picture). A
// light set later refines as a first solve would: the same solution as an engine lit from the
// start.
TEST(RadiosityTest, AnUnlitSceneIsNotRefinedAndLightsSetLaterRefineAsAtFirst) {
  const Scene scene = cornellBoxWithSpots();  // its lamp dark: lit by the spots alone
  ASSERT_FALSE(anyEmits(scene));
  std::unique_ptr<Radiosity> late = engineFor(scene, testing::quietOptions());
  late->setLights({});
  solveCall(*late);
  EXPECT_EQ(statCount(late->stats(), "links"), 0);
  for (const Rgb& b : late->solution().radiosity()) EXPECT_EQ(b.maxComponent(), 0.0);
  late->setLights(lightsAt(scene, 0));
  solveCall(*late);
  std::unique_ptr<Radiosity> lit = engineFor(scene, testing::quietOptions());
  lit->setLights(lightsAt(scene, 0));
  solveCall(*lit);
  EXPECT_GT(statCount(late->stats(), "links"), 1000);
  EXPECT_EQ(statCount(late->stats(), "links"), statCount(lit->stats(), "links"));
  EXPECT_LT(relativeError(late->solution().radiosity(), lit->solution().radiosity()), 1e-6);
}

// With a sky and a sun (the shipped daylit office), a hybrid image draws the sun per pixel, with
// its edges, over the solution, which keeps the sky's direct light (4096 directions an estimate
// cannot be drawn per pixel). It was drawn from the solution alone, the sun patch's edges
// smeared over the elements, while --help called hybrid the default. The two lightings agree on
// the picture's mean: without the sky's part kept in the solution the hybrid one was far darker.
TEST(RadiosityTest, HybridImagesDrawTheSunPerPixelOverTheSkysSolution) {
  Result<Scene> scene = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/scenes/daylight/office-clear.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (Light& light : scene->lights) light.skyDirections = 256;  // the same sky, a sixteenth of the rays: a faster test
  std::unique_ptr<Radiosity> engine = testing::solved(*scene);
  ASSERT_TRUE(engine);
  const SolutionView view = engine->solution();
  for (Shading shading : {Shading::Gouraud, Shading::Flat}) {
    SolutionImageOptions hybrid;
    hybrid.width = 96;
    hybrid.height = 72;
    hybrid.shading = shading;
    SolutionImageOptions radiosity = hybrid;
    radiosity.lighting = Lighting::Radiosity;
    EXPECT_TRUE(drawsLightsPerPixel(view, hybrid));
    const auto meanLuminance = [](const Image& image) {
      double sum = 0;
      for (const Rgb& p : image.pixels) sum += p.luminance();
      return sum / static_cast<double>(image.pixels.size());
    };
    const double perPixel = meanLuminance(renderSolution(view, hybrid)), fromSolution = meanLuminance(renderSolution(view, radiosity));
    std::printf("%s: hybrid %.4f, radiosity %.4f W/(m2 sr)\n", shading == Shading::Flat ? "flat" : "gouraud", perPixel, fromSolution);
    EXPECT_NEAR(perPixel / fromSolution, 1, 0.02);
  }
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
    std::unique_ptr<Radiosity> engine = engineFor(scene, uniformOptions(200, SolverKind::GaussSeidel, 1e-7));
    solveCall(*engine);
    view = &engine->solution();
    before = renderSolution(*view, image);
    engines.push_back(std::move(engine));
  }
  for (int k = 0; k < 16; ++k) engines.push_back(engineFor(testing::closedCube(), uniformOptions(12, SolverKind::GaussSeidel, 1e-7)));
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
// furnace: the point-to-point estimate (cos cos / π r² × A_j between the centres) makes the facing
// patches' rows sum far above 1/ρ, and every solver diverges on them. flat/table.h's
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
