// Moving lights on a fixed scene (the engine with the shoot solver): how many light updates per second a
// per-frame shot budget allows, how far the radiosity lags the moving lights, and how many frames it
// takes to get within 1% of the converged solution once the lights stop. The target: ≥ 60
// light updates per second at 5000 patches on a 2-core machine, with the light within 1% of a fully
// converged solve after the lights stop.
//
// cornell-spots at about --patches patches; form factors computed once (or loaded from
// --cache-dir). For each budget in --shots: a fresh engine, --frames frames with the
// lights at t = frame / fps (both spots turn every frame, so both are re-injected every frame),
// then the lights stop (held at the last frame's) and update() is called until the radiosity is
// within 1% of a cold converged solve for those lights. Prints one JSON document on stdout;
// progress goes to stderr.
//
//   dynamic_bench [--patches 5000] [--frames 240] [--fps 60] [--shots 100,300,1000]
//                 [--light-samples 8] [--tolerance 1e-4] [--max-settle-frames 600]
//                 [--cache-dir /tmp/lambert-bench-cache]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <thread>
#include <time.h>
#include <vector>

#include <nlohmann/json.hpp>

#include "lambert/core/timer.h"
#include "lambert/core/warning.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/light/lights.h"
#include "lambert/scene/builtin.h"
#include "lambert/solve/solver.h"

using namespace lambert;
using Json = nlohmann::ordered_json;

#include <CLI/CLI.hpp>

#include "bench_common.h"

namespace {

using namespace lambert::bench;

constexpr double kTargetUpdatesPerSecond = 60;
constexpr double kTargetRelativeError = 0.01;
// The reference is Eigen LU up to this many patches, Gauss–Seidel to 1e-9 above.
constexpr std::size_t kDirectMaxPatches = 3000;
constexpr double kReferenceTolerance = 1e-9;

struct Options {
  std::size_t patches = 5000;
  int frames = 240;
  double fps = 60;
  std::vector<long long> shots{100, 300, 1000};
  int lightSamples = 8;
  double tolerance = 1e-4;
  int maxSettleFrames = 600;
  std::string cacheDirectory = "/tmp/lambert-bench-cache";
};

Options parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"dynamic_bench: moving spotlights on cornell-spots at a per-frame shot budget, as JSON"};
  app.add_option("--patches", options.patches, "Target patch count")->check(CLI::Range(std::size_t{1}, std::size_t{200000}))->capture_default_str();
  app.add_option("--frames", options.frames, "Frames with the lights moving")->check(CLI::Range(1, 1000000))->capture_default_str();
  app.add_option("--fps", options.fps, "Frames per scene second: the lights move 1/F s a frame")
      ->check(CLI::Range(1e-3, 1e6))
      ->capture_default_str();
  app.add_option("--shots", options.shots, "Per-frame shot budgets to compare; 0 = until converged")
      ->delimiter(',')
      ->check(CLI::Range(0LL, 1000000000LL))
      ->capture_default_str();
  app.add_option("--light-samples", options.lightSamples, "Direct-light points per patch")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--tolerance", options.tolerance, "Unshot power fraction the shooter stops at")
      ->check(CLI::Range(1e-15, 1.0))
      ->capture_default_str();
  app.add_option("--max-settle-frames", options.maxSettleFrames, "Frames to wait for 1% after the lights stop")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--cache-dir", options.cacheDirectory, "Form-factor cache; '' disables it")->capture_default_str();
  parseOrExit(app, argc, argv);
  return options;
}

// Relative errors to three significant digits.
double significant(double value) {
  if (value == 0 || !std::isfinite(value)) return value;
  int decimals = 2 - static_cast<int>(std::floor(std::log10(std::fabs(value))));
  return roundDigits(value, decimals);
}

// mean, p50, p95 and max of a sample of seconds (nearest-rank percentiles).
Json distribution(std::vector<double> values) {
  if (values.empty()) return nullptr;
  std::sort(values.begin(), values.end());
  auto rank = [&](double p) {
    std::size_t k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size())));
    return values[std::min(values.size() - 1, k == 0 ? 0 : k - 1)];
  };
  double mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  return Json{{"mean", seconds(mean)}, {"p50", seconds(rank(0.5))}, {"p95", seconds(rank(0.95))},
              {"max", seconds(values.back())}};
}

struct Deviation {
  double maxRelative = 0;   // max over patches and channels of |B − B_ref|, over max B_ref
  double meanRelative = 0;  // mean over patches with max_c B_ref > 1% of the max of max_c|ΔB| / max_c B_ref
  double maxRelativeIndirect = 0;  // the same max |ΔB| over the max of the reference's indirect light

  Json json() const {
    return Json{{"max_rel", significant(maxRelative)}, {"mean_rel", significant(meanRelative)},
                {"max_rel_indirect", significant(maxRelativeIndirect)}};
  }
};

struct Reference {
  std::vector<Rgb> radiosity;  // B_ref
  double maxRadiosity = 0;
  double maxIndirect = 0;      // max over patches and channels of B_ref − injected
};

Deviation compare(const std::vector<Rgb>& radiosity, const Reference& reference) {
  Deviation error;
  double worst = 0, sum = 0;
  std::size_t counted = 0;
  for (std::size_t i = 0; i < radiosity.size(); ++i) {
    const Rgb& ref = reference.radiosity[i];
    double patchWorst = 0;
    for (int c = 0; c < 3; ++c) patchWorst = std::fmax(patchWorst, std::fabs(radiosity[i][c] - ref[c]));
    worst = std::fmax(worst, patchWorst);
    if (ref.maxComponent() > 0.01 * reference.maxRadiosity) {
      sum += patchWorst / ref.maxComponent();
      ++counted;
    }
  }
  error.maxRelative = worst / reference.maxRadiosity;
  error.meanRelative = counted > 0 ? sum / static_cast<double>(counted) : 0;
  error.maxRelativeIndirect = reference.maxIndirect > 0 ? worst / reference.maxIndirect : INFINITY;
  return error;
}

// When an error measure first fell to 1% after the lights stopped, and what it took.
struct Settle {
  bool reached = false;
  int frames = 0;
  double seconds = 0;  // inject + solve seconds of those frames
  long long shots = 0;

  void note(double error, int frame, double s, long long n) {
    if (reached || error > kTargetRelativeError) return;
    reached = true;
    frames = frame;
    seconds = s;
    shots = n;
  }
  Json json(double fps) const {
    if (!reached)
      return Json{{"frames_to_1_percent", nullptr}, {"seconds_to_1_percent", nullptr},
                  {"scene_seconds_to_1_percent", nullptr}, {"shots_to_1_percent", nullptr}};
    return Json{{"frames_to_1_percent", frames}, {"seconds_to_1_percent", ::seconds(seconds)},
                {"scene_seconds_to_1_percent", roundDigits(frames / fps, 4)}, {"shots_to_1_percent", shots}};
  }
};

struct Setup {
  Scene scene = cornellBoxWithSpots();
  RadiosityOptions options;           // the uniform mesh, form factors, light samples, cache
  std::unique_ptr<Radiosity> coldEngine;  // LU (or Gauss–Seidel to 1e-9): the references

  std::vector<Light> lightsAt(double t) const {
    std::vector<Light> lights;
    for (const Light& light : scene.lights) lights.push_back(lightAtTime(light, t));
    return lights;
  }

  // A fresh engine over the same mesh and form factors (from the cache when there is one).
  std::unique_ptr<Radiosity> engine(SolverKind solver, double tolerance, int maxIterations) const {
    RadiosityOptions o = options;
    o.solver = solver;
    o.tolerance = tolerance;
    o.maxIterations = maxIterations;
    Result<std::unique_ptr<Radiosity>> created = Radiosity::create(scene, o);
    if (!created) {
      std::fprintf(stderr, "dynamic_bench: %s\n", created.error().message.c_str());
      std::exit(1);
    }
    return std::move(*created);
  }

  // Inject the lights and solve cold, to convergence.
  Reference solve(const std::vector<Light>& lights, Json* report) const {
    coldEngine->setLights(lights);
    Result<SolveReport> solved = coldEngine->solve();
    const SolutionView& view = coldEngine->solution();
    Reference reference;
    reference.radiosity = view.radiosity();
    for (std::size_t i = 0; i < reference.radiosity.size(); ++i) {
      reference.maxRadiosity = std::fmax(reference.maxRadiosity, reference.radiosity[i].maxComponent());
      reference.maxIndirect = std::fmax(reference.maxIndirect, (reference.radiosity[i] - view.injected()[i]).maxComponent());
    }
    if (report)
      *report = Json{{"solver", solverName(coldEngine->options().solver)}, {"iterations", solved->iterations},
                     {"residual", relativeResidual(radiosityProblem(view), view.radiosity())}, {"converged", solved->converged},
                     {"seconds", seconds(solved->solveSeconds)}};
    return reference;
  }
};

// The frames at which the moving solution is compared with a cold solve: the end of every scene
// second and the last moving frame.
std::vector<int> checkpoints(const Options& options) {
  std::vector<int> frames;
  int perSecond = std::max(1, static_cast<int>(std::lround(options.fps)));
  for (int f = perSecond - 1; f < options.frames - 1; f += perSecond) frames.push_back(f);
  frames.push_back(options.frames - 1);
  return frames;
}

Json runBudget(const Setup& setup, const Options& options, long long budget,
               const std::map<int, Reference>& references, const Reference& stopped) {
  // Progressive refinement with its state kept between frames: each frame shoots what changed.
  std::unique_ptr<Radiosity> dynamic = setup.engine(SolverKind::Shooting, options.tolerance, 1000000);
  const SolveBudget frameBudget{.maxShots = budget};
  auto update = [&](const std::vector<Light>& lights) {
    dynamic->setLights(lights);
    return *dynamic->solve(frameBudget);
  };

  // Moving: every frame both spots have turned, so both are re-injected.
  std::vector<double> inject, solve, frame, wall;
  std::vector<double> shots;
  Json tracking = Json::array();
  double unshotLast = 0;
  int lightsUpdatedMin = std::numeric_limits<int>::max();
  const std::string loadBefore = loadAverage();
  const double cpuBefore = processCpuSeconds();
  double movingWall = 0;
  for (int f = 0; f < options.frames; ++f) {
    std::vector<Light> lights = setup.lightsAt(f / options.fps);
    Timer timer;
    SolveReport report = update(lights);
    double w = timer.seconds();
    movingWall += w;
    wall.push_back(w);
    inject.push_back(report.injectSeconds);
    solve.push_back(report.solveSeconds);
    frame.push_back(report.injectSeconds + report.solveSeconds);
    shots.push_back(static_cast<double>(report.iterations));
    unshotLast = report.unshotFraction;
    lightsUpdatedMin = std::min(lightsUpdatedMin, report.lightsInjected);
    if (auto it = references.find(f); it != references.end()) {
      Json point = compare(dynamic->solution().radiosity(), it->second).json();
      point["frame"] = f;
      point["t"] = roundDigits(f / options.fps, 4);
      point["unshot_fraction"] = significant(report.unshotFraction);
      tracking.push_back(std::move(point));
    }
  }
  const double movingCpu = processCpuSeconds() - cpuBefore;
  const double meanFrame = std::accumulate(frame.begin(), frame.end(), 0.0) / static_cast<double>(frame.size());
  const double updatesPerSecond = 1.0 / meanFrame;

  // Stopped: the last frame's lights, again and again; nothing is re-injected, only shot. Counted
  // twice: until B is within 1% of the brightest reference patch (max_rel), and until the indirect
  // light is, |ΔB| ≤ 1% of the brightest reference indirect patch (max_rel_indirect; a stricter
  // bar, as the injected direct light is exact from the frame it is injected).
  const std::vector<Light> held = setup.lightsAt((options.frames - 1) / options.fps);
  const Deviation atStop = compare(dynamic->solution().radiosity(), stopped);
  Settle total, indirect;
  total.note(atStop.maxRelative, 0, 0, 0);
  indirect.note(atStop.maxRelativeIndirect, 0, 0, 0);
  int settleFrames = 0;
  double settleSeconds = 0;
  long long settleShots = 0;
  bool stalled = false;
  while (!(total.reached && indirect.reached) && settleFrames < options.maxSettleFrames) {
    SolveReport report = update(held);
    ++settleFrames;
    settleSeconds += report.injectSeconds + report.solveSeconds;
    settleShots += report.iterations;
    Deviation now = compare(dynamic->solution().radiosity(), stopped);
    total.note(now.maxRelative, settleFrames, settleSeconds, settleShots);
    indirect.note(now.maxRelativeIndirect, settleFrames, settleSeconds, settleShots);
    if (report.iterations == 0 && !(total.reached && indirect.reached)) {
      stalled = true;  // the shooter is at its tolerance and will not move again
      break;
    }
  }
  const bool reached = total.reached;
  const Deviation last = compare(dynamic->solution().radiosity(), stopped);

  Json row;
  row["shots_per_frame"] = budget == 0 ? Json("until converged") : Json(budget);
  row["moving"] = Json{
      {"frames", options.frames},
      {"lights_updated_per_frame_min", lightsUpdatedMin},
      {"inject_seconds", distribution(inject)},
      {"solve_seconds", distribution(solve)},
      {"frame_seconds", distribution(frame)},
      {"update_call_wall_seconds", distribution(wall)},
      {"updates_per_second", roundDigits(updatesPerSecond, 1)},
      {"inject_share", roundDigits(std::accumulate(inject.begin(), inject.end(), 0.0) /
                                       std::accumulate(frame.begin(), frame.end(), 0.0), 3)},
      {"shots_mean", roundDigits(std::accumulate(shots.begin(), shots.end(), 0.0) / static_cast<double>(shots.size()), 1)},
      {"unshot_fraction_last", significant(unshotLast)},
      {"wall_seconds", seconds(movingWall)},
      {"cpu_seconds", seconds(movingCpu)},
      {"load_average_before", loadBefore},
      {"tracking_error", std::move(tracking)}};
  Json stop;
  stop["error_at_stop"] = atStop.json();
  const Json totalJson = total.json(options.fps);
  for (const auto& [key, value] : totalJson.items()) stop[key] = value;
  stop["indirect"] = indirect.json(options.fps);
  stop["stalled_at_tolerance"] = stalled;
  stop["frames_run"] = settleFrames;
  stop["error_final"] = last.json();
  row["stopped"] = std::move(stop);
  row["meets_updates_per_second"] = updatesPerSecond >= kTargetUpdatesPerSecond;
  row["converged_within_1_percent"] = reached;
  row["meets_target"] = updatesPerSecond >= kTargetUpdatesPerSecond && reached;
  row["converged_within_1_percent_indirect"] = indirect.reached;
  row["meets_target_indirect"] = updatesPerSecond >= kTargetUpdatesPerSecond && indirect.reached;

  std::fprintf(stderr,
               "  %lld shots/frame: %.1f updates/s (inject %.2f ms, solve %.2f ms mean); error at stop %.3g "
               "(indirect %.3g); frames to 1%%: %d (indirect %d; -1: not reached)\n",
               budget, updatesPerSecond, 1e3 * row["moving"]["inject_seconds"]["mean"].get<double>(),
               1e3 * row["moving"]["solve_seconds"]["mean"].get<double>(), atStop.maxRelative,
               atStop.maxRelativeIndirect, total.reached ? total.frames : -1, indirect.reached ? indirect.frames : -1);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  Options options = parseOptions(argc, argv);
  Setup setup;
  setup.options.meshing = MeshStrategy::Uniform;  // shooting is for the flat methods
  setup.options.uniform.targetPatches = options.patches;
  setup.options.directLight.samplesPerPatch = options.lightSamples;
  setup.options.formFactors.showProgress = true;  // the defaults otherwise: area Monte Carlo, 16 sample pairs
  setup.options.cacheDirectory = options.cacheDirectory;

  Json doc;
  doc["machine"] = cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) + " hardware threads)";
  doc["date"] = utcNow();
  doc["build"] = buildDescription();
  doc["load_average_at_start"] = loadAverage();
  doc["scene"] = setup.scene.name;
  doc["target_patches"] = options.patches;

  // The reference engine computes (or loads) the form factors first; later engines load them.
  std::fprintf(stderr, "dynamic_bench: meshing %s for %zu patches, form factors (cache: %s)\n", setup.scene.name.c_str(),
               options.patches, options.cacheDirectory.empty() ? "off" : options.cacheDirectory.c_str());
  std::string cacheWarning;
  WarningSink previousSink = setWarningSink([&](const std::string& message) {
    std::fprintf(stderr, "lambert: warning: %s\n", message.c_str());
    cacheWarning += (cacheWarning.empty() ? "" : "\n") + message;
  });
  Timer ffTimer;
  const std::size_t n = uniformMesh(setup.scene, setup.options.uniform).numPatches();
  setup.coldEngine = setup.engine(n <= kDirectMaxPatches ? SolverKind::Direct : SolverKind::GaussSeidel, kReferenceTolerance, 10000);
  const double ffSeconds = ffTimer.seconds();
  setWarningSink(previousSink);
  setup.options.formFactors.showProgress = false;
  doc["patches"] = n;

  const Stats setupStats = setup.coldEngine->stats();
  const std::string cache = std::get<std::string>(setupStats.find("formfactor_cache")->value);
  const bool fromCache = cache.rfind("loaded ", 0) == 0;
  Json ff;
  ff["method"] = formFactorMethodName(setup.options.formFactors.method);
  ff["sample_pairs"] = setup.options.formFactors.samplePairs;
  ff["cache"] = options.cacheDirectory.empty() ? "off" : (fromCache ? "loaded" : "computed and saved");
  ff["from_cache"] = fromCache;
  ff["cache_file"] = options.cacheDirectory.empty() ? "" : cache.substr(cache.find(' ') + 1);
  if (!cacheWarning.empty()) ff["cache_warning"] = cacheWarning;
  ff["seconds"] = seconds(ffSeconds);  // mesh, BVH and compute time, or load time when from_cache
  if (!fromCache) ff["visibility_rays"] = std::get<std::int64_t>(setupStats.find("visibility_rays")->value);
  ff["matrix_mib"] = roundDigits(static_cast<double>(n) * static_cast<double>(n) * sizeof(float) / (1024.0 * 1024.0), 1);
  doc["formfactor_seconds"] = fromCache ? Json(nullptr) : Json(seconds(ffSeconds));
  doc["formfactors"] = std::move(ff);
  std::fprintf(stderr, "dynamic_bench: %zu patches, form factors %s in %.2f s\n", n, fromCache ? "loaded" : "computed", ffSeconds);

  doc["lights"] = Json::array();
  for (const Light& light : setup.scene.lights) {
    double speed = length(light.angularVelocity);
    doc["lights"].push_back(Json{{"name", light.name}, {"cone_degrees", light.coneAngleDegrees},
                                 {"angular_speed_rad_per_s", roundDigits(speed, 4)}});
  }
  doc["light_samples_per_patch"] = options.lightSamples;
  doc["frames"] = options.frames;
  doc["fps"] = options.fps;
  doc["scene_seconds_moving"] = roundDigits(options.frames / options.fps, 4);
  doc["shooter_tolerance"] = options.tolerance;
  doc["max_settle_frames"] = options.maxSettleFrames;
  doc["error_measure"] =
      "max_rel: max over patches and channels of |B - B_ref| / max B_ref; mean_rel: mean over patches with "
      "max_c B_ref > 1% of that max of max_c |B - B_ref| / max_c B_ref; max_rel_indirect: the same max |B - B_ref| "
      "over the max of B_ref less the injected direct light";

  // References: a cold converged solve at each tracking checkpoint; the last is the stopped lights'.
  std::map<int, Reference> references;
  Json referenceJson = Json::array();
  for (int f : checkpoints(options)) {
    std::fprintf(stderr, "dynamic_bench: reference solve for frame %d\n", f);
    Json report;
    references.emplace(f, setup.solve(setup.lightsAt(f / options.fps), &report));
    report["frame"] = f;
    referenceJson.push_back(std::move(report));
  }
  doc["reference"] = Json{{"solver", n <= kDirectMaxPatches ? solverName(SolverKind::Direct) : solverName(SolverKind::GaussSeidel)},
                          {"tolerance", kReferenceTolerance},
                          {"solves", std::move(referenceJson)}};
  const Reference& stopped = references.at(options.frames - 1);

  Json budgets = Json::array();
  Json metBy = Json::array();
  Json metByIndirect = Json::array();
  bool anyFast = false, anyConverged = false, anyConvergedIndirect = false;
  for (long long budget : options.shots) {
    std::fprintf(stderr, "dynamic_bench: %lld shots per frame, %d frames\n", budget, options.frames);
    Json row = runBudget(setup, options, budget, references, stopped);
    anyFast |= row["meets_updates_per_second"].get<bool>();
    anyConverged |= row["converged_within_1_percent"].get<bool>();
    anyConvergedIndirect |= row["converged_within_1_percent_indirect"].get<bool>();
    if (row["meets_target"].get<bool>()) metBy.push_back(row["shots_per_frame"]);
    if (row["meets_target_indirect"].get<bool>()) metByIndirect.push_back(row["shots_per_frame"]);
    budgets.push_back(std::move(row));
  }
  doc["load_average_at_end"] = loadAverage();
  doc["load_average"] = doc["load_average_at_end"];
  doc["target"] = Json{{"updates_per_second_min", kTargetUpdatesPerSecond},
                       {"within", kTargetRelativeError},
                       {"updates_per_second_met", anyFast},
                       {"converged_within_1_percent", anyConverged},
                       {"met_by", metBy},
                       {"met", !metBy.empty()},
                       {"converged_within_1_percent_indirect", anyConvergedIndirect},
                       {"met_by_indirect", metByIndirect},
                       {"met_indirect", !metByIndirect.empty()}};
  doc["budgets"] = std::move(budgets);

  std::cout << doc.dump(2) << std::endl;
  return 0;
}
