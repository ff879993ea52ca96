// `lambert view`: the interactive viewer (viewer/viewer.h). Options are checked, the scene read
// and the script parsed before any window opens, so bad input fails fast and without a display.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/bake/probes.h"
#include "options.h"
#include "viewer/viewer.h"

namespace lambert::cli {
namespace {

struct ViewCommandOptions : GivenOptions {
  SolvingOptions solve;
  int width = 1280, height = 720;
  int msaa = 0;  // Mesa's software OpenGL halves its frame rate at 4 samples
  CameraCommandOptions camera;
  double exposure = 0;
  Shading shading = Shading::Gouraud;
  std::string script;
  int frames = 0;
  std::string screenshot;
  double updateMilliseconds = 4;
  long long shotsPerUpdate = 0;
  int sweepsPerUpdate = 0;
  bool lightmaps = false;
  int lightmapSize = 256;
  bool probes = false;
  double probeSpacing = 0;
  std::vector<double> sphere;  // x y z
  double sphereRadius = 0;
};

int runView(const ViewCommandOptions& o) {
  std::optional<Scene> scene = findScene("view", o.solve);
  if (!scene) return 2;
  Result<RadiosityOptions> radiosity = radiosityOptions(*scene, o.solve);
  if (!radiosity) return fail("view", radiosity.error().message);
  Stats cameraStats;
  if (Status ok = chooseCamera(*scene, o.camera, cameraStats); !ok) return fail("view", ok.error().message);

  viewer::ViewerOptions v;
  v.width = o.width;
  v.height = o.height;
  v.msaaSamples = o.msaa;
  // --exposure, else the scene's, else the automatic exposure of each solution (render's policy).
  v.display.exposure = o.given("--exposure") ? o.exposure : scene->exposureStops.value_or(0);
  v.display.autoExposure = !o.given("--exposure") && !scene->exposureStops;
  v.display.flat = o.shading == Shading::Flat;
  // Each update solves within a budget so that the picture follows the solve (the direct solver
  // takes none: it is one step).
  if (radiosity->solver != SolverKind::Direct) {
    v.budget.solve = {o.shotsPerUpdate, o.sweepsPerUpdate, o.updateMilliseconds};
    if (Status ok = checkSolveBudget(radiosity->solver, v.budget.solve); !ok) return fail("view", ok.error().message);
  } else if (Status ok = refuseGiven(o, {"--update-ms", "--shots-per-update", "--sweeps-per-update"}, "the direct solver solves in one step");
             !ok) {
    return fail("view", ok.error().message);
  }
  if (!o.script.empty()) {
    if (Status ok = refuseGiven(o, {"--frames", "--screenshot"}, "--script says when to draw and what to take"); !ok)
      return fail("view", ok.error().message);
    Result<viewer::Script> script = viewer::readScript(o.script);
    if (!script) return fail("view", script.error().message);
    v.script = std::move(*script);
  } else if (o.frames > 0 || !o.screenshot.empty()) {
    // --frames N [--screenshot FILE]: draw N frames, take the screenshot, exit.
    std::string text = "frames " + std::to_string(std::max(o.frames, 1)) + "\n";
    if (!o.screenshot.empty()) text += "screenshot " + o.screenshot + "\n";
    Result<viewer::Script> script = viewer::parseScript(text, "--frames/--screenshot");
    if (!script) return fail("view", script.error().message);
    v.script = std::move(*script);
  }
  if (v.script) {
    if (Status ok = viewer::checkScriptLights(*v.script, scene->lights.size()); !ok) return fail("view", ok.error().message);
    v.vsync = false;
  }
  // Lightmaps and probes (baked by the radiosity thread from each converged solution).
  if (!o.lightmaps)
    if (Status ok = refuseGiven(o, {"--lightmap-size"}, "it sizes --lightmaps' atlases, and no --lightmaps is asked for"); !ok)
      return fail("view", ok.error().message);
  if (o.lightmaps && radiosity->meshing != MeshStrategy::Hierarchical)
    return fail("view", "--lightmaps needs the hierarchical method (the default): only it gathers at the lightmaps' texels");
  if (!o.probes)
    if (Status ok = refuseGiven(o, {"--probe-spacing"}, "it spaces --probes' grid, and no --probes is asked for"); !ok)
      return fail("view", ok.error().message);
  v.display.lightmaps = o.lightmaps;
  v.display.probes = o.probes;
  v.bake.uvs.atlasSize = o.lightmapSize;
  v.bake.uvs.fileSetsShareAtlas = !o.given("--lightmap-size");  // as `solve --lightmaps`
  v.bake.probeOptions.spacing = o.probeSpacing;
  if (Result<ProbeVolume> grid = probeGrid(*scene, v.bake.probeOptions); !grid) return fail("view", grid.error().message);
  // The sphere: where asked, else the middle of the scene's box; a 25th of its diagonal across.
  const Bounds bounds = sceneBounds(*scene);
  v.sphereCentre = o.sphere.empty() ? (bounds.lo + bounds.hi) * 0.5 : Vec3{o.sphere[0], o.sphere[1], o.sphere[2]};
  v.sphereRadius = o.sphereRadius > 0 ? o.sphereRadius : length(bounds.hi - bounds.lo) / 25;

  v.radiosity = std::move(*radiosity);
  v.radiosity.hierarchical.links.showProgress = false;  // the window shows progress
  v.radiosity.formFactors.showProgress = false;
  v.scene = std::move(*scene);

  Stats stats;
  Status ran = viewer::runViewer(v, stats);
  if (!ran) {
    std::fprintf(stderr, "lambert view: %s\n", ran.error().message.c_str());
    return 1;
  }
  stats.append(cameraStats);
  printStats(stats, o.solve.json, o.solve.quiet, "");
  return 0;
}

}  // namespace

std::function<int()> addViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewCommandOptions>();
  // As `animate`: progressive refinement keeps its unshot power between light moves,
  // so the picture follows a moved light at once; the hierarchical method gathers with gs instead.
  options->solve.solver = SolverKind::Shooting;
  options->solve.tolerance = 1e-4;
  options->solve.adaptPasses = 1;
  // The lights' direct light is drawn per pixel; what they inject only feeds the indirect light,
  // which 4 points per patch estimate well enough (a moving spot re-injects 4× faster than at 16).
  options->solve.lightSamples = 4;
  CLI::App* cmd = app.add_subcommand("view", "Open a window on a scene: the radiosity converging live, lights to move, screenshots");
  options->command = cmd;
  addSolveOptions(*cmd, options->solve);
  cmd->add_option("--width", options->width, "Window width")->check(CLI::Range(64, 16384))->capture_default_str();
  cmd->add_option("--height", options->height, "Window height")->check(CLI::Range(64, 16384))->capture_default_str();
  cmd->add_option("--msaa", options->msaa, "Multisample anti-aliasing samples per pixel (0: off)")->check(CLI::Range(0, 16))->capture_default_str();
  cmd->add_option("--exposure", options->exposure, "Exposure in stops (radiance × 2^stops before sRGB)")
      ->default_str("the scene's, else automatic (log-average luminance to middle grey)");
  addCameraOptions(*cmd, options->camera);
  cmd->add_option("--shading", options->shading, "gouraud (interpolated) or flat (one value per element)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Shading>{{"gouraud", Shading::Gouraud}, {"flat", Shading::Flat}}))
      ->default_str("gouraud");
  cmd->add_option("--script", options->script, "Play a script of camera and light moves and screenshots headless, then exit (docs/viewer.md)");
  cmd->add_option("--frames", options->frames, "Draw this many frames, then exit (with --screenshot: then take it)")->check(CLI::Range(1, 10000000));
  cmd->add_option("--screenshot", options->screenshot, "PNG of the 3-D view after --frames frames (1 by default)");
  cmd->add_option("--update-ms", options->updateMilliseconds, "Radiosity budget per update in milliseconds (gs, jacobi, shoot)")
      ->check(CLI::Range(0.1, 1e6))
      ->capture_default_str();
  cmd->add_option("--shots-per-update", options->shotsPerUpdate, "Radiosity budget per update in shots (shoot)")->check(CLI::Range(1LL, 1000000000LL));
  cmd->add_option("--sweeps-per-update", options->sweepsPerUpdate, "Radiosity budget per update in sweeps (gs, jacobi)")->check(CLI::Range(1, 1000000));
  cmd->add_flag("--lightmaps", options->lightmaps,
               "Draw the scene's own faces with lightmaps baked from each converged solution (hierarchical method; docs/viewer.md)");
  cmd->add_option("--lightmap-size", options->lightmapSize, "With --lightmaps: texels per side of each atlas")
      ->check(CLI::Range(16, 4096))
      ->capture_default_str();
  cmd->add_flag("--probes", options->probes, "Bake light probes from each converged solution and draw a sphere lit by them");
  cmd->add_option("--probe-spacing", options->probeSpacing, "Distance between --probes' probes, scene units (default: about 4096 probes over the box)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--sphere", options->sphere, "The probe sphere's centre X Y Z, scene units (default: the middle of the scene's box)")
      ->expected(3);
  cmd->add_option("--sphere-radius", options->sphereRadius, "The probe sphere's radius, scene units (default: a 25th of the box's diagonal)")
      ->check(CLI::PositiveNumber);
  return [options] { return runView(*options); };
}

}  // namespace lambert::cli
