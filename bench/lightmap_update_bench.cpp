// Lightmap updates while a spot moves (the target: "moving spot, 10⁶ texels: ≥ 30 lightmap
// updates/s"): the 10⁵-face building (`lambert generate building --rooms 64 --face-size 0.25`),
// its default 1024² atlas (about 0.94 × 10⁶ texels), a spot under the first office's ceiling
// sweeping across its floor as hierarchical_bench's does. Per frame: the engine's warm re-solve
// (one Gauss–Seidel sweep) and LightmapUpdater::update (bake/lightmap_updates.h), timed apart.
// When the spot stops, the solution is converged, updated once more and compared with a fresh
// bake of that solution (relative RMS and largest difference over the covered texels, by the
// mean). Prints one JSON document on stdout.
//
//   lightmap_update_bench [--rooms 64] [--face-size 0.25] [--lightmap-size 1024] [--frames 30]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/bake/lightmap_updates.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/core/timer.h"
#include "lambert/engine/radiosity.h"
#include "lambert/scene/building.h"

using namespace lambert;
using namespace lambert::bench;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kUpdatesPerSecondTarget = 30;

struct Options {
  int rooms = 64;
  double faceSize = 0.25;
  int lightmapSize = 1024;
  int frames = 30;
};

Options parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"lightmap_update_bench: lightmap updates while a spot moves through the 10⁵-face building, as JSON"};
  addBuildingOptions(app, options.rooms, options.faceSize);
  app.add_option("--lightmap-size", options.lightmapSize, "Texels per side of the atlas")->check(CLI::Range(16, 16384))->capture_default_str();
  app.add_option("--frames", options.frames, "Frames the spot moves")->check(CLI::Range(1, 100000))->capture_default_str();
  parseOrExit(app, argc, argv);
  return options;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  Scene scene = orExit(generateBuilding({options.rooms, options.faceSize, 1}), "lightmap_update_bench");
  // A spot under the first office's ceiling, sweeping across its floor (hierarchical_bench's).
  Light spot;
  spot.name = "bench spot";
  spot.kind = LightKind::Spot;
  spot.intensity = Rgb::gray(60);
  spot.coneAngleDegrees = 25;
  spot.falloffDegrees = 5;
  spot.position = scene.camera.eye + Vec3{0, 0.9, 0};
  const auto aimed = [&](int frame) {
    Light l = spot;
    const double angle = 0.05 * frame;
    l.direction = normalize(Vec3{std::cos(angle) * 0.5, -1, std::sin(angle) * 0.5});
    return l;
  };
  scene.lights.push_back(aimed(0));
  std::unique_ptr<Radiosity> engine = orExit(Radiosity::create(scene, RadiosityOptions{}), "lightmap_update_bench");
  orExit(engine->solve(), "lightmap_update_bench");
  const SolutionView& view = engine->solution();
  LightmapBakeOptions bake;
  bake.uvs.atlasSize = options.lightmapSize;
  bake.showProgress = false;
  Timer bakeTimer;
  const BakedLightmaps baked = orExit(bakeLightmaps(view, bake), "lightmap_update_bench");
  const double bakeSeconds = bakeTimer.seconds();
  const double rssBefore = currentRssMib();
  LightmapUpdater updater = orExit(LightmapUpdater::create(view, baked), "lightmap_update_bench");
  const double rssAfter = currentRssMib();

  std::vector<double> solveSeconds, updateSeconds, traced;
  for (int frame = 1; frame <= options.frames; ++frame) {
    engine->setLights({aimed(frame)});
    Timer solveTimer;
    orExit(engine->solve({.maxSweeps = 1}), "lightmap_update_bench");
    solveSeconds.push_back(solveTimer.seconds());
    Timer updateTimer;
    orExit(updater.update(view), "lightmap_update_bench");
    updateSeconds.push_back(updateTimer.seconds());
    traced.push_back(static_cast<double>(updater.stats().directTexelsTraced));
  }
  // The spot stops: converge, update, and compare with a fresh bake of the same solution.
  orExit(engine->solve(), "lightmap_update_bench");
  orExit(updater.update(view), "lightmap_update_bench");
  const BakedLightmaps fresh = orExit(bakeLightmaps(view, baked.uvs, bake), "lightmap_update_bench");
  double sum2 = 0, sumFresh = 0, largest = 0, staleSum2 = 0;
  std::size_t n = 0;
  for (std::size_t a = 0; a < fresh.irradiance.size(); ++a)
    for (std::size_t t = 0; t < fresh.irradiance[a].pixels.size(); ++t) {
      if (!fresh.covered[a][t]) continue;
      const double f = fresh.irradiance[a].pixels[t].luminance();
      const double d = updater.lightmaps()[a].pixels[t].luminance() - f;
      const double stale = baked.irradiance[a].pixels[t].luminance() - f;
      sum2 += d * d;
      staleSum2 += stale * stale;
      sumFresh += f;
      largest = std::fmax(largest, std::fabs(d));
      ++n;
    }
  const double mean = sumFresh / static_cast<double>(n);
  const double update = median(updateSeconds), solve = median(solveSeconds);
  std::vector<double> frameSeconds(updateSeconds.size());
  for (std::size_t i = 0; i < frameSeconds.size(); ++i) frameSeconds[i] = updateSeconds[i] + solveSeconds[i];
  const double frame = median(frameSeconds);
  const LightmapUpdateStats& stats = updater.stats();

  Json doc;
  doc["machine"] = {{"cpu", cpuModel()}, {"threads", std::thread::hardware_concurrency()}, {"build", buildDescription()},
                    {"date", utcNow()}, {"load_average", loadAverage()}};
  doc["scene"] = {{"rooms", options.rooms}, {"face_size_m", options.faceSize}};
  doc["texels"] = stats.texels;
  doc["gather_points"] = stats.gatherPoints;
  doc["weights"] = stats.weights;
  doc["updater_mib"] = roundDigits(static_cast<double>(stats.bytes) / (1024.0 * 1024.0), 1);
  doc["rss_growth_mib"] = roundDigits(rssAfter - rssBefore, 1);
  doc["bake_seconds"] = bench::seconds(bakeSeconds);
  doc["create_seconds"] = bench::seconds(stats.createSeconds);
  doc["frames"] = options.frames;
  doc["update_seconds_median"] = bench::seconds(update);
  doc["resolve_seconds_median"] = bench::seconds(solve);
  doc["frame_seconds_median"] = bench::seconds(frame);
  doc["updates_per_second"] = roundDigits(1 / update, 1);
  doc["updates_per_second_with_resolve"] = roundDigits(1 / frame, 1);
  doc["direct_texels_traced_median"] = median(traced);
  doc["gather_points_updated_last"] = stats.gatherPointsUpdated;
  doc["after_stop"] = {{"rms_vs_fresh_bake", roundDigits(std::sqrt(sum2 / static_cast<double>(n)) / mean, 5)},
                       {"max_vs_fresh_bake", roundDigits(largest / mean, 4)},
                       {"stale_rms_vs_fresh_bake", roundDigits(std::sqrt(staleSum2 / static_cast<double>(n)) / mean, 4)}};
  doc["peak_rss_mib"] = peakRssMib();
  doc["targets"] = Json::array({Json{{"name", "updates_per_second_with_resolve"}, {"min", kUpdatesPerSecondTarget},
                                     {"value", roundDigits(1 / frame, 1)}, {"target_met", 1 / frame >= kUpdatesPerSecondTarget}}});
  std::cout << doc.dump(2) << "\n";
  return 0;
}
