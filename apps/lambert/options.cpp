#include "options.h"

#include <cstdio>
#include <cstdlib>
#include <map>

#include "lambert/mesh/mesh.h"
#include "lambert/render/hybrid.h"
#include "lambert/scene/builtin.h"

namespace lambert::cli {

void addMeshOptions(CLI::App& cmd, MeshCommandOptions& o) {
  cmd.add_option("--scene", o.scene, "Built-in scene name (see `lambert scenes`)")->capture_default_str();
  auto* patches = cmd.add_option("--patches", o.patches, "Target patch count; the mesh edge length is chosen to reach it")
                      ->check(CLI::Range(std::size_t{1}, std::size_t{200000}))
                      ->capture_default_str();
  cmd.add_option("--max-edge", o.maxEdge, "Longest patch edge in scene units (instead of --patches)")
      ->check(CLI::Range(1e-9, 1e12))
      ->excludes(patches);
  cmd.add_option("--seed", o.seed, "Random seed")->capture_default_str();
}

Mesh meshFor(const Scene& scene, const MeshCommandOptions& o) {
  return subdivideScene(scene, o.maxEdge > 0 ? o.maxEdge : edgeLengthForPatchCount(scene, o.patches));
}

void addSolveOptions(CLI::App& cmd, SolveCommandOptions& o) {
  addMeshOptions(cmd, o);
  cmd.add_option("--formfactor", o.formFactor,
                 "Form-factor method: mc (area Monte Carlo), point (seed 000), hemicube (seed 001) or hemisphere (ray-cast)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, FormFactorMethod>{
          {"mc", FormFactorMethod::AreaMonteCarlo},
          {"point", FormFactorMethod::PointToPoint},
          {"hemicube", FormFactorMethod::Hemicube},
          {"hemisphere", FormFactorMethod::HemisphereRays}}))
      ->default_str("mc");
  cmd.add_option("--hemicube-resolution", o.hemicubeResolution, "Hemi-cube: pixels along the top face (even)")
      ->check(CLI::Range(2, 4096) & CLI::Validator([](std::string& v) { return std::stoi(v) % 2 == 0 ? "" : "must be even"; }, "EVEN"))
      ->capture_default_str();
  cmd.add_option("--hemisphere-rays", o.hemisphereRays, "Hemisphere: rays per patch")
      ->check(CLI::Range(1, 1 << 24))
      ->capture_default_str();
  cmd.add_option("--samples", o.samples, "Sample pairs per patch pair (mc)")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd.add_option("--light-samples", o.lightSamples, "Points per patch the lights' direct light is averaged over")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd.add_option("--solver", o.solver, "Solver: direct, gs (Gauss-Seidel), jacobi or shoot (progressive)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, SolverKind>{{"direct", SolverKind::Direct},
                                                                            {"gs", SolverKind::GaussSeidel},
                                                                            {"jacobi", SolverKind::Jacobi},
                                                                            {"shoot", SolverKind::Shooting}}))
      ->default_str("gs");
  cmd.add_option("--tolerance", o.tolerance, "Relative stopping tolerance of iterative solvers")
      ->check(CLI::Range(1e-15, 1.0))
      ->capture_default_str();
  cmd.add_option("--max-iterations", o.maxIterations, "Sweep limit (shots per patch for shoot)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd.add_option("--cache-dir", o.cacheDir, "Form-factor cache directory (default $XDG_CACHE_HOME/lambert or ~/.cache/lambert)");
  cmd.add_flag("--no-cache", o.noCache, "Neither read nor write the form-factor cache");
  cmd.add_flag("--normalize-rows", o.normalizeRows,
               "Divide each row of F by its sum (seed 003): hides estimation error, adds energy where light should escape");
  cmd.add_flag("--adaptive", o.adaptive, "Adaptive quad-tree mesh refined at spot and shadow edges (seed 003)");
  cmd.add_option("--base-edge", o.baseEdge, "Adaptive: longest edge of the coarsest cells, scene units (default: diagonal / 6)")
      ->check(CLI::Range(1e-9, 1e12));
  cmd.add_option("--max-level", o.maxLevel, "Adaptive: deepest refinement level (each halves a cell)")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  cmd.add_option("--gradient-threshold", o.gradientThreshold,
                 "Adaptive: split cells whose corners' radiosity spans more than this × the mean (0: off)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd.add_option("--adapt-passes", o.adaptPasses, "Adaptive (render): refine-and-solve passes")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  cmd.add_flag("--json", o.json, "Print the stats as JSON instead of a table");
  cmd.add_flag("-q,--quiet", o.quiet, "Print nothing on success");
}

void addImageOptions(CLI::App& cmd, ImageCommandOptions& o) {
  cmd.add_option("--width", o.width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd.add_option("--height", o.height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd.add_option("--shading", o.shading, "gouraud (interpolated) or flat (one value per patch)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Shading>{{"gouraud", Shading::Gouraud}, {"flat", Shading::Flat}}))
      ->default_str("gouraud");
  cmd.add_option("--lighting", o.lighting,
                 "hybrid (lights' direct light per pixel, with shadow rays) or radiosity (all from the solution)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Lighting>{{"hybrid", Lighting::Hybrid}, {"radiosity", Lighting::Radiosity}}))
      ->default_str("hybrid");
  cmd.add_option("--supersample", o.supersample, "Samples per pixel along each axis")->check(CLI::Range(1, 8))->capture_default_str();
  cmd.add_option("--exposure", o.exposure, "Exposure in stops (radiance × 2^stops before sRGB)")->capture_default_str();
}

void printStats(const Stats& stats, bool json, bool quiet, const std::string& headline) {
  if (json)
    std::printf("%s\n", stats.json().dump(2).c_str());
  else if (!quiet)
    std::printf("%s%s", headline.empty() ? "" : (headline + "\n").c_str(), stats.table().c_str());
}

std::optional<Scene> findScene(const std::string& command, const std::string& name) {
  std::optional<Scene> scene = builtinScene(name);
  if (!scene) {
    std::string names;
    for (const auto& n : builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
    std::fprintf(stderr, "lambert %s: unknown scene '%s' (built-in scenes: %s)\n", command.c_str(), name.c_str(), names.c_str());
  }
  return scene;
}

namespace {

std::string defaultCacheDirectory() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/lambert";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/lambert";
  return ".lambert-cache";
}

}  // namespace

PipelineOptions pipelineOptions(const SolveCommandOptions& o) {
  PipelineOptions p;
  p.targetPatches = o.patches;
  p.maxEdgeLength = o.maxEdge;
  p.formFactors.method = o.formFactor;
  p.formFactors.samplePairs = o.samples;
  p.formFactors.hemicubeResolution = o.hemicubeResolution;
  p.formFactors.hemisphereRays = o.hemisphereRays;
  p.formFactors.seed = o.seed;
  p.formFactors.showProgress = !o.quiet && !o.json;
  p.directLight.samplesPerPatch = o.lightSamples;
  p.directLight.seed = o.seed;
  p.solver = o.solver;
  p.solve.tolerance = o.tolerance;
  p.solve.maxIterations = o.maxIterations;
  p.cacheDirectory = o.noCache ? "" : (o.cacheDir.empty() ? defaultCacheDirectory() : o.cacheDir);
  p.normalizeRows = o.normalizeRows;
  return p;
}

AdaptiveOptions adaptiveOptions(const Scene& scene, const SolveCommandOptions& o) {
  AdaptiveOptions a;
  a.quadtree.baseEdgeLength = o.baseEdge > 0 ? o.baseEdge : sceneDiagonal(scene) / 6;
  a.quadtree.maxLevel = o.maxLevel;
  a.formFactors = pipelineOptions(o).formFactors;
  a.formFactors.showProgress = false;
  a.direct.samplesPerPatch = o.lightSamples;
  a.direct.seed = o.seed;
  a.gradientThreshold = o.gradientThreshold;
  a.normalizeRows = o.normalizeRows;
  a.cacheDirectory = pipelineOptions(o).cacheDirectory;
  return a;
}

void saveAdaptiveTable(AdaptiveRadiosity& adaptive, Stats& stats) {
  // A failure is already reported on stderr by saveTable, and costs only the next run's time.
  (void)adaptive.saveTable();
  const AdaptiveTableFile& file = adaptive.tableFile();
  std::string cache;
  if (file.path.empty()) {
    cache = "off";
  } else {
    if (file.loaded) cache = "loaded " + file.path + " (" + std::to_string(file.pairsInFile) + " pairs)";
    if (file.saved) cache += (cache.empty() ? "" : "; ") + ("saved " + file.path + " (" + std::to_string(file.pairsSaved) + " pairs)");
    if (cache.empty()) cache = "not saved: " + file.path;
  }
  stats.add("pairs_loaded", "cell pairs loaded from the table file", static_cast<std::int64_t>(adaptive.table().pairsLoaded()));
  stats.add("formfactor_cache", "form-factor table file", cache);
  stats.add("formfactor_cache_seconds", "table file load + save time", file.loadSeconds + file.saveSeconds, "s");
}

Image renderAdaptiveImage(const Scene& scene, const std::vector<Light>& lights, const AdaptiveRadiosity& adaptive,
                          const ImageCommandOptions& options) {
  const AdaptiveMesh& mesh = adaptive.mesh();
  if (options.shading == Shading::Flat) {
    Mesh active = mesh.activeMesh();
    return renderImage(scene, lights, active, adaptive.caster(), adaptive.radiosity(), adaptive.indirectRadiosity(),
                       adaptive.problem().albedo, options);
  }
  const bool hybrid = options.lighting == Lighting::Hybrid && !lights.empty();
  std::vector<Rgb> vertices = mesh.fineVertexRadiosity(hybrid ? adaptive.indirectRadiosity() : adaptive.radiosity());
  std::vector<Rgb> albedo = adaptive.fineAlbedo();
  RenderOptions render = renderOptions(options);
  if (hybrid) render = withDirectLight(render, scene, mesh.fineMesh(), adaptive.caster(), albedo, lights);
  return renderVertexRadiosity(scene.camera, mesh.fineMesh(), vertices, render);
}

RenderOptions renderOptions(const ImageCommandOptions& o) {
  RenderOptions r;
  r.width = o.width;
  r.height = o.height;
  r.shading = o.shading;
  r.supersample = o.supersample;
  return r;
}

Image renderImage(const Scene& scene, const std::vector<Light>& lights, const Mesh& mesh, const RayCaster& caster,
                  const std::vector<Rgb>& radiosity, const std::vector<Rgb>& indirect, const std::vector<Rgb>& albedo,
                  const ImageCommandOptions& options) {
  if (options.lighting == Lighting::Hybrid && !lights.empty())
    return renderHybrid(scene, mesh, caster, indirect, albedo, lights, renderOptions(options));
  return renderRadiance(scene.camera, mesh, radiosity, renderOptions(options));
}

}  // namespace lambert::cli
