// `lambert compare`: how far a radiosity solution is from the path-traced truth of the same scene:
// per-vertex and per-image RMSE and largest errors, and the solution's energy balance. Either side
// may come from a vertex file written by `solve` / `reference --export-vertices`.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "lambert/io/vertices.h"
#include "lambert/reference/compare.h"
#include "lambert/reference/reference.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct CompareCommandOptions {
  SolvingOptions solve;
  ImageCommandOptions image;
  CameraCommandOptions camera;
  ReferenceOptions reference;
  double rimDistance = -1;  // scene units; negative: 5% of the scene's diagonal
  std::string radiosityVertices, referenceVertices;
  std::string radiosityImage, referenceImage;
  bool noImage = false;
};

// A vertex file, or nothing with the reason on stderr.
std::optional<std::vector<VertexSample>> loadVertices(const std::string& path) {
  Result<std::vector<VertexSample>> loaded = readVertices(path);
  if (!loaded) {
    std::fprintf(stderr, "lambert compare: %s\n", loaded.error().message.c_str());
    return std::nullopt;
  }
  return std::move(*loaded);
}

void addError(Stats& stats, const std::string& prefix, const std::string& what, const RadianceError& e) {
  stats.add(prefix + "_compared", what + " values compared", static_cast<std::int64_t>(e.count));
  stats.add(prefix + "_mean_reference", what + " mean reference radiance", e.meanReference, "W/(m2 sr)");
  stats.add(prefix + "_bias", what + " bias (mean / reference mean - 1)", e.meanReference > 0 ? e.meanValue / e.meanReference - 1 : 0.0);
  stats.add(prefix + "_rmse", what + " RMSE", e.rmse, "W/(m2 sr)");
  stats.add(prefix + "_relative_rmse", what + " relative RMSE", e.relativeRmse);
  stats.add(prefix + "_max_abs", what + " max error", e.maxAbsolute, "W/(m2 sr)");
  stats.add(prefix + "_max_rel", what + " max relative error", e.maxRelative);
}

// Options that the chosen sources would not use are refused: a solve's options when both sides
// are files (with a radiosity file alone they choose the vertices the reference is traced at, as
// `reference --export-vertices` does), the tracer's when the reference side is a file, images
// when nothing solves.
Status checkSources(const CompareCommandOptions& o) {
  const bool radiosityFile = !o.radiosityVertices.empty(), referenceFile = !o.referenceVertices.empty();
  const std::initializer_list<const char*> imageOptions = {"--width", "--height", "--shading", "--lighting", "--supersample",
                                                           "--exposure", "--radiosity-image", "--reference-image",
                                                           "--eye", "--target", "--up", "--fov"};
  if (radiosityFile) {
    if (referenceFile)
      if (Status s = refuseGiven(o.solve, solveOnlyOptions(), "both sides come from vertex files"); !s) return s;
    const std::string why = "images are compared only when compare solves (not with --radiosity-vertices)";
    if (Status s = refuseGiven(o.image, imageOptions, why); !s) return s;
    if (Status s = refuseGiven(o.solve, {"--no-image"}, why); !s) return s;
  } else if (o.noImage) {
    if (Status s = refuseGiven(o.image, imageOptions, "--no-image compares vertices only"); !s) return s;
  }
  const bool tracesImage = !radiosityFile && !o.noImage;
  if (referenceFile) {
    if (Status s = refuseGiven(o.solve, {"--vertex-samples"}, "the reference side comes from --reference-vertices"); !s) return s;
    if (!tracesImage)
      if (Status s = refuseGiven(o.solve, {"--spp", "--max-bounces"}, "nothing is path-traced: both vertex sides are files and no image is compared"); !s)
        return s;
  }
  if (radiosityFile && referenceFile)
    if (Status s = refuseGiven(o.solve, {"--patches", "--max-edge", "--seed"}, "both sides come from vertex files"); !s) return s;
  return Ok{};
}

int runCompare(const CompareCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("compare", o.solve);
  if (!scene) return 2;
  if (Status ok = checkSources(o); !ok) return fail("compare", ok.error().message);
  if (Status ok = checkImageOptions(*scene, o.image); !ok) return fail("compare", ok.error().message);
  Stats cameraStats;
  if (o.radiosityVertices.empty() && !o.noImage)
    if (Status ok = chooseCamera(*scene, o.camera, cameraStats); !ok) return fail("compare", ok.error().message);
  for (const std::string& path : {o.radiosityImage, o.referenceImage})
    if (!path.empty())
      if (Status ok = checkImagePath(path, o.image); !ok) return fail("compare", ok.error().message);
  Stats stats;

  // The radiosity side: a vertex file, or a solve.
  std::vector<VertexSample> radiosity;
  std::unique_ptr<Radiosity> engine;
  Timer radiosityTimer;
  if (!o.radiosityVertices.empty()) {
    auto loaded = loadVertices(o.radiosityVertices);
    if (!loaded) return 2;
    radiosity = std::move(*loaded);
  } else {
    engine = makeEngine("compare", *scene, o.solve);
    if (!engine) return 2;
    if (Result<SolveReport> solved = engine->solve(); !solved) return fail("compare", solved.error().message);
    (void)engine->saveCache();
    stats = engine->stats();
    radiosity = vertexSamples(engine->solution());
  }
  stats.add("radiosity_seconds", "radiosity time", radiosityTimer.seconds(), "s");

  // The reference side: a vertex file, or the path tracer at the same vertices.
  ReferenceOptions referenceOptions = o.reference;
  referenceOptions.seed = o.solve.seed;
  referenceOptions.showProgress = !o.solve.quiet && !o.solve.json;
  std::unique_ptr<ReferenceRenderer> renderer;
  auto tracer = [&]() -> ReferenceRenderer& {
    if (!renderer)
      renderer = std::make_unique<ReferenceRenderer>(*scene, subdivideScene(*scene, 2 * sceneDiagonal(*scene)), referenceOptions);
    return *renderer;
  };
  std::vector<VertexSample> reference;
  Timer referenceTimer;
  if (!o.referenceVertices.empty()) {
    auto loaded = loadVertices(o.referenceVertices);
    if (!loaded) return 2;
    reference = std::move(*loaded);
  } else {
    // The solve's vertices, or, for a radiosity file, those `solve` with these options exports.
    Result<Mesh> exported = engine ? Result<Mesh>(engine->solution().vertexMesh()) : exportedVertexMesh(*scene, o.solve);
    if (!exported) return fail("compare", exported.error().message);
    reference = vertexSamples(*exported, tracer().vertexRadiance(*exported));
  }
  stats.add("reference_seconds", "reference time", referenceTimer.seconds(), "s");

  Result<VertexComparison> vertices = compareVertices(*scene, radiosity, reference, o.rimDistance);
  if (!vertices) return fail("compare", vertices.error().message);
  stats.add("near_emitter_vertices", "vertices near emitters (left out)", static_cast<std::int64_t>(vertices->nearEmitters));
  stats.add("covered_vertices", "vertices inside geometry (left out)", static_cast<std::int64_t>(vertices->covered));
  addError(stats, "vertex", "vertex", vertices->error);
  addError(stats, "vertex_all", "vertex (all)", vertices->everywhere);

  if (!o.noImage && engine) {
    Image mine = renderSolution(engine->solution(), o.image.image);
    Image truth = tracer().render(o.image.image.width, o.image.image.height);
    addError(stats, "image", "image", radianceError(mine.pixels, truth.pixels));
    stats.append(cameraStats);
    // Both images at the radiosity image's exposure, so that they compare by eye.
    const double exposure = imageExposureStops(o.image, o.image.exposure, *scene, mine, stats);
    for (auto [path, image] : {std::pair{o.radiosityImage, &mine}, std::pair{o.referenceImage, &truth}}) {
      if (path.empty()) continue;
      Status written = writeImageFile(path, *image, exposure);
      if (!written) {
        std::fprintf(stderr, "lambert compare: %s\n", written.error().message.c_str());
        return 1;
      }
    }
  }
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.solve.json, o.solve.quiet);
  return 0;
}

}  // namespace

std::function<int()> addCompareCommand(CLI::App& app) {
  auto options = std::make_shared<CompareCommandOptions>();
  options->reference.samplesPerPixel = 64;
  options->reference.vertexSamples = 1024;
  // The path tracer box-filters 64 samples a pixel; match it, so edge pixels compare like with like.
  options->image.image.supersample = 8;
  CLI::App* cmd = app.add_subcommand("compare", "Measure a radiosity solution against the path-traced reference");
  addSolveOptions(*cmd, options->solve);
  addImageOptions(*cmd, options->image);
  addCameraOptions(*cmd, options->camera);
  addReferenceOptions(*cmd, options->reference);
  cmd->add_option("--rim-distance", options->rimDistance,
                  "Leave out vertices this close to an emitter, scene units (default 5% of the scene's diagonal)");
  cmd->add_option("--radiosity-vertices", options->radiosityVertices,
                  "Take the radiosity side from this vertex file (from `solve`; without --reference-vertices, give the same solve "
                  "options, which choose the vertices the reference is traced at)");
  cmd->add_option("--reference-vertices", options->referenceVertices, "Take the reference side from this vertex file (from `reference`)");
  cmd->add_option("--radiosity-image", options->radiosityImage, "Also write the radiosity image compared (.png or .exr)");
  cmd->add_option("--reference-image", options->referenceImage, "Also write the reference image compared (.png or .exr)");
  cmd->add_flag("--no-image", options->noImage, "Compare vertices only");
  return [options] { return runCompare(*options); };
}

}  // namespace lambert::cli
