#pragma once
// `lambert view`: a window (GLFW, OpenGL 3.3 core, Dear ImGui) that shows a scene at once and its
// radiosity as it converges, with an orbit and fly camera, lights to select, move, turn and
// recolour while the indirect light follows, display toggles, screenshots and scripted runs.
// The radiosity runs on its own thread (viewer/solve_worker.h) through the library's one engine.
#include <optional>
#include <string>

#include "lambert/core/stats.h"
#include "lambert/engine/radiosity.h"
#include "viewer/mesh_renderer.h"
#include "viewer/script.h"
#include "viewer/solve_worker.h"

namespace lambert::viewer {

struct ViewerOptions {
  Scene scene;
  RadiosityOptions radiosity;
  UpdateBudget budget;
  int width = 1280, height = 720;  // window, in screen coordinates
  int msaaSamples = 0;             // multisampling of the window (0: none)
  DisplaySettings display;
  std::optional<Script> script;    // played headless, then the viewer exits
  bool vsync = true;               // off for scripts: frames as fast as they draw
  // Lightmaps and light probes baked by the radiosity thread (display.lightmaps, display.probes
  // say whether at the start); lightmaps need the hierarchical method.
  BakeSettings bake;
  Vec3 sphereCentre;               // the probe-lit sphere, scene units
  double sphereRadius = 1;
  Rgb sphereAlbedo = Rgb::gray(0.8);
};

// Runs the viewer until its window closes or its script ends. Returns 0, or an error (no display,
// no OpenGL 3.3, a script that failed) with the reason; figures for --json in `stats`.
Status runViewer(const ViewerOptions& options, Stats& stats);

}  // namespace lambert::viewer
