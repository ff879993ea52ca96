// Hierarchical radiosity with clustering, in process, as one JSON document on stdout:
//   dynamic   a spot moving through an office of the ~10⁵-face building: inject + warm re-solve
//             updates per second, and the indirect light after it stops against a cold solve;
//   real_scene  the shipped MGF floor (scenes/floor/floor.mgf) with its cylinders divided into
//             --mgf-divisions segments (1024: ~25,000 faces, the "real scene"), converged.
// The Cornell box's accuracy and time, the buildings' scaling and the link cache are timed as a
// user waits for them, whole `lambert` processes, by bench/default_method_bench.py.
//
//   hierarchical_bench [--quick] [--part all|dynamic|real_scene] [--face-size 0.25] [--real-scene scenes/floor/floor.mgf]
//                      [--mgf-divisions 1024]
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/core/timer.h"
#include "lambert/engine/radiosity.h"
#include "lambert/scene/building.h"
#include "lambert/load/scene_file.h"
#include "lambert/solve/solver.h"

using namespace lambert;
using namespace lambert::bench;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kRealSceneSecondsTarget = 30;
constexpr double kUpdatesPerSecondTarget = 60, kIndirectTarget = 0.01;  // the targets: ≥ 60 updates/s, within 1% after it stops

struct Options {
  bool quick = false;
  double faceSize = 0.25;
  std::string realScene = "scenes/floor/floor.mgf";
  int mgfDivisions = 1024;
  std::string part = "all";  // "dynamic", "real_scene" or both
};

double number(const Stats& stats, const std::string& key) {
  const Stats::Entry* e = stats.find(key);
  if (!e) return 0;
  if (auto i = std::get_if<std::int64_t>(&e->value)) return static_cast<double>(*i);
  if (auto d = std::get_if<double>(&e->value)) return *d;
  return 0;
}

double seconds_(const Stats& stats, const std::string& key) { return bench::seconds(number(stats, key)); }

RadiosityOptions hierarchical() {
  RadiosityOptions options;
  options.meshing = MeshStrategy::Hierarchical;
  options.hierarchical.links.showProgress = true;
  options.tolerance = 1e-6;
  return options;
}

// The scene, or a message naming what is wrong and exit 1.
Scene sceneOrExit(Result<Scene> scene) {
  if (!scene) {
    std::fprintf(stderr, "hierarchical_bench: %s\n", scene.error().message.c_str());
    std::exit(1);
  }
  return std::move(*scene);
}

std::unique_ptr<Radiosity> solved(const Scene& scene, const RadiosityOptions& options, double& seconds) {
  Timer timer;
  auto engine = Radiosity::create(scene, options);
  if (!engine) {
    std::fprintf(stderr, "hierarchical_bench: %s\n", engine.error().message.c_str());
    std::exit(1);
  }
  auto report = (*engine)->solve();
  if (!report) {
    std::fprintf(stderr, "hierarchical_bench: %s\n", report.error().message.c_str());
    std::exit(1);
  }
  seconds = timer.seconds();
  return std::move(*engine);
}

// Indirect light (B less the injected direct light) summed per scene surface, area-weighted: the
// moved engine and a cold one refine differently, so they are compared surface by surface.
std::vector<double> indirectPerSurface(const SolutionView& view) {
  std::vector<double> power(view.scene().surfaces.size(), 0.0);
  const std::vector<Rgb> indirect = view.indirectRadiosity();
  for (std::size_t i = 0; i < indirect.size(); ++i)
    power[view.mesh().patches[i].surface] += indirect[i].luminance() * view.mesh().patches[i].area;
  return power;
}

Json dynamic(int rooms, double faceSize, bool quick) {
  Scene scene = sceneOrExit(generateBuilding({rooms, faceSize, 1}));
  // A spot under the first office's ceiling, sweeping across its floor.
  Light spot;
  spot.name = "bench spot";
  spot.kind = LightKind::Spot;
  spot.intensity = Rgb::gray(60);
  spot.coneAngleDegrees = 25;
  spot.falloffDegrees = 5;
  const Camera& camera = scene.camera;
  spot.position = camera.eye + Vec3{0, 0.9, 0};  // near the ceiling (the eye is at 1.6 m in a 2.8 m room)
  auto aimed = [&](int frame) {
    Light l = spot;
    const double angle = 0.05 * frame;
    l.direction = normalize(Vec3{std::cos(angle) * 0.5, -1, std::sin(angle) * 0.5});
    return l;
  };
  scene.lights.push_back(aimed(0));
  double seconds = 0;
  auto engine = solved(scene, hierarchical(), seconds);
  const int frames = quick ? 30 : 120;
  const int sweeps = 1;  // Gauss–Seidel: one sweep carries the moved light one more bounce
  Timer timer;
  double injectSeconds = 0, solveSeconds = 0;
  for (int frame = 1; frame <= frames; ++frame) {
    engine->setLights({aimed(frame)});
    auto report = engine->solve({.maxSweeps = sweeps});
    if (!report) std::exit(1);
    injectSeconds += report->injectSeconds;
    solveSeconds += report->solveSeconds;
  }
  const double updateSeconds = timer.seconds() / frames;
  // The light stops: solve to the tolerance warm, and compare with a cold solve there.
  auto settled = engine->solve();
  if (!settled) std::exit(1);
  Scene still = scene;
  still.lights = {aimed(frames)};
  double coldSeconds = 0;
  auto cold = solved(still, hierarchical(), coldSeconds);
  const std::vector<double> warm = indirectPerSurface(engine->solution()), truth = indirectPerSurface(cold->solution());
  // Over the surfaces of the spot's own office (within 5 m of it): the rest of the building,
  // lit by its own lamps, would dilute the difference.
  double difference = 0, total = 0;
  for (std::size_t s = 0; s < warm.size(); ++s) {
    if (length(scene.surfaces[s].vertices[0] - spot.position) > 5) continue;
    difference += std::fabs(warm[s] - truth[s]);
    total += std::fabs(truth[s]);
  }
  const double relative = total > 0 ? difference / total : 0;
  const double rate = 1 / updateSeconds;
  return {{"faces", number(engine->stats(), "faces")},
          {"leaves", number(engine->stats(), "patches")},
          {"links", number(engine->stats(), "links")},
          {"first_solve_seconds", bench::seconds(seconds)},
          {"frames", frames},
          {"sweeps_per_update", sweeps},
          {"update_seconds", bench::seconds(updateSeconds)},
          {"inject_seconds_per_update", bench::seconds(injectSeconds / frames)},
          {"solve_seconds_per_update", bench::seconds(solveSeconds / frames)},
          {"updates_per_second", roundDigits(rate, 1)},
          {"settle_sweeps", settled->iterations},
          {"indirect_relative_difference_to_cold", roundDigits(relative, 5)},
          {"targets", Json::array({Json{{"name", "updates_per_second"}, {"min", kUpdatesPerSecondTarget}, {"value", rate}, {"target_met", rate >= kUpdatesPerSecondTarget}},
                                   Json{{"name", "indirect_relative_difference_to_cold"}, {"max", kIndirectTarget}, {"value", relative},
                                        {"target_met", relative <= kIndirectTarget}}})}};
}

Json realScene(const Options& options) {
  LoadOptions load;
  load.mgfDivisions = options.mgfDivisions;
  const Scene scene = sceneOrExit(loadScene(options.realScene, load));
  std::fprintf(stderr, "%s at %d divisions\n", options.realScene.c_str(), options.mgfDivisions);
  double seconds = 0;
  auto engine = solved(scene, hierarchical(), seconds);
  const Stats s = engine->stats();
  return {{"scene", options.realScene},
          {"mgf_divisions", options.mgfDivisions},
          {"faces", number(s, "faces")},
          {"leaves", number(s, "patches")},
          {"links", number(s, "links")},
          {"cluster_links", number(s, "cluster_links")},
          {"visibility_rays", number(s, "visibility_rays")},
          {"link_seconds", seconds_(s, "link_seconds")},
          {"solve_seconds", seconds_(s, "solve_seconds")},
          {"total_seconds", bench::seconds(seconds)},
          {"absorbed_watts", roundDigits(number(s, "absorbed_watts"), 2)},
          {"escaped_watts", roundDigits(number(s, "escaped_watts"), 2)},
          {"peak_rss_mib", peakRssMib()},
          {"targets", Json::array({Json{{"name", "total_seconds"}, {"max", kRealSceneSecondsTarget}, {"value", seconds},
                                        {"target_met", seconds < kRealSceneSecondsTarget}}})}};
}

Options parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"hierarchical_bench: a spot moving through the 10⁵-face building and the MGF floor, in process, as JSON (Cornell and scaling: default_method_bench.py)"};
  app.add_flag("--quick", options.quick, "Fewer dynamic frames, the real scene at 128 divisions");
  app.add_option("--face-size", options.faceSize, "Largest face of the buildings, m")->check(CLI::Range(0.01, 100.0))->capture_default_str();
  app.add_option("--real-scene", options.realScene, "The real scene's file")->capture_default_str();
  auto* divisions = app.add_option("--mgf-divisions", options.mgfDivisions, "The real scene's segments per circle (--quick: 128)")
                        ->check(CLI::Range(3, 1024))
                        ->capture_default_str();
  app.add_option("--part", options.part, "Which measurement to run")
      ->check(CLI::IsMember({"all", "dynamic", "real_scene"}))
      ->capture_default_str();
  parseOrExit(app, argc, argv);
  if (options.quick && !divisions->count()) options.mgfDivisions = 128;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  Json doc;
  doc["machine"] = {{"cpu", cpuModel()}, {"threads", std::thread::hardware_concurrency()}, {"build", buildDescription()},
                    {"date", utcNow()}, {"load_average", loadAverage()}};
  if (options.part != "real_scene") doc["dynamic"] = dynamic(64, options.faceSize, options.quick);
  if (options.part != "dynamic") doc["real_scene"] = realScene(options);
  std::cout << doc.dump(2) << "\n";
  return 0;
}
