// Lightmap bake of the 10⁵-face building (the target: "a 10⁵-face building at 10⁶ texels: < 30 s
// after the solve, < 2 GB"): the building `lambert generate building --rooms 64 --face-size 0.25`
// writes (111k faces), solved with the default method, then baked at the default atlas (one
// 1024² atlas at the smallest texel size whose charts fit it: about 0.94 × 10⁶ texels) three
// times; the median bake, the texels, the process's peak resident set, and the bake's rate.
// Prints one JSON document on stdout.
//
//   lightmap_bench [--rooms 64] [--face-size 0.25] [--lightmap-size 1024] [--runs 3]
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/core/timer.h"
#include "lambert/engine/radiosity.h"
#include "lambert/scene/building.h"

using namespace lambert;
using namespace lambert::bench;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kBakeSecondsTarget = 30, kPeakMibTarget = 2048;

struct Options {
  int rooms = 64;
  double faceSize = 0.25;
  int lightmapSize = 1024;
  int runs = 3;
};

Options parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"lightmap_bench: bake lightmaps of the 10⁵-face building after its solve, as JSON"};
  addBuildingOptions(app, options.rooms, options.faceSize);
  app.add_option("--lightmap-size", options.lightmapSize, "Texels per side of the atlas")->check(CLI::Range(16, 16384))->capture_default_str();
  app.add_option("--runs", options.runs, "Bakes timed (the median is reported)")->check(CLI::Range(1, 99))->capture_default_str();
  parseOrExit(app, argc, argv);
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  const Scene scene = orExit(generateBuilding({options.rooms, options.faceSize, 1}), "lightmap_bench");
  RadiosityOptions radiosity;  // the CLI's default: hierarchical
  Timer solveTimer;
  std::unique_ptr<Radiosity> engine = orExit(Radiosity::create(scene, radiosity), "lightmap_bench");
  orExit(engine->solve(), "lightmap_bench");
  const double solveSeconds = solveTimer.seconds();
  const double rssAfterSolve = currentRssMib();
  const SolutionView& view = engine->solution();

  LightmapBakeOptions bake;
  bake.uvs.atlasSize = options.lightmapSize;
  bake.showProgress = false;
  std::vector<double> seconds;
  std::size_t texels = 0, faces = 0;
  int atlases = 0;
  double efficiency = 0;
  for (int run = 0; run < options.runs; ++run) {
    Timer timer;  // what a user waits for after the solve: the charts, the atlas and the bake
    const BakedLightmaps baked = orExit(bakeLightmaps(view, bake), "lightmap_bench");
    seconds.push_back(timer.seconds());
    texels = baked.texelsBaked;
    atlases = baked.uvs.numAtlases;
    efficiency = baked.uvs.efficiency;
  }
  for (const Surface& surface : scene.surfaces) faces += surfaceFaces(surface).size();
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  const double peak = peakRssMib();

  Json doc;
  doc["machine"] = {{"cpu", cpuModel()}, {"threads", std::thread::hardware_concurrency()}, {"build", buildDescription()},
                    {"date", utcNow()}, {"load_average", loadAverage()}};
  doc["scene"] = {{"rooms", options.rooms}, {"face_size_m", options.faceSize}, {"faces", faces}};
  doc["solve_seconds"] = bench::seconds(solveSeconds);
  doc["rss_after_solve_mib"] = rssAfterSolve;
  doc["atlases"] = atlases;
  doc["atlas_size"] = options.lightmapSize;
  doc["packing_efficiency"] = roundDigits(efficiency, 4);
  doc["texels_baked"] = texels;
  doc["bake_seconds"] = Json::array();
  for (double s : seconds) doc["bake_seconds"].push_back(bench::seconds(s));
  doc["bake_seconds_median"] = bench::seconds(median);
  doc["texels_per_second"] = roundDigits(static_cast<double>(texels) / median, 0);
  doc["peak_rss_mib"] = peak;
  doc["targets"] = Json::array({Json{{"name", "bake_seconds_median"}, {"max", kBakeSecondsTarget}, {"value", bench::seconds(median)},
                                     {"target_met", median < kBakeSecondsTarget}},
                                Json{{"name", "peak_rss_mib"}, {"max", kPeakMibTarget}, {"value", peak}, {"target_met", peak < kPeakMibTarget}}});
  std::cout << doc.dump(2) << "\n";
  return 0;
}
