// Illuminance at 10⁵ points after the solve (the target: "illuminance at 10⁵ points in < 5 s after
// the solve"): the 10⁵-face building (`lambert generate building --rooms 64 --face-size 0.25`,
// 111k faces, its ceiling panels the lights) solved with the default method, then a work plane
// 0.8 m above its ground floor laid with the spacing that gives about 10⁵ points, measured three
// times (design/illuminance.h: the meter's setup — the solution's vertex irradiance — and every
// point's direct and indirect light); the median, its parts, rays per second.
// Prints one JSON document on stdout.
//
//   illuminance_bench [--rooms 64] [--face-size 0.25] [--points 100000] [--runs 3] [--indirect-rays 256]
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
#include "lambert/core/timer.h"
#include "lambert/design/calculation_grid.h"
#include "lambert/design/illuminance.h"
#include "lambert/engine/radiosity.h"
#include "lambert/scene/building.h"

using namespace lambert;
using namespace lambert::bench;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kSecondsTarget = 5;

struct Options {
  int rooms = 64;
  double faceSize = 0.25;
  int points = 100000;
  int runs = 3;
  int indirectRays = IlluminanceOptions{}.indirectRays;
};

Options parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"illuminance_bench: lux at 10⁵ points of the 10⁵-face building after its solve, as JSON"};
  addBuildingOptions(app, options.rooms, options.faceSize);
  app.add_option("--points", options.points, "Points on the work plane, about")->check(CLI::Range(1, 10000000))->capture_default_str();
  app.add_option("--runs", options.runs, "Runs timed (the median is reported)")->check(CLI::Range(1, 99))->capture_default_str();
  app.add_option("--indirect-rays", options.indirectRays, "Hemisphere rays per point (lambert's --illuminance-rays)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  parseOrExit(app, argc, argv);
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  const Scene scene = orExit(generateBuilding({options.rooms, options.faceSize, 1}), "illuminance_bench");
  Timer solveTimer;
  std::unique_ptr<Radiosity> engine = orExit(Radiosity::create(scene, RadiosityOptions{}), "illuminance_bench");
  orExit(engine->solve(), "illuminance_bench");
  const double solveSeconds = solveTimer.seconds();
  const SolutionView& view = engine->solution();

  const Bounds bounds = sceneBounds(scene);
  const double area = (bounds.hi.x - bounds.lo.x) * (bounds.hi.z - bounds.lo.z) * scene.metresPerUnit * scene.metresPerUnit;
  WorkPlaneSpec plane;
  plane.spacingMetres = std::sqrt(area / options.points);
  const CalculationGrid grid = orExit(workPlaneGrid(scene, plane), "illuminance_bench");

  std::vector<double> seconds, setup, measure;
  std::uint64_t rays = 0;
  double average = 0;
  for (int run = 0; run < options.runs; ++run) {
    Timer timer;  // what a user waits for after the solve: the meter and every point
    IlluminanceOptions illuminance;
    illuminance.indirectRays = options.indirectRays;
    const IlluminanceMeter meter(view, illuminance);
    const std::vector<PointIrradiance> e = orExit(meter.measure(grid.points), "illuminance_bench");
    seconds.push_back(timer.seconds());
    setup.push_back(meter.setupSeconds());
    measure.push_back(seconds.back() - meter.setupSeconds());
    rays = meter.raysCast();
    average = 0;
    for (const PointIrradiance& p : e) average += p.total().luminance() * 683 / static_cast<double>(e.size());
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::size_t faces = 0;
  for (const Surface& surface : scene.surfaces) faces += surfaceFaces(surface).size();
  const double total = median(seconds);
  Json doc;
  doc["machine"] = {{"cpu", cpuModel()}, {"threads", std::thread::hardware_concurrency()}, {"build", buildDescription()},
                    {"date", utcNow()}, {"load_average", loadAverage()}};
  doc["scene"] = {{"rooms", options.rooms}, {"face_size_m", options.faceSize}, {"faces", faces}, {"lights", scene.lights.size()}};
  doc["solve_seconds"] = bench::seconds(solveSeconds);
  doc["points"] = grid.points.size();
  doc["indirect_rays"] = options.indirectRays;
  doc["spacing_m"] = roundDigits(plane.spacingMetres, 4);
  doc["mean_lux"] = roundDigits(average, 1);
  doc["seconds"] = Json::array();
  for (double s : seconds) doc["seconds"].push_back(bench::seconds(s));
  doc["seconds_median"] = bench::seconds(total);
  doc["setup_seconds_median"] = bench::seconds(median(setup));
  doc["measure_seconds_median"] = bench::seconds(median(measure));
  doc["rays_per_run"] = rays;
  doc["points_per_second"] = roundDigits(static_cast<double>(grid.points.size()) / total, 0);
  doc["targets"] = Json::array({Json{{"name", "seconds_median"}, {"max", kSecondsTarget}, {"value", bench::seconds(total)},
                                     {"target_met", total < kSecondsTarget}}});
  std::cout << doc.dump(2) << "\n";
  return 0;
}
