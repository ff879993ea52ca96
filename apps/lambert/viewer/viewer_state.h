#pragma once
// What the viewer shows and the user has changed: the camera, the display settings, the lights as
// edited (and their animation), the selected light, the probe-lit sphere.
#include "viewer/mesh_renderer.h"
#include "viewer/solve_worker.h"
#include "viewer/view_camera.h"

namespace lambert::viewer {

struct ViewerState {
  ViewCamera camera;
  DisplaySettings display;
  LightAnimation animation;  // the lights as edited, turned by their angular velocity over time
  int selectedLight = -1;
  bool screenshotRequested = false;  // F12 or the panel's button: taken in the next frame
  Vec3 sphereCentre;                 // the probe-lit sphere
  bool lightmapsAvailable = false;   // the method gathers at points (hierarchical)
};

// Play or pause: the animation's time carries on from where it is now.
void setPlaying(LightAnimation& animation, bool playing);

}  // namespace lambert::viewer
