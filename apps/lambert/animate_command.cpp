// `lambert animate`: a scene's lights turning over time, drawn frame by frame. Form
// factors are computed (or loaded) once; each frame re-injects the lights that moved and solves
// the difference, warm from the previous frame, within an optional budget per frame.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/progress.h"
#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "lambert/light/lights.h"
#include "lambert/render/tonemap.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct AnimateCommandOptions {
  SolvingOptions solve;
  ImageCommandOptions image;
  CameraCommandOptions camera;
  int frames = 120;
  double fps = 30;
  long long shotsPerFrame = 0;    // shoot
  int sweepsPerFrame = 0;         // gs, jacobi
  double frameMilliseconds = 0;   // gs, jacobi, shoot
  std::string output = "frames";
  bool video = true;
};

struct Summary {
  double mean = 0, max = 0;
  void add(double v, int n) {
    mean += v / n;
    max = std::max(max, v);
  }
};

// Encodes the PNG sequence with ffmpeg when it is installed; a missing ffmpeg is not an error.
std::string encodeVideo(const std::filesystem::path& directory, double fps, bool quiet) {
  if (std::system("command -v ffmpeg > /dev/null 2>&1") != 0) return "";
  std::filesystem::path video = directory / "animation.mp4";
  std::string command = "ffmpeg -y -loglevel error -framerate " + std::to_string(fps) + " -i '" +
                        (directory / "frame_%04d.png").string() + "' -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' '" +
                        video.string() + "'";
  if (std::system(command.c_str()) != 0) {
    if (!quiet) std::fprintf(stderr, "lambert animate: warning: ffmpeg could not encode %s\n", video.string().c_str());
    return "";
  }
  return video.string();
}

int runAnimate(const AnimateCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("animate", o.solve);
  if (!scene) return 2;
  if (Status ok = checkImageOptions(*scene, o.image); !ok) return fail("animate", ok.error().message);
  Stats cameraStats;
  if (Status ok = chooseCamera(*scene, o.camera, cameraStats); !ok) return fail("animate", ok.error().message);
  // The budget suits the solver (which the scene file may choose) before anything is computed.
  Result<RadiosityOptions> chosen = radiosityOptions(*scene, o.solve);
  if (!chosen) return fail("animate", chosen.error().message);
  const SolverKind solver = chosen->solver;
  if (chosen->meshing == MeshStrategy::Hierarchical)
    if (Status ok = refuseGiven(o.solve, {"--shots-per-frame"},
                                "a shot is progressive refinement's unit, on the flat method (--method flat, whose animate solver is "
                                "shoot); the hierarchical method gathers over its links: give --sweeps-per-frame K (1: each frame "
                                "carries the moved light one bounce further, the real-time setting) or --frame-ms T");
        !ok)
      return fail("animate", ok.error().message);
  const SolveBudget budget{o.shotsPerFrame, o.sweepsPerFrame, o.frameMilliseconds};
  if (Status ok = checkSolveBudget(solver, budget); !ok) return fail("animate", ok.error().message);
  if (scene->lights.empty())
    std::fprintf(stderr, "lambert animate: note: scene '%s' has no point, spot or directional lights; every frame is the same\n",
                 scene->name.c_str());

  // The static part (mesh, form factors or links, surface emission) is made once; every frame sets
  // the lights where they are at its time and solves warm from the previous frame. The first frame
  // is solved to the tolerance: it is the warm start the others build on, and the hierarchical
  // method refines its links in it, from its solution, once for the whole animation. Later frames
  // solve within the budget, leaving the rest to the frames after.
  std::unique_ptr<Radiosity> engine = makeEngine("animate", *scene, o.solve);
  if (!engine) return 2;

  std::filesystem::path directory(o.output);
  Summary inject, solve, render, frameTime, unshot, elements;
  long long iterations = 0;
  // Every frame at the first frame's exposure, so that what changes is the light, not the camera.
  std::optional<double> exposure;
  Stats exposureStats;
  Progress progress("frames", static_cast<std::uint64_t>(o.frames), !o.solve.quiet && !o.solve.json);
  for (int frame = 0; frame < o.frames; ++frame) {
    Timer frameTimer;
    std::vector<Light> lights;
    for (const Light& light : scene->lights) lights.push_back(lightAtTime(light, frame / o.fps));
    engine->setLights(std::move(lights));
    Result<SolveReport> report = engine->solve(frame == 0 ? SolveBudget{} : budget);
    if (!report) return fail("animate", report.error().message);
    inject.add(report->injectSeconds, o.frames);
    solve.add(report->adaptSeconds + report->formFactorSeconds + report->solveSeconds, o.frames);
    unshot.add(report->unshotFraction, o.frames);
    elements.add(static_cast<double>(report->elements), o.frames);
    iterations += report->iterations;

    Timer renderTimer;
    Image image = renderSolution(engine->solution(), o.image.image);
    if (!exposure) exposure = imageExposureStops(o.image, o.image.exposure, *scene, image, exposureStats);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame + 1);
    Status written = writePng((directory / name).string(), image.width, image.height, toSrgb8(image, *exposure));
    if (!written) {
      std::fprintf(stderr, "lambert animate: %s\n", written.error().message.c_str());
      (void)engine->saveCache();  // the form factors computed so far are still good
      return 1;
    }
    render.add(renderTimer.seconds(), o.frames);
    frameTime.add(frameTimer.seconds(), o.frames);
    progress.advance();
  }
  progress.finish();
  (void)engine->saveCache();
  std::string video = encodeVideo(directory, o.fps, o.solve.quiet);

  // The engine's figures describe the last frame's solution (its lights, energy balance) and the
  // totals over all frames; the per-frame figures follow.
  Stats stats = engine->stats();
  stats.add("frames", "frames", static_cast<std::int64_t>(o.frames));
  stats.append(cameraStats);
  stats.append(exposureStats);
  stats.add("iterations_all_frames", solver == SolverKind::Shooting ? "shots (all frames)" : "iterations (all frames)",
            static_cast<std::int64_t>(iterations));
  if (o.solve.adaptive) {
    stats.add("active_cells_mean", "active cells per frame (mean)", elements.mean);
    stats.add("active_cells_max", "active cells per frame (max)", elements.max);
  }
  stats.add("inject_ms_mean", "light injection per frame (mean)", 1e3 * inject.mean, "ms");
  stats.add("solve_ms_mean", "radiosity update per frame (mean)", 1e3 * solve.mean, "ms");
  stats.add("solve_ms_max", "radiosity update per frame (max)", 1e3 * solve.max, "ms");
  stats.add("light_updates_per_second", "light updates per second (inject + update)",
            inject.mean + solve.mean > 0 ? 1 / (inject.mean + solve.mean) : 0.0, "/s");
  if (solver == SolverKind::Shooting)
    stats.add("unshot_fraction_max", "unshot power left in a frame (max)", unshot.max);
  stats.add("render_ms_mean", "render + PNG per frame (mean)", 1e3 * render.mean, "ms");
  stats.add("frame_ms_mean", "whole frame (mean)", 1e3 * frameTime.mean, "ms");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  stats.add("output", "output", directory.string());
  stats.add("video", "video", video.empty() ? std::string("none (ffmpeg not installed)") : video);
  printStats(stats, o.solve.json, o.solve.quiet, "wrote " + std::to_string(o.frames) + " frames to " + directory.string());
  return 0;
}

}  // namespace

std::function<int()> addAnimateCommand(CLI::App& app) {
  auto options = std::make_shared<AnimateCommandOptions>();
  options->solve.scene = "cornell-spots";
  options->solve.patches = 3000;  // the flat method's mesh
  // The flat method's solver: progressive refinement keeps its unshot power between frames, so a
  // moved light costs the shots its change needs (the hierarchical method, the default, gathers
  // with gs instead: radiosityOptions). 1e-4 of the power left unsolved is invisible in an 8-bit
  // frame.
  options->solve.solver = SolverKind::Shooting;
  options->solve.tolerance = 1e-4;
  options->solve.adaptPasses = 1;
  CLI::App* cmd = app.add_subcommand("animate", "Render a PNG sequence (and an MP4 with ffmpeg) of a scene's moving lights");
  addSolveOptions(*cmd, options->solve);
  addImageOptions(*cmd, options->image);
  addCameraOptions(*cmd, options->camera);
  cmd->add_option("--frames", options->frames, "Number of frames")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--fps", options->fps, "Frames per second of scene time")->check(CLI::Range(0.001, 10000.0))->capture_default_str();
  cmd->add_option("--shots-per-frame", options->shotsPerFrame,
                  "Flat method's shoot solver only: radiosity budget per frame after the first, in shots (0: to the tolerance); "
                  "the default method takes --sweeps-per-frame or --frame-ms")
      ->check(CLI::Range(0LL, 1000000000LL))
      ->capture_default_str();
  cmd->add_option("--sweeps-per-frame", options->sweepsPerFrame,
                  "Radiosity budget per frame after the first, in sweeps (gs, jacobi; 0: to the tolerance); 1 is the default "
                  "method's real-time setting")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--frame-ms", options->frameMilliseconds,
                  "Radiosity budget per frame after the first, in milliseconds (gs, jacobi, shoot; 0: none)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  cmd->add_option("-o,--output", options->output, "Directory for frame_0001.png … (and animation.mp4)")->capture_default_str();
  return [options] { return runAnimate(*options); };
}

}  // namespace lambert::cli
