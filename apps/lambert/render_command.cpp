// `lambert render`: solve a scene's radiosity and write an image of it from the scene camera.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "lambert/render/tonemap.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct RenderCommandOptions {
  SolveCommandOptions solve;
  ImageCommandOptions image;
  std::string output = "out/cornell.png";
};

int runRender(const RenderCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("render", o.solve.scene);
  if (!scene) return 2;
  RadiositySolution solution = solveScene(*scene, pipelineOptions(o.solve));

  Timer renderTimer;
  Image image = renderImage(*scene, scene->lights, solution.mesh, *solution.caster, solution.radiosity,
                            solution.indirectRadiosity(), solution.problem.albedo, o.image);
  std::vector<std::uint8_t> pixels = toSrgb8(image, o.image.exposure);
  double renderSeconds = renderTimer.seconds();

  Status written = writePng(o.output, image.width, image.height, pixels);
  if (!written) {
    std::fprintf(stderr, "lambert render: %s\n", written.error().message.c_str());
    return 1;
  }

  Stats& stats = solution.stats;
  stats.add("image_width", "image width", static_cast<std::int64_t>(image.width), "px");
  stats.add("image_height", "image height", static_cast<std::int64_t>(image.height), "px");
  stats.add("lighting", "lighting", std::string(o.image.lighting == Lighting::Hybrid && !scene->lights.empty() ? "hybrid" : "radiosity"));
  stats.add("render_seconds", "render time", renderSeconds, "s");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  stats.add("output", "output", o.output);
  if (o.solve.json) {
    std::printf("%s\n", stats.json().dump(2).c_str());
  } else if (!o.solve.quiet) {
    std::printf("wrote %s\n%s", o.output.c_str(), stats.table().c_str());
  }
  return 0;
}

}  // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Solve a scene's radiosity and render it to a PNG");
  addSolveOptions(*cmd, options->solve);
  addImageOptions(*cmd, options->image);
  cmd->add_option("-o,--output", options->output, "Output PNG path")->capture_default_str();
  return [options] { return runRender(*options); };
}

}  // namespace lambert::cli
