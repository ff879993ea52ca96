#pragma once
// `lambert view --script FILE`: a sequence of camera, light and display changes, waits and
// screenshots that the viewer plays without a user, then exits (for tests and for making videos).
// One command per line; `#` starts a comment. docs/viewer.md lists the commands.
#include <string>
#include <variant>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/vec3.h"
#include "lambert/core/rgb.h"

namespace lambert::viewer {

// Draw this many frames.
struct DrawFrames { int frames = 1; };
// Draw until the first radiosity solution is on screen.
struct WaitForSolution { double timeoutSeconds = 300; };
// Draw until the solution for the current lights has converged and is on screen.
struct WaitForConvergence { double timeoutSeconds = 300; };
// Draw until the lightmaps (or the probes) baked for the current lights are on screen; the
// display must show them (`lightmaps on`, `probes on`).
struct WaitForLightmaps { double timeoutSeconds = 300; };
struct WaitForProbes { double timeoutSeconds = 300; };
// Move the probe-lit sphere's centre to a point (scene units).
struct SetSphere { Vec3 centre; };
// The 3-D view (without the panels) of the frame just drawn, as a PNG.
struct Screenshot {
  std::string path;
  bool withPanels = false;  // screenshot-window: the whole window, panels and light markers too
};
struct SetCamera { Vec3 eye, target; };
// Turn the camera about its target: yaw about the up axis, pitch about the right axis (degrees).
struct OrbitCamera { double yawDegrees = 0, pitchDegrees = 0; };
struct SetLightPosition { int light = 0; Vec3 position; };
struct SetLightDirection { int light = 0; Vec3 direction; };
// Point a spot or directional light's axis at a point.
struct AimLight { int light = 0; Vec3 target; };
struct SetLightIntensity { int light = 0; Rgb intensity; };  // W/sr (point, spot) or W/m² (directional)
struct SetLightCone { int light = 0; double coneDegrees = 0, falloffDegrees = 0; };
// A display setting by name and value (`lighting both`, `shading flat`, `exposure -1`, …).
struct SetDisplay { std::string setting, value; };
// Select a light in the panel, as a click on it does.
struct SelectLight { int light = 0; };
// Play or pause the scene's light animation.
struct SetPlaying { bool playing = false; };

using ScriptStep = std::variant<DrawFrames, WaitForSolution, WaitForConvergence, WaitForLightmaps, WaitForProbes, SetSphere, Screenshot, SetCamera, OrbitCamera,
                                SetLightPosition, SetLightDirection, AimLight, SetLightIntensity, SetLightCone, SetDisplay,
                                SetPlaying, SelectLight>;

struct ScriptLine {
  int line = 0;  // 1-based, for messages
  ScriptStep step;
};

struct Script {
  std::string path;
  std::vector<ScriptLine> lines;
};

// Reads and checks the whole script before anything runs: an error names the file and line and
// says what is wrong. Light indices are checked against the scene later (checkScriptLights).
Result<Script> parseScript(const std::string& text, const std::string& path);
Result<Script> readScript(const std::string& path);

// A light index out of range for a scene with `lightCount` lights, named by file and line.
Status checkScriptLights(const Script& script, std::size_t lightCount);

// Whether `setting value` is a display setting the viewer knows (also used by parseScript).
Status checkDisplaySetting(const std::string& setting, const std::string& value);

}  // namespace lambert::viewer
