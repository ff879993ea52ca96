#pragma once
// The viewer's panel (Dear ImGui): what the solve is doing, the display toggles, the baked light,
// the camera and the lights, each light's position, axis, colour and cone to drag.
#include "viewer/solve_worker.h"
#include "viewer/viewer.h"
#include "viewer/viewer_state.h"

namespace lambert::viewer {

// The panel: what the solve is doing, the display toggles, the camera and the lights.
void drawPanel(ViewerState& state, const Snapshot& snapshot, const SolveWorker& worker, const ViewerOptions& options,
               const LightmapFrame* lightmaps, const ProbeFrame* probes, bool sphereLit);

}  // namespace lambert::viewer
