// `lambert render`: solve a scene's radiosity and write an image of it from the scene camera.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct RenderCommandOptions {
  SolvingOptions solve;
  ImageCommandOptions image;
  CameraCommandOptions camera;
  ExportCommandOptions exported;
  std::string output = "out/cornell.png";
};

int runRender(const RenderCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("render", o.solve);
  if (!scene) return 2;
  if (Status ok = checkImageOptions(*scene, o.image); !ok) return fail("render", ok.error().message);
  if (Status ok = checkImagePath(o.output, o.image); !ok) return fail("render", ok.error().message);
  if (Status ok = checkExportOptions(o.exported); !ok) return fail("render", ok.error().message);
  Stats cameraStats;
  if (Status ok = chooseCamera(*scene, o.camera, cameraStats); !ok) return fail("render", ok.error().message);
  std::unique_ptr<Radiosity> engine = makeEngine("render", *scene, o.solve);
  if (!engine) return 2;
  if (Result<SolveReport> solved = engine->solve(); !solved) return fail("render", solved.error().message);
  // The solve is done, so the adaptive table is complete: save it now, whatever follows. A
  // failure is already a warning, and costs only the next run's time.
  (void)engine->saveCache();

  Timer renderTimer;
  Image image = renderSolution(engine->solution(), o.image.image);
  double renderSeconds = renderTimer.seconds();

  Stats stats = engine->stats();
  stats.append(cameraStats);
  const double exposure = imageExposureStops(o.image, o.image.exposure, *scene, image, stats);
  Status written = writeImageFile(o.output, image, exposure);
  if (!written) {
    std::fprintf(stderr, "lambert render: %s\n", written.error().message.c_str());
    return 1;
  }

  if (Status exported = exportSolution(o.exported, engine->solution(), exposure); !exported) {
    std::fprintf(stderr, "lambert render: %s\n", exported.error().message.c_str());
    return 1;
  }
  if (!o.exported.glb.empty()) stats.add("export", "glTF written to", o.exported.glb);
  stats.add("image_width", "image width", static_cast<std::int64_t>(image.width), "px");
  stats.add("image_height", "image height", static_cast<std::int64_t>(image.height), "px");
  stats.add("lighting", "lighting", std::string(drawsLightsPerPixel(engine->solution(), o.image.image) ? "hybrid" : "radiosity"));
  stats.add("render_seconds", "render time", renderSeconds, "s");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  stats.add("output", "output", o.output);
  printStats(stats, o.solve.json, o.solve.quiet, "wrote " + o.output);
  return 0;
}

}  // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Solve a scene's radiosity and render it to a PNG");
  addSolveOptions(*cmd, options->solve);
  addImageOptions(*cmd, options->image);
  addCameraOptions(*cmd, options->camera);
  addExportOptions(*cmd, options->exported);
  cmd->add_option("-o,--output", options->output, "Output image: .png (tone mapped) or .exr (linear float radiance)")->capture_default_str();
  return [options] { return runRender(*options); };
}

}  // namespace lambert::cli
