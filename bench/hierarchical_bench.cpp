// Hierarchical radiosity with clustering (issue 9's targets), as one JSON document on stdout:
//   cornell   the built-in Cornell box: hierarchical form factors + solve time and the per-vertex
//             relative RMSE against the path tracer (the `compare` metric), beside the flat
//             method at 784 and 3000 patches;
//   scaling   generated office buildings (scene/building.h) from ~10³ to ~10⁶ faces: time per
//             phase, elements, links, rays, peak memory, residual; the growth exponent of time
//             between the sizes (n log n is an exponent a little above 1);
//   dynamic   a spot moving through an office of the ~10⁵-face building: inject + warm re-solve
//             updates per second, and the indirect light after it stops against a cold solve;
//   real_scene  the shipped MGF floor (scenes/floor/floor.mgf) with its cylinders divided into
//             --mgf-divisions segments (1024: ~25,000 faces, the "real scene"), converged.
//
//   hierarchical_bench [--quick] [--rooms 1,8,64,640] [--face-size 0.25] [--reference-samples 1024]
//                      [--real-scene scenes/floor/floor.mgf] [--mgf-divisions 1024]
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
#include "lambert/io/vertices.h"
#include "lambert/reference/compare.h"
#include "lambert/reference/reference.h"
#include "lambert/scene/builtin.h"
#include "lambert/scene/building.h"
#include "lambert/scene/scene_file.h"
#include "lambert/solve/solver.h"

using namespace lambert;
using namespace lambert::bench;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kCornellRmseTarget = 0.03, kCornellSecondsTarget = 1.0;
constexpr double kRealSceneSecondsTarget = 30;
constexpr double k1e5SecondsTarget = 60, k1e5MemoryTargetMib = 4096, kUpdatesPerSecondTarget = 30, kIndirectTarget = 0.02;

struct Options {
  bool quick = false;
  int referenceSamples = 1024;  // per vertex of the Cornell box's path-traced reference
  std::vector<int> rooms{1, 8, 64, 640};
  double faceSize = 0.25;
  std::string realScene = "scenes/floor/floor.mgf";
  int mgfDivisions = 1024;
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

// Per-vertex relative RMSE against the path tracer at the solution's own vertices; adds the
// time the solution took to give its vertex values (the hierarchical final gather) to seconds.
// `truth` receives the reference's samples at those vertices.
double cornellError(const Scene& scene, const SolutionView& view, const ReferenceRenderer& tracer, double& seconds,
                    std::vector<VertexSample>& truth) {
  const Mesh& mesh = view.vertexMesh();
  Timer timer;
  std::vector<VertexSample> mine = vertexSamples(mesh, view.vertexRadiance());
  seconds += timer.seconds();
  truth = vertexSamples(mesh, tracer.vertexRadiance(mesh));
  Result<VertexComparison> c = compareVertices(scene, mine, truth);
  return c ? c->error.relativeRmse : NAN;
}

Json cornell(bool quick, int referenceSamples) {
  const Scene scene = cornellBox();
  ReferenceOptions referenceOptions;
  referenceOptions.showProgress = true;
  referenceOptions.vertexSamples = referenceSamples;
  ReferenceRenderer tracer(scene, subdivideScene(scene, 2 * sceneDiagonal(scene)), referenceOptions);
  Json out;
  double seconds = 0, work = 0, rmse = 0;
  Mesh defaultMesh;  // the default link error's vertex mesh, and the reference at its vertices
  std::vector<VertexSample> defaultTruth, truth;
  // The default link error, and a finer one.
  for (double linkError : {2e-4, 5e-5}) {
    RadiosityOptions options = hierarchical();
    options.hierarchical.links.linkError = linkError;
    auto h = solved(scene, options, seconds);
    const Stats stats = h->stats();
    double gatherSeconds = 0;
    const double hRmse = cornellError(scene, h->solution(), tracer, gatherSeconds, truth);
    const double hWork = number(stats, "formfactor_seconds") + number(stats, "solve_seconds") + gatherSeconds;
    if (linkError == 2e-4) {
      work = hWork, rmse = hRmse;
      defaultMesh = h->solution().vertexMesh();
      defaultTruth = std::move(truth);
    }
    out[linkError == 2e-4 ? "hierarchical" : "hierarchical_5e-5"] = {
        {"link_error", linkError},
        {"leaves", number(stats, "patches")},
        {"links", number(stats, "links")},
        {"visibility_rays", number(stats, "visibility_rays")},
        {"formfactor_seconds", seconds_(stats, "formfactor_seconds")},
        {"solve_seconds", seconds_(stats, "solve_seconds")},
        {"gather_seconds", bench::seconds(gatherSeconds)},
        {"seconds", bench::seconds(hWork)},
        {"total_seconds", bench::seconds(seconds)},
        {"vertex_relative_rmse", roundDigits(hRmse, 5)}};
  }
  for (std::size_t patches : quick ? std::vector<std::size_t>{784} : std::vector<std::size_t>{784, 3000}) {
    RadiosityOptions flat;
    flat.meshing = MeshStrategy::Uniform;
    flat.uniform.targetPatches = patches;
    flat.formFactors.showProgress = true;
    auto f = solved(scene, flat, seconds);
    const Stats fs = f->stats();
    double interpolateSeconds = 0;
    const double fRmse = cornellError(scene, f->solution(), tracer, interpolateSeconds, truth);
    out["flat_" + std::to_string(patches)] = {
        {"patches", number(fs, "patches")},
        {"seconds", bench::seconds(number(fs, "formfactor_seconds") + number(fs, "solve_seconds") + interpolateSeconds)},
        {"vertex_relative_rmse", roundDigits(fRmse, 5)}};
  }
  // The reference's own noise: the same vertices traced with another seed, compared the same way
  // (the difference of two references, so each one's own noise is this over √2).
  {
    ReferenceOptions other = referenceOptions;
    other.seed = referenceOptions.seed + 1;
    ReferenceRenderer second(scene, subdivideScene(scene, 2 * sceneDiagonal(scene)), other);
    Result<VertexComparison> noise =
        compareVertices(scene, vertexSamples(defaultMesh, second.vertexRadiance(defaultMesh)), defaultTruth);
    out["reference_samples"] = referenceSamples;
    out["reference_noise_vertex_relative_rmse"] = roundDigits(noise ? noise->error.relativeRmse : NAN, 5);
  }
  out["targets"] = Json::array({Json{{"name", "vertex_relative_rmse"}, {"max", kCornellRmseTarget}, {"value", rmse}, {"target_met", rmse <= kCornellRmseTarget}},
                                Json{{"name", "seconds"}, {"max", kCornellSecondsTarget}, {"value", work}, {"target_met", work < kCornellSecondsTarget}}});
  return out;
}

Json scaling(const Options& options, std::vector<std::pair<double, double>>& facesAndSeconds) {
  Json rows = Json::array();
  for (int rooms : options.rooms) {
    const Scene scene = sceneOrExit(generateBuilding({rooms, options.faceSize, 1}));
    std::fprintf(stderr, "building of %d rooms\n", rooms);
    double seconds = 0;
    auto engine = solved(scene, hierarchical(), seconds);
    const Stats s = engine->stats();
    const double faces = number(s, "faces");
    facesAndSeconds.push_back({faces, seconds});
    rows.push_back({{"rooms", rooms},
                    {"faces", faces},
                    {"leaves", number(s, "patches")},
                    {"elements", number(s, "elements")},
                    {"clusters", number(s, "clusters")},
                    {"links", number(s, "links")},
                    {"visibility_rays", number(s, "visibility_rays")},
                    {"light_edge_samples", number(s, "light_edge_samples")},
                    {"link_mib", roundDigits(number(s, "link_bytes"), 1)},
                    {"bytes_per_link", roundDigits(number(s, "bytes_per_link"), 2)},
                    {"hierarchy_mib", roundDigits(number(s, "node_bytes"), 1)},
                    {"link_seconds", seconds_(s, "link_seconds")},
                    {"leaf_mesh_seconds", seconds_(s, "leaf_mesh_seconds")},
                    {"solve_seconds", seconds_(s, "solve_seconds")},
                    {"total_seconds", bench::seconds(seconds)},
                    {"residual", number(s, "residual")},
                    {"converged", s.find("converged") ? std::get<std::string>(s.find("converged")->value) : "?"},
                    {"peak_rss_mib", peakRssMib()}});
  }
  return rows;
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
  CLI::App app{"hierarchical_bench: hierarchical radiosity on the Cornell box and on generated buildings, as JSON"};
  app.add_flag("--quick", options.quick, "Buildings of 1, 8 and 64 rooms only, fewer dynamic frames, flat at 784 patches only");
  auto* rooms = app.add_option("--rooms", options.rooms, "Building sizes (offices) for the scaling curve")->delimiter(',')->check(CLI::Range(1, 100000));
  app.add_option("--reference-samples", options.referenceSamples,
                 "Cornell box: path-traced samples per vertex of the reference (its noise is reported)")
      ->check(CLI::Range(16, 1 << 20))
      ->capture_default_str();
  app.add_option("--face-size", options.faceSize, "Largest face of the buildings, m")->check(CLI::Range(0.01, 100.0))->capture_default_str();
  app.add_option("--real-scene", options.realScene, "The real scene's file")->capture_default_str();
  auto* divisions = app.add_option("--mgf-divisions", options.mgfDivisions, "The real scene's segments per circle (--quick: 128)")
                        ->check(CLI::Range(3, 1024))
                        ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
  if (options.quick && !rooms->count()) options.rooms = {1, 8, 64};
  if (options.quick && !divisions->count()) options.mgfDivisions = 128;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  Json doc;
  doc["machine"] = {{"cpu", cpuModel()}, {"threads", std::thread::hardware_concurrency()}, {"build", buildDescription()},
                    {"date", utcNow()}, {"load_average", loadAverage()}};
  doc["cornell"] = cornell(options.quick, options.referenceSamples);
  std::vector<std::pair<double, double>> points;
  doc["scaling"] = scaling(options, points);
  // Growth exponent of time in faces between consecutive sizes: log(t2/t1) / log(n2/n1).
  Json growth = Json::array();
  for (std::size_t i = 1; i < points.size(); ++i)
    growth.push_back({{"from_faces", points[i - 1].first}, {"to_faces", points[i].first},
                      {"exponent", roundDigits(std::log(points[i].second / points[i - 1].second) / std::log(points[i].first / points[i - 1].first), 3)}});
  doc["growth"] = growth;
  Json targets = Json::array();
  for (const Json& row : doc["scaling"])
    if (row["faces"].get<double>() >= 0.9e5 && row["faces"].get<double>() <= 2e5) {
      const double t = row["total_seconds"], m = row["peak_rss_mib"];
      targets.push_back({{"name", "seconds_at_1e5_faces"}, {"max", k1e5SecondsTarget}, {"value", t}, {"target_met", t < k1e5SecondsTarget}});
      targets.push_back({{"name", "peak_rss_mib_at_1e5_faces"}, {"max", k1e5MemoryTargetMib}, {"value", m}, {"target_met", m < k1e5MemoryTargetMib}});
    }
  doc["scaling_targets"] = targets;
  doc["dynamic"] = dynamic(64, options.faceSize, options.quick);
  doc["real_scene"] = realScene(options);
  std::cout << doc.dump(2) << "\n";
  return 0;
}
