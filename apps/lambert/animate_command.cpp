// `lambert animate`: a scene's lights turning over time (seed 003), drawn frame by frame. Form
// factors are computed (or loaded) once; each frame re-injects the lights that moved and shoots
// the difference, warm from the previous frame.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/progress.h"
#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "lambert/pipeline/dynamic.h"
#include "lambert/render/tonemap.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct AnimateCommandOptions {
  SolveCommandOptions solve;
  ImageCommandOptions image;
  int frames = 120;
  double fps = 30;
  long long shotsPerFrame = 0;
  double frameTolerance = 1e-4;
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
  std::optional<Scene> scene = findScene("animate", o.solve.scene);
  if (!scene) return 2;
  if (scene->lights.empty())
    std::fprintf(stderr, "lambert animate: note: scene '%s' has no point, spot or directional lights; every frame is the same\n",
                 scene->name.c_str());

  // Uniform mesh: the static part (mesh, form factors, surface emission) once, lights per frame
  // through DynamicRadiosity. Adaptive mesh: the quad-tree follows the lights every frame.
  Stats stats;
  std::optional<RadiositySolution> base;
  std::unique_ptr<DynamicRadiosity> dynamic;
  std::unique_ptr<AdaptiveRadiosity> adaptive;
  if (o.solve.adaptive) {
    auto created = AdaptiveRadiosity::create(*scene, adaptiveOptions(*scene, o.solve));
    if (!created) {
      std::fprintf(stderr, "lambert animate: %s\n", created.error().message.c_str());
      return 2;
    }
    adaptive = std::move(*created);
    stats.add("scene", "scene", scene->name);
    stats.add("mesh", "mesh", std::string("adaptive quad-tree"));
  } else {
    Scene surfacesOnly = *scene;
    surfacesOnly.lights.clear();
    base = solveScene(surfacesOnly, pipelineOptions(o.solve));
    stats = base->stats;
    DynamicOptions dynamicOptions;
    dynamicOptions.direct.samplesPerPatch = o.solve.lightSamples;
    dynamicOptions.direct.seed = o.solve.seed;
    dynamicOptions.shotsPerFrame = o.shotsPerFrame;
    dynamicOptions.tolerance = o.frameTolerance;
    dynamic = std::make_unique<DynamicRadiosity>(base->mesh, *base->caster, base->problem, scene->metresPerUnit, dynamicOptions);
  }

  std::filesystem::path directory(o.output);
  Summary inject, solve, render, frameTime, unshot, cells;
  long long totalShots = 0;
  std::uint64_t pairsEstimated = 0;
  Progress progress("frames", static_cast<std::uint64_t>(o.frames), !o.solve.quiet && !o.solve.json);
  for (int frame = 0; frame < o.frames; ++frame) {
    Timer frameTimer;
    std::vector<Light> lights;
    for (const Light& light : scene->lights) lights.push_back(lightAtTime(light, frame / o.fps));
    Timer renderTimer;
    Image image;
    if (adaptive) {
      AdaptiveUpdate report = adaptive->update(lights);
      inject.add(report.injectSeconds, o.frames);
      solve.add(report.adaptSeconds + report.formFactorSeconds + report.solveSeconds, o.frames);
      cells.add(static_cast<double>(report.activeNodes), o.frames);
      pairsEstimated += report.pairsEstimated;
      renderTimer = Timer();
      image = renderAdaptiveImage(*scene, lights, *adaptive, o.image);
    } else {
      FrameReport report = dynamic->update(lights);
      inject.add(report.injectSeconds, o.frames);
      solve.add(report.solveSeconds, o.frames);
      unshot.add(report.unshotFraction, o.frames);
      totalShots += report.shots;
      renderTimer = Timer();
      image = renderImage(*scene, lights, base->mesh, *base->caster, dynamic->radiosity(), dynamic->indirectRadiosity(),
                          dynamic->albedo(), o.image);
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame + 1);
    Status written = writePng((directory / name).string(), image.width, image.height, toSrgb8(image, o.image.exposure));
    if (!written) {
      std::fprintf(stderr, "lambert animate: %s\n", written.error().message.c_str());
      if (adaptive) (void)adaptive->saveTable();  // the pairs computed so far are still good
      return 1;
    }
    render.add(renderTimer.seconds(), o.frames);
    frameTime.add(frameTimer.seconds(), o.frames);
    progress.advance();
  }
  progress.finish();
  std::string video = encodeVideo(directory, o.fps, o.solve.quiet);

  stats.add("frames", "frames", static_cast<std::int64_t>(o.frames));
  if (adaptive) {
    stats.add("active_cells_mean", "active cells per frame (mean)", cells.mean);
    stats.add("active_cells_max", "active cells per frame (max)", cells.max);
    stats.add("cells_created", "cells ever created", static_cast<std::int64_t>(adaptive->mesh().numNodes()));
    stats.add("pairs_estimated", "cell pairs estimated (master table)", static_cast<std::int64_t>(pairsEstimated));
    stats.add("pairs_reused", "cell pairs reused from the table", static_cast<std::int64_t>(adaptive->table().pairsReused()));
    saveAdaptiveTable(*adaptive, stats);
  } else {
    stats.add("shots", "shots (all frames)", static_cast<std::int64_t>(totalShots));
  }
  stats.add("inject_ms_mean", "light injection per frame (mean)", 1e3 * inject.mean, "ms");
  stats.add("solve_ms_mean", "radiosity update per frame (mean)", 1e3 * solve.mean, "ms");
  stats.add("solve_ms_max", "radiosity update per frame (max)", 1e3 * solve.max, "ms");
  stats.add("light_updates_per_second", "light updates per second (inject + update)",
            inject.mean + solve.mean > 0 ? 1 / (inject.mean + solve.mean) : 0.0, "/s");
  if (!adaptive) stats.add("unshot_fraction_max", "unshot power left in a frame (max)", unshot.max);
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
  options->solve.patches = 3000;
  CLI::App* cmd = app.add_subcommand("animate", "Render a PNG sequence (and an MP4 with ffmpeg) of a scene's moving lights");
  addSolveOptions(*cmd, options->solve);
  addImageOptions(*cmd, options->image);
  cmd->add_option("--frames", options->frames, "Number of frames")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--fps", options->fps, "Frames per second of scene time")->check(CLI::Range(0.001, 10000.0))->capture_default_str();
  cmd->add_option("--shots-per-frame", options->shotsPerFrame,
                  "Radiosity budget per frame in shots (0: converge every frame)")
      ->check(CLI::Range(0LL, 1000000000LL))
      ->capture_default_str();
  cmd->add_option("--frame-tolerance", options->frameTolerance, "Unshot power fraction at which a frame counts as converged")
      ->check(CLI::Range(1e-12, 1.0))
      ->capture_default_str();
  cmd->add_option("-o,--output", options->output, "Directory for frame_0001.png … (and animation.mp4)")->capture_default_str();
  return [options] { return runAnimate(*options); };
}

}  // namespace lambert::cli
