// End-to-end timings of the radiosity pipeline on the Cornell box, one row per patch count:
// mesh → Embree BVH → area Monte Carlo form factors → Gauss–Seidel → 512×512 render, plus (up to
// 3000 patches) the direct LU solve and the seed-000 point-to-point form factors for comparison.
// Prints one JSON document on stdout; progress goes to stderr.
//
//   pipeline_bench [--quick] [--patches 192,784] [--samples 16]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <time.h>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "lambert/core/stats.h"
#include "lambert/core/timer.h"
#include "lambert/flat/form_factors.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/render/solution_image.h"
#include "lambert/scene/builtin.h"
#include "lambert/solve/solver.h"

using namespace lambert;
using Json = nlohmann::ordered_json;

#include <CLI/CLI.hpp>

#include "bench_common.h"

namespace {

using namespace lambert::bench;

// Direct LU and point-to-point form factors run for target patch counts up to this (the target,
// not the mesh's actual count: 3000 meshes to 3152 patches and is still compared).
constexpr std::size_t kComparisonMaxPatches = 3000;
constexpr double kTarget784Seconds = 1.0;

struct Options {
  std::vector<std::size_t> patches{192, 304, 464, 784, 3000, 10000};
  int samples = 16;
};

Options parseOptions(int argc, char** argv) {
  Options options;
  bool quick = false;
  CLI::App app{"pipeline_bench: the whole radiosity pipeline on the Cornell box per mesh size, as JSON"};
  app.add_flag("--quick", quick, "Only 192, 304, 464 and 784 patches");
  auto* patches = app.add_option("--patches", options.patches, "Target patch counts")
                      ->delimiter(',')
                      ->check(CLI::Range(std::size_t{1}, std::size_t{200000}))
                      ->capture_default_str();
  app.add_option("--samples", options.samples, "Area Monte Carlo sample pairs per patch pair")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  parseOrExit(app, argc, argv);
  if (quick && patches->count() == 0) options.patches = {192, 304, 464, 784};
  return options;
}

double statNumber(const Stats& stats, const std::string& key) {
  const Stats::Entry* entry = stats.find(key);
  if (!entry) return NAN;
  if (const auto* i = std::get_if<std::int64_t>(&entry->value)) return static_cast<double>(*i);
  if (const auto* d = std::get_if<double>(&entry->value)) return *d;
  return NAN;
}

std::int64_t statInt(const Stats& stats, const std::string& key) {
  const Stats::Entry* entry = stats.find(key);
  if (entry)
    if (const auto* i = std::get_if<std::int64_t>(&entry->value)) return *i;
  return -1;
}

std::string statString(const Stats& stats, const std::string& key) {
  const Stats::Entry* entry = stats.find(key);
  if (entry)
    if (const auto* s = std::get_if<std::string>(&entry->value)) return *s;
  return "";
}

Json benchSize(const Scene& scene, std::size_t target, int samples) {
  RadiosityOptions options;
  options.meshing = MeshStrategy::Uniform;
  options.uniform.targetPatches = target;
  options.formFactors.method = FormFactorMethod::AreaMonteCarlo;
  options.formFactors.samplePairs = samples;
  options.formFactors.showProgress = true;
  options.solver = SolverKind::GaussSeidel;
  options.tolerance = 1e-7;

  Timer total;
  const double cpuBefore = processCpuSeconds();
  std::unique_ptr<Radiosity> engine = std::move(*Radiosity::create(scene, options));
  if (Result<SolveReport> solved = engine->solve(); !solved) std::fprintf(stderr, "pipeline_bench: %s\n", solved.error().message.c_str());
  Timer renderTimer;
  Image image = renderSolution(engine->solution(), SolutionImageOptions{});
  double renderSeconds = renderTimer.seconds();
  double totalSeconds = total.seconds();
  double cpuSeconds = processCpuSeconds() - cpuBefore;
  if (image.pixels.empty()) std::fprintf(stderr, "pipeline_bench: empty image\n");

  const Stats stats = engine->stats();
  const SolutionView& solution = engine->solution();
  const std::size_t n = solution.mesh().numPatches();
  Json row;
  row["target_patches"] = target;
  row["patches"] = n;
  row["mesh_seconds"] = seconds(statNumber(stats, "mesh_seconds"));
  row["bvh_seconds"] = seconds(statNumber(stats, "bvh_seconds"));
  row["formfactor_seconds"] = seconds(statNumber(stats, "formfactor_seconds"));
  row["sample_pairs"] = samples;
  row["visibility_rays"] = statInt(stats, "visibility_rays");
  row["rays_per_second"] = static_cast<std::int64_t>(std::llround(statNumber(stats, "rays_per_second")));
  row["solver"] = statString(stats, "solver");
  row["iterations"] = statInt(stats, "iterations");
  row["residual"] = statNumber(stats, "residual");
  row["solve_seconds"] = seconds(statNumber(stats, "solve_seconds"));
  row["render_seconds"] = seconds(renderSeconds);
  row["total_seconds"] = seconds(totalSeconds);
  row["cpu_seconds"] = seconds(cpuSeconds);  // process CPU time over the same span as total_seconds
  row["matrix_mib"] = roundDigits(static_cast<double>(n) * n * sizeof(float) / (1024.0 * 1024.0), 1);

  if (target <= kComparisonMaxPatches) {
    std::fprintf(stderr, "  direct LU solve (%zu patches)\n", n);
    std::vector<Rgb> direct;
    SolverReport report = makeSolver(SolverKind::Direct)->solve(radiosityProblem(solution), direct);
    row["direct_solve_seconds"] = seconds(report.seconds);
    row["direct_residual"] = report.residual;

    std::fprintf(stderr, "  point-to-point form factors (%zu patches)\n", n);
    auto caster = makeEmbreeRayCaster(solution.mesh());
    FormFactorOptions pointOptions;
    pointOptions.method = FormFactorMethod::PointToPoint;
    pointOptions.showProgress = true;
    FormFactorStats pointStats;
    {
      FormFactorMatrix F = computeFormFactors(solution.mesh(), *caster, pointOptions, &pointStats);
      (void)F;  // freed here, before anything else is allocated
    }
    row["point_formfactor_seconds"] = seconds(pointStats.seconds);
    row["point_visibility_rays"] = pointStats.visibilityRays;
  }
  return row;  // the engine, and with it the form-factor matrix, is freed here
}

}  // namespace

int main(int argc, char** argv) {
  Options options = parseOptions(argc, argv);
  Scene scene = cornellBox();

  Json doc;
  doc["machine"] = cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) + " hardware threads)";
  doc["date"] = utcNow();
  doc["build"] = buildDescription();
  doc["load_average_at_start"] = loadAverage();
  doc["scene"] = scene.name;
  doc["formfactor_method"] = formFactorMethodName(FormFactorMethod::AreaMonteCarlo);
  doc["solver"] = solverName(SolverKind::GaussSeidel);
  doc["tolerance"] = 1e-7;
  doc["render"] = Json{{"width", SolutionImageOptions{}.width}, {"height", SolutionImageOptions{}.height},
                       {"supersample", SolutionImageOptions{}.supersample}};
  doc["target"] = Json{{"pipeline_784_seconds_max", kTarget784Seconds}, {"met", nullptr}};

  Json sizes = Json::array();
  for (std::size_t target : options.patches) {
    std::fprintf(stderr, "cornell box, %zu target patches\n", target);
    Json row = benchSize(scene, target, options.samples);
    std::fprintf(stderr, "  %lld patches: total %.3f s (form factors %.3f s, solve %.3f s, render %.3f s)\n",
                 static_cast<long long>(row["patches"].get<std::int64_t>()), row["total_seconds"].get<double>(),
                 row["formfactor_seconds"].get<double>(), row["solve_seconds"].get<double>(),
                 row["render_seconds"].get<double>());
    if (target == 784) doc["target"]["met"] = row["total_seconds"].get<double>() <= kTarget784Seconds;
    sizes.push_back(std::move(row));
  }
  doc["sizes"] = std::move(sizes);

  std::cout << doc.dump(2) << std::endl;
  return 0;
}
