// Many lights: an open-plan office floor of about 10⁵ faces lit by 200 ceiling
// downlights in a regular grid, solved by the default method (hierarchical radiosity) with lux on
// its work planes, as one JSON document on stdout.
//
// The floor (made here, metres, y up): 48 m × 24 m, 2.8 m high, closed by four walls; 60
// clusters of four desks (desk tops 0.8 m above the floor, the work plane), each cluster split by
// a low screen; eight columns. Every rectangle is a grid of faces no longer than --face-size.
// The lights: a 20 × 10 grid at 2.4 m spacing, 2 cm under the ceiling, aimed straight down:
// IES luminaires (LightKind::Luminaire, far field) from an LM-63-2002 file the bench writes, a
// round downlight of 2000 lm with the cosine-power distribution I(γ) = I₀ cos²γ (I₀ = 3Φ/2π =
// 955 cd, nothing above the horizontal), every 5° in γ; or (--lights spot) wide spots (60° cone,
// 20° soft edge, 955 cd on the axis).
//
// Each run is timed from the scene's generation through Radiosity::create, solve() and
// the illuminance meter at the work-plane points (as `lambert solve --work-plane`), in this process,
// from nothing cached.
// The points: each desk's task area (1.6 m × 0.8 m) gridded as EN 12464-1 spaces a
// calculation grid, p = 0.2 · 5^log10(d) with d the area's longer side, at the cells' centres.
// The runs under the default shadow tolerance are repeated (--runs, median reported), then one
// with the exact every-light sum (tolerance 0) for the time ratio and the error: the lux at the
// points against the exact run's, and the direct part alone against the exact sum at the same
// sites of the same solution (the bound |E − E_exact| ≤ τ·U checked at every point).
//
//   office_bench [--runs 3] [--face-size 0.19] [--tolerance 0.01] [--quick]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/core/timer.h"
#include "lambert/design/illuminance.h"
#include "lambert/method/point_gather.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/light/many_lights.h"
#include "lambert/light/photometry.h"
#include "lambert/load/photometry_file.h"

using namespace lambert;
using namespace lambert::bench;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kTargetSeconds = 60;  // the target: solved, with lux on the work planes, in < 60 s on 2 cores
constexpr double kLumensPerWatt = 683;
constexpr double kWidth = 48, kDepth = 24, kHeight = 2.8, kDeskHeight = 0.8;
constexpr double kDeskWidth = 1.6, kDeskDepth = 0.8;  // one desk's top, the task area
constexpr double kLightSpacing = 2.4;
constexpr int kLightsAlongX = 20, kLightsAlongZ = 10;

enum MaterialId { kWall, kFloor, kCeiling, kDesk, kScreen, kColumn };

struct Options {
  std::string lights = "ies";  // "ies" or "spot"
  int runs = 3;
  double faceSize = 0.19;
  double tolerance = 0.01;
  bool quick = false;  // a coarse floor (0.5 m faces), one run: that the bench works, in seconds
};

double lux(const Rgb& irradiance) { return kLumensPerWatt * irradiance.luminance(); }

class FloorBuilder {
 public:
  FloorBuilder(Scene& scene, double faceSize) : scene_(scene), faceSize_(faceSize) {}

  // A rectangle from corner o along u and v, facing u × v, as a grid of faces; returns its surface.
  std::uint32_t rectangle(const std::string& name, int material, const Vec3& o, const Vec3& u, const Vec3& v) {
    const int nu = std::max(1, static_cast<int>(std::ceil(length(u) / faceSize_ - 1e-9)));
    const int nv = std::max(1, static_cast<int>(std::ceil(length(v) / faceSize_ - 1e-9)));
    Surface s;
    s.name = name;
    s.material = material;
    for (int j = 0; j <= nv; ++j)
      for (int i = 0; i <= nu; ++i) s.vertices.push_back(o + u * (static_cast<double>(i) / nu) + v * (static_cast<double>(j) / nv));
    auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (nu + 1) + a); };
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    scene_.surfaces.push_back(std::move(s));
    return static_cast<std::uint32_t>(scene_.surfaces.size() - 1);
  }
  // An axis-aligned box standing on lo.y, faces outward, no bottom; returns its top's surface.
  std::uint32_t box(const std::string& name, int material, const Vec3& lo, const Vec3& hi, bool withTop = true) {
    const Vec3 d = hi - lo;
    std::uint32_t top = 0;
    if (withTop) top = rectangle(name + " top", material, {lo.x, hi.y, lo.z}, {0, 0, d.z}, {d.x, 0, 0});
    rectangle(name + " -x", material, lo, {0, 0, d.z}, {0, d.y, 0});
    rectangle(name + " +x", material, {hi.x, lo.y, lo.z}, {0, d.y, 0}, {0, 0, d.z});
    rectangle(name + " -z", material, lo, {0, d.y, 0}, {d.x, 0, 0});
    rectangle(name + " +z", material, {lo.x, lo.y, hi.z}, {d.x, 0, 0}, {0, d.y, 0});
    return top;
  }

 private:
  Scene& scene_;
  double faceSize_;
};

struct TaskArea {
  std::uint32_t surface;  // the desk cluster's top
  Vec3 lo;                // the desk's corner (least x, z) on the work plane
};

struct Office {
  Scene scene;
  std::vector<TaskArea> desks;
};

constexpr double kDownlightLumens = 2000;
const double kPeakCandela = 3 * kDownlightLumens / (2 * kPi);  // ∫ I₀cos²γ dω over the lower hemisphere = 2πI₀/3

// The downlight as an IES LM-63-2002 file (absolute photometry: lumens per lamp −1, so the
// candela values are the luminaire's own), written where `directory` says and read back by the
// reader a user's file goes through.
std::shared_ptr<const Photometry> downlightPhotometry(const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  const std::filesystem::path path = directory / "downlight.ies";
  {
    std::ofstream out(path);
    out.precision(10);
    out << "IESNA:LM-63-2002\n[TEST] office_bench\n[LUMINAIRE] round downlight, I = I0 cos^2(gamma), 2000 lm\nTILT=NONE\n";
    out << "1 -1 1 19 1 1 2 -0.15 -0.15 0.02\n1 1 20\n";
    for (int v = 0; v <= 90; v += 5) out << v << (v < 90 ? " " : "\n");
    out << "0\n";
    for (int v = 0; v <= 90; v += 5) {
      const double c = std::cos(v * kPi / 180);
      out << (v < 90 ? kPeakCandela * c * c : 0.0) << (v < 90 ? " " : "\n");
    }
  }
  auto photometry = std::make_shared<const Photometry>(orExit(readIes(path.string()), "office_bench"));
  std::error_code ignored;
  std::filesystem::remove_all(directory, ignored);
  return photometry;
}

Office makeOffice(double faceSize, const std::shared_ptr<const Photometry>& photometry) {
  Office office;
  Scene& scene = office.scene;
  scene.name = "open-plan office";
  scene.metresPerUnit = 1;
  scene.materials = {{"wall", Rgb::gray(0.5)}, {"carpet", Rgb::gray(0.2)},  {"ceiling", Rgb::gray(0.7)},
                     {"desk", Rgb::gray(0.5)}, {"screen", Rgb::gray(0.3)}, {"column", Rgb::gray(0.5)}};
  FloorBuilder b(scene, faceSize);
  b.rectangle("floor", kFloor, {0, 0, 0}, {0, 0, kDepth}, {kWidth, 0, 0});
  b.rectangle("ceiling", kCeiling, {0, kHeight, 0}, {kWidth, 0, 0}, {0, 0, kDepth});
  b.rectangle("south wall", kWall, {0, 0, 0}, {kWidth, 0, 0}, {0, kHeight, 0});
  b.rectangle("north wall", kWall, {0, 0, kDepth}, {0, kHeight, 0}, {kWidth, 0, 0});
  b.rectangle("west wall", kWall, {0, 0, 0}, {0, kHeight, 0}, {0, 0, kDepth});
  b.rectangle("east wall", kWall, {kWidth, 0, 0}, {0, 0, kDepth}, {0, kHeight, 0});
  // 10 × 6 clusters of four desks (two facing two across a 0.45 m screen), 4.8 m × 4 m apart.
  for (int cx = 0; cx < 10; ++cx)
    for (int cz = 0; cz < 6; ++cz) {
      const double x0 = 0.8 + 4.8 * cx, z0 = 1.2 + 4.0 * cz;
      const std::string name = "desks " + std::to_string(cx + 1) + "," + std::to_string(cz + 1);
      const std::uint32_t top = b.box(name, kDesk, {x0, 0, z0}, {x0 + 2 * kDeskWidth, kDeskHeight, z0 + 2 * kDeskDepth});
      b.box(name + " screen", kScreen, {x0, kDeskHeight, z0 + kDeskDepth - 0.02}, {x0 + 2 * kDeskWidth, kDeskHeight + 0.45, z0 + kDeskDepth + 0.02});
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) office.desks.push_back({top, {x0 + i * kDeskWidth, kDeskHeight, z0 + j * kDeskDepth}});
    }
  for (int k = 0; k < 4; ++k)
    for (int side = 0; side < 2; ++side) {
      const double x = 9.6 * (k + 1) - 0.2, z = side ? 16.0 : 8.0;
      b.box("column " + std::to_string(2 * k + side + 1), kColumn, {x - 0.2, 0, z - 0.2}, {x + 0.2, kHeight, z + 0.2}, false);
    }
  for (int i = 0; i < kLightsAlongX; ++i)
    for (int j = 0; j < kLightsAlongZ; ++j) {
      Light light;
      light.name = "downlight " + std::to_string(i + 1) + "," + std::to_string(j + 1);
      light.position = {kLightSpacing * (i + 0.5), kHeight - 0.02, kLightSpacing * (j + 0.5)};
      light.direction = {0, -1, 0};
      if (photometry) {
        light.kind = LightKind::Luminaire;
        light.photometry = photometry;
        light.intensity = Rgb::gray(1);  // white: W/sr = candela / 683
      } else {
        light.kind = LightKind::Spot;
        light.intensity = Rgb::gray(kPeakCandela / kLumensPerWatt);  // on the axis, white
        light.coneAngleDegrees = 60;
        light.falloffDegrees = 20;
      }
      scene.lights.push_back(light);
    }
  return office;
}

// EN 12464-1's calculation-grid spacing for an area whose longer side is d metres.
double gridSpacing(double d) { return 0.2 * std::pow(5.0, std::log10(d)); }

// The work-plane points: each desk's task area gridded at EN 12464-1's spacing, the cells'
// centres, each on the face of its cluster's top that holds it.
std::vector<SurfacePoint> workPlanePoints(const Office& office) {
  const double p = gridSpacing(kDeskWidth);
  const int nx = static_cast<int>(std::ceil(kDeskWidth / p)), nz = static_cast<int>(std::ceil(kDeskDepth / p));
  std::vector<SurfacePoint> points;
  for (const TaskArea& desk : office.desks) {
    const Surface& top = office.scene.surfaces[desk.surface];
    const std::vector<std::vector<std::uint32_t>> faces = surfaceFaces(top);
    for (int i = 0; i < nx; ++i)
      for (int k = 0; k < nz; ++k) {
        SurfacePoint q;
        q.point = desk.lo + Vec3{(i + 0.5) * kDeskWidth / nx, 0, (k + 0.5) * kDeskDepth / nz};
        q.normal = {0, 1, 0};
        q.surface = desk.surface;
        // The face whose (axis-aligned) corners' box holds the point.
        bool found = false;
        for (std::uint32_t f = 0; f < faces.size() && !found; ++f) {
          Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
          for (std::uint32_t v : faces[f]) lo = componentMin(lo, top.vertices[v]), hi = componentMax(hi, top.vertices[v]);
          if (q.point.x >= lo.x && q.point.x <= hi.x && q.point.z >= lo.z && q.point.z <= hi.z) q.face = f, found = true;
        }
        if (!found) {
          std::fprintf(stderr, "office_bench: a work-plane point on no face of %s\n", top.name.c_str());
          std::exit(1);
        }
        points.push_back(q);
      }
  }
  return points;
}

double number(const Stats& stats, const std::string& key) {
  const Stats::Entry* e = stats.find(key);
  if (!e) return 0;
  if (auto i = std::get_if<std::int64_t>(&e->value)) return static_cast<double>(*i);
  if (auto d = std::get_if<double>(&e->value)) return *d;
  return 0;
}

struct Run {
  double cpuSeconds = 0;  // process CPU time over the run, all threads: against seconds, the cores it got
  double seconds = 0, generateSeconds = 0, createSeconds = 0, solveSeconds = 0, pointSeconds = 0;
  std::vector<double> lux;  // at the work-plane points
  Json stats;
  std::unique_ptr<Radiosity> engine;  // kept from the last run, for the direct-light check
  std::vector<SurfacePoint> points;
};

Run run(const Options& options, double tolerance, bool keepEngine) {
  Run r;
  const double cpuBefore = processCpuSeconds();
  Timer total;
  const std::shared_ptr<const Photometry> photometry =
      options.lights == "ies" ? downlightPhotometry(std::filesystem::temp_directory_path() / ("office_bench-" + std::to_string(getpid()))) : nullptr;
  Office office = makeOffice(options.faceSize, photometry);
  r.points = workPlanePoints(office);
  r.generateSeconds = total.seconds();
  RadiosityOptions radiosity;  // the defaults: hierarchical radiosity, as `lambert solve`
  radiosity.directLight.shadowTolerance = tolerance;
  Timer phase;
  std::unique_ptr<Radiosity> engine = orExit(Radiosity::create(std::move(office.scene), radiosity), "office_bench");
  r.createSeconds = phase.seconds();
  phase = Timer();
  orExit(engine->solve(), "office_bench");
  r.solveSeconds = phase.seconds();
  phase = Timer();
  // The lux as `lambert solve --work-plane` measures it (design/illuminance.h).
  IlluminanceOptions meterOptions;
  meterOptions.shadowTolerance = tolerance;
  const IlluminanceMeter meter(engine->solution(), meterOptions);
  std::vector<CalculationPoint> calculationPoints;
  for (const SurfacePoint& q : r.points) calculationPoints.push_back({q.point, q.normal});
  const std::vector<PointIrradiance> e = orExit(meter.measure(calculationPoints), "office_bench");
  r.pointSeconds = phase.seconds();
  r.seconds = total.seconds();
  r.cpuSeconds = processCpuSeconds() - cpuBefore;
  for (const PointIrradiance& x : e) r.lux.push_back(lux(x.total()));
  const Stats stats = engine->stats();
  for (const char* key : {"faces", "patches", "links", "light_splits", "light_edge_samples", "light_edge_rays", "shadow_rays",
                          "lights_reaching_per_point", "shadow_rays_per_point", "inject_seconds", "light_edge_seconds",
                          "link_seconds", "solve_seconds", "iterations"})
    if (stats.find(key)) r.stats[key] = number(stats, key);
  if (keepEngine) r.engine = std::move(engine);
  return r;
}

Json describe(const Run& r) {
  Json j;
  j["seconds"] = seconds(r.seconds);
  j["cpu_seconds"] = seconds(r.cpuSeconds);
  j["generate_seconds"] = seconds(r.generateSeconds);
  j["create_seconds"] = seconds(r.createSeconds);
  j["solve_seconds"] = seconds(r.solveSeconds);
  j["work_plane_seconds"] = seconds(r.pointSeconds);
  j["stats"] = r.stats;
  return j;
}

struct Summary {
  double average = 0, least = INFINITY, most = 0;
};
Summary summarise(const std::vector<double>& values) {
  Summary s;
  for (double v : values) s.average += v, s.least = std::min(s.least, v), s.most = std::max(s.most, v);
  s.average /= std::max<std::size_t>(values.size(), 1);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"office_bench: an open-plan floor of ~10^5 faces and 200 downlights, solved with lux on its desks, as JSON"};
  app.add_option("--runs", options.runs, "runs under the shadow tolerance (median reported)")->check(CLI::Range(1, 20));
  app.add_option("--face-size", options.faceSize, "longest face edge (m)")->check(CLI::Range(0.05, 2.0));
  app.add_option("--tolerance", options.tolerance, "Ward's shadow tolerance τ")->check(CLI::Range(0.0, 0.5));
  app.add_flag("--quick", options.quick, "0.5 m faces, one run");
  app.add_option("--lights", options.lights, "ies (luminaires from an IES file the bench writes) or spot")
      ->check(CLI::IsMember({"ies", "spot"}))
      ->capture_default_str();
  parseOrExit(app, argc, argv);
  if (options.quick) options.faceSize = 0.5, options.runs = 1;

  Json out;
  out["benchmark"] = "office_bench";
  out["utc"] = utcNow();
  out["cpu"] = cpuModel();
  out["threads"] = std::thread::hardware_concurrency();
  out["build"] = buildDescription();
  out["load_average_before"] = loadAverage();
  const double cpuBefore = processCpuSeconds();
  Timer wall;

  std::vector<Run> runs;
  for (int k = 0; k < options.runs; ++k) runs.push_back(run(options, options.tolerance, k + 1 == options.runs));
  Run exact = run(options, 0, false);
  std::vector<double> times;
  for (const Run& r : runs) times.push_back(r.seconds);
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const Run& last = runs.back();

  // The lux at the points against the exact run's (different meshes: the refinement follows the
  // first estimate, so this includes the meshing's own variation).
  std::vector<double> relative;
  double largestLux = 0;
  for (double v : exact.lux) largestLux = std::max(largestLux, v);
  for (std::size_t i = 0; i < exact.lux.size(); ++i)
    relative.push_back(std::fabs(last.lux[i] - exact.lux[i]) / std::max(exact.lux[i], 1e-3 * largestLux));
  const Summary luxError = summarise(relative);

  // The direct light alone, Ward's against the exact sum, at the same sites of one solution: the
  // culling's own error, and the bound checked at every point.
  const SolutionView& view = last.engine->solution();
  const PointGather sites = orExit(pointGather(view, last.points, PointGatherRequest::Sites), "office_bench");
  const DirectLighting ward(view.lights(), view.scene().metresPerUnit, options.tolerance);
  const DirectLighting everyLight(view.lights(), view.scene().metresPerUnit, 0);
  DirectLightingCounts wardCounts, exactCounts;
  std::vector<double> directRelative;
  double worstBoundRatio = 0;
  Timer wardTimer;
  std::vector<Rgb> wardDirect;
  for (const VertexSite& s : sites.sites) wardDirect.push_back(ward.irradiance(s.point, s.normal, view.caster(), sites.rayEpsilon, &wardCounts));
  const double wardSeconds = wardTimer.seconds();
  Timer exactTimer;
  std::vector<Rgb> exactDirect;
  for (const VertexSite& s : sites.sites)
    exactDirect.push_back(everyLight.irradiance(s.point, s.normal, view.caster(), sites.rayEpsilon, &exactCounts));
  const double exactSeconds = exactTimer.seconds();
  for (std::size_t i = 0; i < sites.sites.size(); ++i) {
    const Rgb unoccluded = everyLight.unoccluded(sites.sites[i].point, sites.sites[i].normal);
    directRelative.push_back(std::fabs(lux(wardDirect[i]) - lux(exactDirect[i])) / std::max(lux(exactDirect[i]), 1e-9));
    for (int c = 0; c < 3; ++c)
      if (unoccluded[c] > 0) worstBoundRatio = std::max(worstBoundRatio, std::fabs(wardDirect[i][c] - exactDirect[i][c]) / (options.tolerance * unoccluded[c]));
  }
  const Summary directError = summarise(directRelative);
  const Summary workPlane = summarise(last.lux);

  out["faces"] = last.stats.value("faces", 0.0);
  out["lights"] = kLightsAlongX * kLightsAlongZ;
  out["light"] = options.lights == "ies" ? "IES luminaire (far field), round downlight, I = 955 cd cos²γ, 2000 lm, aimed down"
                                         : "spot, 955 cd on the axis, 60° cone, 20° soft edge, aimed down";
  out["face_size_m"] = options.faceSize;
  out["shadow_tolerance"] = options.tolerance;
  out["work_plane_points"] = last.points.size();
  out["grid_spacing_m"] = roundDigits(gridSpacing(kDeskWidth), 4);
  out["median_seconds"] = seconds(median);
  out["seconds"] = times;
  out["target_seconds"] = kTargetSeconds;
  out["target_met"] = median < kTargetSeconds;
  std::vector<double> cpu;
  for (const Run& r : runs) cpu.push_back(r.cpuSeconds);
  std::sort(cpu.begin(), cpu.end());
  out["median_cpu_seconds"] = seconds(cpu[cpu.size() / 2]);
  out["exact_seconds"] = seconds(exact.seconds);
  out["exact_cpu_seconds"] = seconds(exact.cpuSeconds);
  out["cpu_speedup_vs_exact"] = roundDigits(exact.cpuSeconds / cpu[cpu.size() / 2], 3);
  out["speedup_vs_exact"] = roundDigits(exact.seconds / median, 3);
  out["work_plane_lux"] = {{"average", roundDigits(workPlane.average, 2)}, {"min", roundDigits(workPlane.least, 2)},
                           {"max", roundDigits(workPlane.most, 2)}, {"uniformity_U0", roundDigits(workPlane.least / workPlane.average, 4)}};
  out["lux_error_vs_exact_run"] = {{"mean", roundDigits(luxError.average, 6)}, {"max", roundDigits(luxError.most, 6)}};
  out["direct"] = {{"error_vs_exact_mean", roundDigits(directError.average, 7)},
                   {"error_vs_exact_max", roundDigits(directError.most, 7)},
                   {"worst_error_over_bound", roundDigits(worstBoundRatio, 4)},
                   {"bound_held", worstBoundRatio <= 1 + 1e-9},
                   {"lights_reaching_per_point", roundDigits(static_cast<double>(wardCounts.lightsReaching) / wardCounts.points, 2)},
                   {"shadow_rays_per_point", roundDigits(static_cast<double>(wardCounts.shadowRays) / wardCounts.points, 2)},
                   {"exact_shadow_rays_per_point", roundDigits(static_cast<double>(exactCounts.shadowRays) / exactCounts.points, 2)},
                   {"ward_seconds", seconds(wardSeconds)},
                   {"exact_seconds", seconds(exactSeconds)}};
  Json runsJson = Json::array();
  for (const Run& r : runs) runsJson.push_back(describe(r));
  out["runs"] = runsJson;
  out["exact_run"] = describe(exact);
  out["cpu_seconds"] = seconds(processCpuSeconds() - cpuBefore);
  out["wall_seconds"] = seconds(wall.seconds());
  out["peak_rss_mib"] = peakRssMib();
  out["load_average_after"] = loadAverage();
  std::cout << out.dump(2) << "\n";
  return 0;
}
