// Where the default (hierarchical) method's error is on the Cornell box, as one JSON document on
// stdout (docs/hierarchical.md, "Cornell box, where the error is"). For each seed: the solve at
// --link-error (hierarchy, links, solve and final gather, in process), and the per-vertex relative
// RMSE of compare's metric against a path-traced reference at the solution's own vertices, traced
// twice with --reference-samples each under two seeds: their difference / √2 is one trace's
// noise, and the reference is their mean (its noise a further √2 smaller). Over several seeds, the
// error of the seeds' mean is the bias part, their spread the noise of the links' visibility
// sampling; both are split by where the vertices lie (room edges, the blocks, each surface).
// The reference dominates the time: about 1 s of CPU per 10⁵ samples; --reference-cache FILE
// keeps it per vertex (key: surface, position and evaluation site) between runs.
//
//   cornell_accuracy [--link-error 2e-4] [--seeds 1,2,3] [--reference-samples 16384]
//                    [--reference-cache FILE] [--dump PREFIX] [--visibility-rays N] [--leaf-samples N]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/engine/radiosity.h"
#include "lambert/geometry/coverage.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/io/vertices.h"
#include "lambert/mesh/vertex_radiosity.h"
#include "lambert/reference/compare.h"
#include "lambert/reference/reference.h"
#include "lambert/scene/builtin.h"

using namespace lambert;
using Json = nlohmann::ordered_json;

namespace {

struct Traced {
  Rgb first, second;  // the two seeds' estimates
};

struct Run {
  std::vector<VertexSample> value;
  std::vector<Traced> reference;
  std::vector<char> keep;  // compare's mask: away from the light's rim, not inside a block
  std::vector<std::uint32_t> surface;
  std::vector<std::string> key;
};

std::string category(const Scene& scene, std::uint32_t surface, const Vec3& p) {
  if (surface >= 5) return "blocks";
  const double x = p.x, y = p.y, z = p.z;
  double d;
  if (surface <= 1) d = std::fmin(std::fmin(x, 556 - x), std::fmin(z, 559.2 - z));
  else if (surface == 2) d = std::fmin(std::fmin(x, 556 - x), std::fmin(y, 548.8 - y));
  else d = std::fmin(std::fmin(y, 548.8 - y), std::fmin(z, 559.2 - z));
  if (d < 15) return "within 15 of a room edge";
  return scene.surfaces[surface].name + " (inside)";
}

}  // namespace

int main(int argc, char** argv) {
  double linkError = 2e-4;
  std::vector<std::uint64_t> seeds{1, 2, 3};
  int samples = 16384;
  std::string cachePath, dumpPrefix;
  CLI::App app{"cornell_accuracy: the default method's per-vertex error on the Cornell box and where it is, as JSON"};
  app.add_option("--link-error", linkError, "Link error")->check(CLI::Range(1e-9, 1.0))->capture_default_str();
  int leafSamples = 0;
  app.add_option("--leaf-samples", leafSamples, "Also trace each open leaf's centroid with this many samples (first seed)")
      ->check(CLI::Range(0, 1 << 20));
  int visibilityRays = LinkOptions{}.visibilityRays;
  app.add_option("--visibility-rays", visibilityRays, "Sample pairs per link (and the gather's rays per source)")
      ->check(CLI::Range(1, 255))
      ->capture_default_str();
  app.add_option("--seeds", seeds, "Solve seeds (links' and gather's rays)")->delimiter(',')->capture_default_str();
  app.add_option("--reference-samples", samples, "Samples a vertex for each of the reference's two seeds")
      ->check(CLI::Range(16, 1 << 22))
      ->capture_default_str();
  app.add_option("--reference-cache", cachePath, "File keeping the reference per vertex between runs");
  app.add_option("--dump", dumpPrefix, "Write PREFIX<seed>.csv: per vertex position, surface, mask, value, both references");
  bench::parseOrExit(app, argc, argv);

  const Scene scene = cornellBox();
  const double diagonal = sceneDiagonal(scene);
  const Mesh geometry = subdivideScene(scene, 2 * diagonal);
  ReferenceOptions first;
  first.vertexSamples = samples;
  first.seed = 1001;
  first.showProgress = false;
  ReferenceOptions second = first;
  second.seed = 2002;
  const ReferenceRenderer tracerA(scene, geometry, first), tracerB(scene, geometry, second);
  auto caster = makeEmbreeRayCaster(geometry);
  const double epsilon = rayEpsilon(geometry);

  std::unordered_map<std::string, Traced> cache;
  if (!cachePath.empty()) {
    std::ifstream in(cachePath);
    std::string key;
    int n;
    Traced t;
    while (in >> key >> n >> t.first.r >> t.first.g >> t.first.b >> t.second.r >> t.second.g >> t.second.b)
      if (n == samples) cache[key] = t;
  }

  Json out;
  out["link_error"] = linkError;
  out["reference_samples_per_seed"] = samples;
  Json perSeed = Json::array();
  std::vector<Run> runs;
  for (std::uint64_t seed : seeds) {
    RadiosityOptions options;
    options.meshing = MeshStrategy::Hierarchical;
    options.hierarchical.links.linkError = linkError;
    options.hierarchical.links.seed = seed;
    options.hierarchical.links.visibilityRays = visibilityRays;
    options.directLight.seed = seed;
    options.solver = SolverKind::GaussSeidel;
    Timer timer;
    auto created = Radiosity::create(scene, options);
    if (!created) {
      std::fprintf(stderr, "cornell_accuracy: %s\n", created.error().message.c_str());
      return 1;
    }
    std::unique_ptr<Radiosity> engine = std::move(*created);
    if (auto solved = engine->solve(); !solved) {
      std::fprintf(stderr, "cornell_accuracy: %s\n", solved.error().message.c_str());
      return 1;
    }
    Run run;
    run.value = vertexSamples(engine->solution());
    const double solveSeconds = timer.seconds();
    const Mesh& mesh = engine->solution().vertexMesh();
    const std::vector<VertexSite> sites = vertexSites(mesh, 1e-4 * diagonal);
    const std::size_t n = run.value.size();
    run.surface = mesh.vertexSurface;
    run.key.resize(n);
    run.reference.resize(n);
    std::vector<std::size_t> missing;
    for (std::size_t v = 0; v < n; ++v) {
      char buffer[160];
      const Vec3 p = run.value[v].position, s = sites[v].point;
      std::snprintf(buffer, sizeof buffer, "%u_%.4f_%.4f_%.4f_%.2f_%.2f_%.2f", mesh.vertexSurface[v], p.x, p.y, p.z, s.x, s.y, s.z);
      run.key[v] = buffer;
      if (auto it = cache.find(run.key[v]); it != cache.end()) run.reference[v] = it->second;
      else if (lengthSquared(sites[v].normal) > 0) missing.push_back(v);
    }
    Timer referenceTimer;
    parallelFor(0, missing.size(), [&](std::size_t i) {
      const std::size_t v = missing[i];
      const std::uint64_t stream = std::hash<std::string>{}(run.key[v]) & 0xffffffffffull;
      run.reference[v] = {tracerA.outgoingRadiance(sites[v].point, sites[v].normal, mesh.vertexSurface[v], stream),
                          tracerB.outgoingRadiance(sites[v].point, sites[v].normal, mesh.vertexSurface[v], stream)};
    });
    if (!cachePath.empty() && !missing.empty()) {
      std::ofstream append(cachePath, std::ios::app);
      append.precision(9);
      for (std::size_t v : missing) {
        const Traced& t = run.reference[v];
        cache[run.key[v]] = t;
        append << run.key[v] << ' ' << samples << ' ' << t.first.r << ' ' << t.first.g << ' ' << t.first.b << ' ' << t.second.r
               << ' ' << t.second.g << ' ' << t.second.b << '\n';
      }
    }
    if (leafSamples > 0 && runs.empty()) {
      // The solve's own element means against the path tracer at each open leaf's centroid: the
      // final gather reads these means, so a bias here reaches every vertex.
      ReferenceOptions leafOptions = first;
      leafOptions.vertexSamples = leafSamples;
      const ReferenceRenderer leafTracer(scene, geometry, leafOptions);
      const Mesh& elements = engine->solution().mesh();
      const std::vector<Rgb>& b = engine->solution().radiosity();
      std::vector<Rgb> traced(elements.numPatches());
      parallelFor(0, elements.numPatches(), [&](std::size_t p) {
        const Patch& patch = elements.patches[p];
        if (patch.openFraction < 1) return;
        traced[p] = leafTracer.outgoingRadiance(patch.centroid + patch.normal * (1e-4 * diagonal), patch.normal, patch.surface, p);
      });
      std::vector<double> solved(scene.surfaces.size(), 0.0), path(scene.surfaces.size(), 0.0);
      const auto luminance = [](const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
      for (std::size_t p = 0; p < elements.numPatches(); ++p) {
        const Patch& patch = elements.patches[p];
        if (patch.openFraction < 1) continue;
        solved[patch.surface] += luminance(b[p]) / kPi * patch.area;
        path[patch.surface] += luminance(traced[p]) * patch.area;
      }
      Json leaves = Json::object();
      for (std::size_t s = 0; s < solved.size(); ++s)
        if (path[s] > 0) leaves[scene.surfaces[s].name] = solved[s] / path[s] - 1;
      out["leaf_mean_bias_by_surface"] = leaves;
    }
    std::vector<VertexSample> reference = run.value, a = run.value, b = run.value;
    for (std::size_t v = 0; v < n; ++v) {
      a[v].radiance = run.reference[v].first;
      b[v].radiance = run.reference[v].second;
      reference[v].radiance = (a[v].radiance + b[v].radiance) * 0.5;
    }
    const Result<VertexComparison> error = compareVertices(scene, run.value, reference);
    const Result<VertexComparison> noise = compareVertices(scene, a, b);
    if (!error || !noise) return 1;
    std::vector<Vec3> positions;
    for (const VertexSample& s : run.value) positions.push_back(s.position);
    run.keep = awayFromEmitters(scene, positions, 0.05 * diagonal);
    for (std::size_t v = 0; v < n; ++v)
      if (run.keep[v] && isCovered(*caster, run.value[v].position, run.value[v].normal, epsilon)) run.keep[v] = 0;
    const double oneTrace = noise->error.relativeRmse / std::sqrt(2.0);
    perSeed.push_back({{"seed", seed},
                       {"vertices", n},
                       {"solve_and_gather_seconds", solveSeconds},
                       {"vertex_relative_rmse", error->error.relativeRmse},
                       {"vertex_bias", error->error.meanValue / error->error.meanReference - 1},
                       {"reference_noise_relative_rmse", oneTrace / std::sqrt(2.0)},
                       {"reference_vertices_traced", missing.size()},
                       {"reference_seconds", referenceTimer.seconds()}});
    if (!dumpPrefix.empty()) {
      std::ofstream dump(dumpPrefix + std::to_string(seed) + ".csv");
      dump.precision(8);
      dump << "x,y,z,surface,keep,value_r,value_g,value_b,ref1_r,ref1_g,ref1_b,ref2_r,ref2_g,ref2_b\n";
      for (std::size_t v = 0; v < n; ++v) {
        const VertexSample& s = run.value[v];
        const Traced& t = run.reference[v];
        dump << s.position.x << ',' << s.position.y << ',' << s.position.z << ',' << run.surface[v] << ',' << int(run.keep[v]) << ','
             << s.radiance.r << ',' << s.radiance.g << ',' << s.radiance.b << ',' << t.first.r << ',' << t.first.g << ','
             << t.first.b << ',' << t.second.r << ',' << t.second.g << ',' << t.second.b << '\n';
      }
    }
    runs.push_back(std::move(run));
  }
  out["per_seed"] = perSeed;

  // Over the vertices every seed has (the links, and so the leaves, differ between seeds): the
  // error of the seeds' mean (bias, plus the noise over √seeds) and the seeds' spread, by region.
  if (runs.size() >= 2) {
    std::map<std::string, std::size_t> index;
    for (std::size_t v = 0; v < runs[0].key.size(); ++v)
      if (runs[0].keep[v]) index[runs[0].key[v]] = v;
    struct Sums {
      double bias2 = 0, noise2 = 0, signedSum = 0, reference = 0;
      std::size_t vertices = 0;
    };
    std::map<std::string, Sums> regions;
    Sums all;
    const double k = static_cast<double>(runs.size());
    for (const auto& [key, v0] : index) {
      std::vector<Rgb> values;
      for (const Run& run : runs) {
        for (std::size_t v = 0; v < run.key.size(); ++v)  // linear search is fine for a bench
          if (run.key[v] == key) {
            values.push_back(run.value[v].radiance);
            break;
          }
      }
      if (values.size() != runs.size()) continue;
      const Rgb truth = (runs[0].reference[v0].first + runs[0].reference[v0].second) * 0.5;
      Sums& region = regions[category(scene, runs[0].surface[v0], runs[0].value[v0].position)];
      for (Sums* s : {&region, &all}) ++s->vertices;
      for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (const Rgb& value : values) mean += value[c] / k;
        double spread = 0;
        for (const Rgb& value : values) spread += (value[c] - mean) * (value[c] - mean) / (k - 1);
        for (Sums* s : {&region, &all}) {
          s->bias2 += (mean - truth[c]) * (mean - truth[c]);
          s->noise2 += spread;
          s->signedSum += mean - truth[c];
          s->reference += truth[c];
        }
      }
    }
    const double meanReference = all.reference / (3.0 * static_cast<double>(all.vertices));
    out["common_vertices"] = all.vertices;
    out["seeds_mean_relative_rmse"] = std::sqrt(all.bias2 / (3.0 * all.vertices)) / meanReference;
    out["seed_noise_relative_rmse"] = std::sqrt(all.noise2 / (3.0 * all.vertices)) / meanReference;
    Json byRegion = Json::object();
    for (const auto& [name, s] : regions)
      byRegion[name] = {{"vertices", s.vertices},
                        {"share_of_squared_bias", s.bias2 / all.bias2},
                        {"share_of_squared_noise", all.noise2 > 0 ? s.noise2 / all.noise2 : 0.0},
                        {"signed_bias", s.signedSum / s.reference}};
    out["regions"] = byRegion;
  }
  std::cout << out.dump(2) << "\n";
  return 0;
}
