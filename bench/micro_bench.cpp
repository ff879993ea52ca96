// Micro-benchmarks of lambert's inner loops (Google Benchmark):
//   - the analytic point-to-polygon form factor on a triangle,
//   - Embree occlusion rays through the Cornell box at 784 patches, one at a time and 16 at once,
//   - one Gauss–Seidel sweep of the 784-patch system,
//   - rendering the 784-patch solution at 512×512.
// Single-threaded except the renderer (which uses TBB like the library does).
//
// DoNotOptimize is only ever handed const values: with benchmark 1.7.1 (Debian's) and GCC 12, a
// double passed to the non-const overload (asm constraint "+m,r") and summed afterwards came out as
// garbage; the const overload only reads. The calls timed are in another translation unit, so the
// compiler cannot drop them anyway.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "lambert/core/rng.h"
#include "lambert/flat/form_factors.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/render/rasterizer.h"
#include "lambert/scene/builtin.h"
#include "lambert/light/emission.h"
#include "lambert/solve/problem.h"
#include "lambert/solve/solver.h"

using namespace lambert;

namespace {

constexpr std::size_t kPatches = 784;

// The Cornell box meshed at 784 patches, its BVH, form factors and converged radiosity, built once
// on first use (outside every timed loop).
struct CornellFixture {
  Scene scene = cornellBox();
  Mesh mesh;
  std::unique_ptr<RayCaster> caster;
  RadiosityProblem problem;
  std::vector<Rgb> radiosity;
  std::vector<Ray> rays;  // segments between sample points on mutually facing patches

  CornellFixture() {
    mesh = subdivideScene(scene, edgeLengthForPatchCount(scene, kPatches));
    caster = makeEmbreeRayCaster(mesh);
    FormFactorOptions ffOptions;
    ffOptions.showProgress = false;
    auto F = std::make_shared<DenseTransport>(std::make_shared<FormFactorMatrix>(computeFormFactors(mesh, *caster, ffOptions)));
    problem = makeRadiosityProblem(mesh, emittedRadiosity(scene, mesh), patchAlbedo(scene, mesh), F);
    makeSolver(SolverKind::GaussSeidel)->solve(problem, radiosity);
    makeRays();
  }

  // Like the form-factor estimator's: a random point on patch i to a random point on patch j,
  // both lifted off their surfaces by the ray epsilon, t ∈ [0, 1]. Pairs are on different
  // surfaces and face each other (centroid in front of the other's plane), so the rays are the
  // kind form factors trace; the tall and short blocks occlude some of them.
  void makeRays() {
    constexpr std::size_t kRays = 1 << 16;
    const double epsilon = rayEpsilon(mesh);
    const auto n = static_cast<std::uint32_t>(mesh.numPatches());
    Pcg32 rng(7, 11);
    rays.reserve(kRays);
    while (rays.size() < kRays) {
      std::uint32_t i = rng.nextBelow(n), j = rng.nextBelow(n);
      const Patch& pi = mesh.patches[i];
      const Patch& pj = mesh.patches[j];
      if (pi.surface == pj.surface) continue;
      if (dot(pj.centroid - pi.centroid, pi.normal) <= 0 || dot(pi.centroid - pj.centroid, pj.normal) <= 0) continue;
      Vec3 x = sampleConvexPolygon(mesh.corners(i), rng.nextDouble(), rng.nextDouble()) + pi.normal * epsilon;
      Vec3 y = sampleConvexPolygon(mesh.corners(j), rng.nextDouble(), rng.nextDouble()) + pj.normal * epsilon;
      rays.push_back(Ray{x, y - x, 0, 1});
    }
  }
};

const CornellFixture& cornell() {
  static const CornellFixture fixture;
  return fixture;
}

void BM_PointToPolygonFormFactor(benchmark::State& state) {
  // A triangle above and tilted relative to a set of receiver points on the floor.
  const std::array<Vec3, 3> triangle{Vec3{0, 1, 0}, Vec3{0.6, 1.2, 0.1}, Vec3{0.1, 1.1, 0.7}};
  const Vec3 polygonNormal = normalize(cross(triangle[1] - triangle[0], triangle[2] - triangle[0]));
  const Vec3 up{0, 1, 0};
  constexpr std::size_t kPoints = 64;
  std::vector<Vec3> points;
  Pcg32 rng(3, 5);
  for (std::size_t k = 0; k < kPoints; ++k) points.push_back({rng.nextDouble() * 2 - 1, 0, rng.nextDouble() * 2 - 1});
  // The triangle must face the receivers for a nonzero factor.
  const Vec3 normal = dot(polygonNormal, up) < 0 ? polygonNormal : -polygonNormal;
  std::array<Vec3, 3> polygon = triangle;
  if (normal != polygonNormal) std::swap(polygon[1], polygon[2]);

  std::size_t k = 0;
  double sum = 0;
  for (auto _ : state) {
    const double f = pointToPolygonFormFactor(points[k], up, polygon, normal);
    benchmark::DoNotOptimize(f);
    sum += f;
    k = (k + 1) % kPoints;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["mean_F"] = sum / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PointToPolygonFormFactor);

void BM_EmbreeOccludedSingle(benchmark::State& state) {
  const CornellFixture& f = cornell();
  std::size_t k = 0, blocked = 0;
  for (auto _ : state) {
    const bool occluded = f.caster->occluded(f.rays[k]);
    benchmark::DoNotOptimize(occluded);
    blocked += occluded;
    k = (k + 1) % f.rays.size();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["patches"] = static_cast<double>(f.mesh.numPatches());
  state.counters["occluded_fraction"] = static_cast<double>(blocked) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_EmbreeOccludedSingle);

void BM_EmbreeOccludedBatch16(benchmark::State& state) {
  const CornellFixture& f = cornell();
  constexpr std::size_t kBatch = 16;
  bool out[kBatch];
  std::size_t k = 0, blocked = 0;
  for (auto _ : state) {
    f.caster->occluded(std::span<const Ray>(f.rays.data() + k, kBatch), std::span<bool>(out, kBatch));
    for (bool b : out) blocked += b;
    k += kBatch;
    if (k + kBatch > f.rays.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["patches"] = static_cast<double>(f.mesh.numPatches());
  state.counters["occluded_fraction"] =
      static_cast<double>(blocked) / static_cast<double>(state.iterations() * kBatch);
}
BENCHMARK(BM_EmbreeOccludedBatch16);

// What `makeSolver(GaussSeidel, maxIterations = 1)` costs: one in-place sweep plus the relative
// residual the solver computes before returning (a second pass over F).
void BM_GaussSeidelSolveOneSweep(benchmark::State& state) {
  const CornellFixture& f = cornell();
  SolverOptions options;
  options.maxIterations = 1;
  auto solver = makeSolver(SolverKind::GaussSeidel, options);
  std::vector<Rgb> radiosity = f.problem.emitted;
  for (auto _ : state) {
    const SolverReport report = solver->solve(f.problem, radiosity);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(radiosity.data());
  }
  const double n = static_cast<double>(f.problem.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(f.problem.size()));  // rows
  state.counters["patches"] = n;
  state.counters["matrix_bytes_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n * n * sizeof(float), benchmark::Counter::kIsRate,
                         benchmark::Counter::kIs1024);
}
BENCHMARK(BM_GaussSeidelSolveOneSweep)->Unit(benchmark::kMicrosecond);

// The sweep alone, the solver's own (Transport::sweep in place), no residual: the lower bound of
// the call above.
void BM_GaussSeidelSweepOnly(benchmark::State& state) {
  const CornellFixture& f = cornell();
  const Transport& transport = *f.problem.transport;
  std::vector<Rgb> radiosity = f.problem.emitted;
  const std::size_t n = f.problem.size();
  for (auto _ : state) {
    const SweepChange step = transport.sweep(f.problem.emitted, f.problem.albedo, radiosity, /*inPlace=*/true);
    benchmark::DoNotOptimize(step);
    benchmark::DoNotOptimize(radiosity.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));  // rows
  state.counters["patches"] = static_cast<double>(n);
}
BENCHMARK(BM_GaussSeidelSweepOnly)->Unit(benchmark::kMicrosecond);

void BM_RenderRadiance512(benchmark::State& state) {
  const CornellFixture& f = cornell();
  RenderOptions options;  // 512×512, Gouraud, 2×2 supersampling
  for (auto _ : state) {
    Image image = renderRadiance(f.scene.camera, f.mesh, f.radiosity, options);
    benchmark::DoNotOptimize(image.pixels.data());
  }
  state.SetItemsProcessed(state.iterations() * options.width * options.height);  // pixels
  state.counters["patches"] = static_cast<double>(f.mesh.numPatches());
}
BENCHMARK(BM_RenderRadiance512)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
