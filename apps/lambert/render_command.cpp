// `lambert render`: solve a scene's radiosity and write an image of it from the scene camera.
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "lambert/pipeline/pipeline.h"
#include "lambert/render/rasterizer.h"
#include "lambert/render/tonemap.h"
#include "lambert/scene/builtin.h"

namespace lambert::cli {
namespace {

struct RenderCommandOptions {
  std::string scene = "cornell";
  std::size_t patches = 784;
  double maxEdge = 0;
  FormFactorMethod formFactor = FormFactorMethod::AreaMonteCarlo;
  int samples = 16;
  std::uint64_t seed = 1;
  SolverKind solver = SolverKind::GaussSeidel;
  double tolerance = 1e-7;
  int maxIterations = 1000;
  int width = 512, height = 512;
  Shading shading = Shading::Gouraud;
  int supersample = 2;
  double exposure = 0;
  std::string output = "out/cornell.png";
  bool json = false;
  bool quiet = false;
};

int runRender(const RenderCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = builtinScene(o.scene);
  if (!scene) {
    std::string names;
    for (const auto& name : builtinSceneNames()) names += (names.empty() ? "" : ", ") + name;
    std::fprintf(stderr, "lambert render: unknown scene '%s' (built-in scenes: %s)\n", o.scene.c_str(), names.c_str());
    return 2;
  }

  PipelineOptions pipeline;
  pipeline.targetPatches = o.patches;
  pipeline.maxEdgeLength = o.maxEdge;
  pipeline.formFactors.method = o.formFactor;
  pipeline.formFactors.samplePairs = o.samples;
  pipeline.formFactors.seed = o.seed;
  pipeline.formFactors.showProgress = !o.quiet && !o.json;
  pipeline.solver = o.solver;
  pipeline.solve.tolerance = o.tolerance;
  pipeline.solve.maxIterations = o.maxIterations;
  RadiositySolution solution = solveScene(*scene, pipeline);

  Timer renderTimer;
  RenderOptions renderOptions;
  renderOptions.width = o.width;
  renderOptions.height = o.height;
  renderOptions.shading = o.shading;
  renderOptions.supersample = o.supersample;
  Image image = renderRadiance(scene->camera, solution.mesh, solution.radiosity, renderOptions);
  std::vector<std::uint8_t> pixels = toSrgb8(image, o.exposure);
  double renderSeconds = renderTimer.seconds();

  Status written = writePng(o.output, image.width, image.height, pixels);
  if (!written) {
    std::fprintf(stderr, "lambert render: %s\n", written.error().message.c_str());
    return 1;
  }

  Stats& stats = solution.stats;
  stats.add("image_width", "image width", static_cast<std::int64_t>(image.width), "px");
  stats.add("image_height", "image height", static_cast<std::int64_t>(image.height), "px");
  stats.add("render_seconds", "render time", renderSeconds, "s");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  stats.add("output", "output", o.output);
  if (o.json) {
    std::printf("%s\n", stats.json().dump(2).c_str());
  } else if (!o.quiet) {
    std::printf("wrote %s\n%s", o.output.c_str(), stats.table().c_str());
  }
  return 0;
}

}  // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Solve a scene's radiosity and render it to a PNG");
  cmd->add_option("--scene", options->scene, "Built-in scene name (see `lambert scenes`)")->capture_default_str();
  auto* patches = cmd->add_option("--patches", options->patches, "Target patch count; the mesh edge length is chosen to reach it")
                      ->check(CLI::Range(std::size_t{1}, std::size_t{200000}))
                      ->capture_default_str();
  cmd->add_option("--max-edge", options->maxEdge, "Longest patch edge in scene units (instead of --patches)")
      ->check(CLI::PositiveNumber)
      ->excludes(patches);
  cmd->add_option("--formfactor", options->formFactor, "Form-factor estimator: mc (area Monte Carlo) or point (seed 000)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, FormFactorMethod>{
          {"mc", FormFactorMethod::AreaMonteCarlo}, {"point", FormFactorMethod::PointToPoint}}))
      ->default_str("mc");
  cmd->add_option("--samples", options->samples, "Sample pairs per patch pair (mc)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Random seed")->capture_default_str();
  cmd->add_option("--solver", options->solver, "Solver: direct, gs (Gauss-Seidel), jacobi or shoot (progressive)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, SolverKind>{{"direct", SolverKind::Direct},
                                                                            {"gs", SolverKind::GaussSeidel},
                                                                            {"jacobi", SolverKind::Jacobi},
                                                                            {"shoot", SolverKind::Shooting}}))
      ->default_str("gs");
  cmd->add_option("--tolerance", options->tolerance, "Relative stopping tolerance of iterative solvers")
      ->check(CLI::Range(1e-15, 1.0))
      ->capture_default_str();
  cmd->add_option("--max-iterations", options->maxIterations, "Sweep limit (shots per patch for shoot)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--width", options->width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", options->height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--shading", options->shading, "gouraud (interpolated) or flat (one value per patch)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Shading>{{"gouraud", Shading::Gouraud}, {"flat", Shading::Flat}}))
      ->default_str("gouraud");
  cmd->add_option("--supersample", options->supersample, "Samples per pixel along each axis")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  cmd->add_option("--exposure", options->exposure, "Exposure in stops (radiance × 2^stops before sRGB)")->capture_default_str();
  cmd->add_option("-o,--output", options->output, "Output PNG path")->capture_default_str();
  cmd->add_flag("--json", options->json, "Print the stats as JSON instead of a table");
  cmd->add_flag("-q,--quiet", options->quiet, "Print nothing on success");
  return [options] { return runRender(*options); };
}

}  // namespace lambert::cli
