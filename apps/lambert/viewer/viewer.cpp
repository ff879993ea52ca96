#include "viewer/viewer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <Eigen/Geometry>

#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/mesh.h"
#include "viewer/baked_renderer.h"

namespace lambert::viewer {
namespace {

constexpr double kDegrees = kPi / 180;

Eigen::Vector3f toFloat(const Vec3& v) { return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; }

// The camera the user moves, kept as lambert's own Camera (eye, target, up, vertical field of
// view) so that screenshots from it and lambert's software images of it agree.
struct ViewCamera {
  Camera camera;
  bool fly = false;  // fly: dragging turns the view about the eye; orbit: about the target

  Vec3 forward() const { return normalize(camera.target - camera.eye); }
  Vec3 right() const {
    Vec3 side = cross(forward(), camera.up);
    return lengthSquared(side) > 0 ? normalize(side) : Vec3{1, 0, 0};
  }
  // Yaw about the up axis, pitch about the right axis, keeping clear of the poles.
  void turn(double yaw, double pitch) {
    const Vec3 up = normalize(camera.up);
    const Vec3 pivot = fly ? camera.eye : camera.target;
    Vec3 offset = (fly ? camera.target : camera.eye) - pivot;
    offset = rotate(offset, up, yaw);
    const double elevation = std::asin(std::clamp(dot(normalize(offset), up), -1.0, 1.0));
    const double limit = 89 * kDegrees;
    pitch = std::clamp(elevation + pitch, -limit, limit) - elevation;
    Vec3 side = cross(offset, up);
    if (lengthSquared(side) > 0) offset = rotate(offset, normalize(side), pitch);
    (fly ? camera.target : camera.eye) = pivot + offset;
  }
  void orbit(double yaw, double pitch) {
    const bool wasFly = fly;
    fly = false;
    turn(yaw, pitch);
    fly = wasFly;
  }
  void pan(double dx, double dy) {
    const double distance = length(camera.target - camera.eye);
    const Vec3 upOnScreen = cross(right(), forward());
    const Vec3 shift = (right() * -dx + upOnScreen * dy) * distance;
    camera.eye += shift;
    camera.target += shift;
  }
  void dolly(double factor) { camera.eye = camera.target + (camera.eye - camera.target) * factor; }
  void move(const Vec3& step) {
    camera.eye += step;
    camera.target += step;
  }

  Eigen::Matrix4f view() const {
    const Vec3 f = forward(), s = right(), u = cross(s, f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<1, 3>(0, 0) = toFloat(s).transpose();
    m.block<1, 3>(1, 0) = toFloat(u).transpose();
    m.block<1, 3>(2, 0) = -toFloat(f).transpose();
    m(0, 3) = static_cast<float>(-dot(s, camera.eye));
    m(1, 3) = static_cast<float>(-dot(u, camera.eye));
    m(2, 3) = static_cast<float>(dot(f, camera.eye));
    return m;
  }
  // Near and far planes from the scene's bounds, so the depth buffer spans what can be seen.
  Eigen::Matrix4f projection(double aspect, const Vec3& lo, const Vec3& hi) const {
    double far = 0;
    for (int corner = 0; corner < 8; ++corner) {
      Vec3 p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
      far = std::max(far, dot(p - camera.eye, forward()));
    }
    far = std::max(far * 1.01, 1e-6);
    const double near = std::max(1e-3 * length(camera.target - camera.eye), far * 1e-5);
    far = std::max(far, near * 2);
    const double f = 1 / std::tan(camera.verticalFovDegrees * kDegrees / 2);
    Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
    m(0, 0) = static_cast<float>(f / aspect);
    m(1, 1) = static_cast<float>(f);
    m(2, 2) = static_cast<float>((far + near) / (near - far));
    m(2, 3) = static_cast<float>(2 * far * near / (near - far));
    m(3, 2) = -1;
    return m;
  }
};

// The framebuffer's pixels, top row first, as the PNG writer wants them.
Status saveScreenshot(const std::string& path, int width, int height) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  std::vector<std::uint8_t> flipped(pixels.size());
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height - 1 - y) * row), row,
                flipped.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row));
  return writePng(path, width, height, flipped);
}

std::string glfwMessage;
void onGlfwError(int, const char* description) { glfwMessage = description; }

// Figures over a span of frames.
struct FrameFigures {
  long long frames = 0;
  double seconds = 0, cpuSeconds = 0, uploadSeconds = 0;
};

// Plays a Script: commands run at the start of a frame until one has to wait (frames to draw, a
// solution to arrive, a screenshot of this frame).
struct ScriptPlayer {
  enum class Waiting { None, Frames, Solution, Converged, Lightmaps, Probes };

  const Script* script = nullptr;  // null: no script, a user drives
  std::size_t next = 0, current = 0;
  Waiting waiting = Waiting::None;
  int framesLeft = 0;
  double timeout = 0;
  Timer waitTimer;

  bool active() const { return script != nullptr; }
  bool finished() const { return script && next >= script->lines.size() && waiting == Waiting::None; }
  // "file:line" of the command run last, for messages.
  std::string where() const { return script->path + ":" + std::to_string(script->lines.at(current).line); }
};

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
void setPlaying(LightAnimation& animation, bool playing) {
  const double now = steadyClockSeconds();
  animation.seconds = animation.secondsAt(now);
  animation.setAt = now;
  animation.playing = playing;
}

// Applies one script command; one that waits (frames, a solution) sets the player waiting, and a
// screenshot is taken when this frame is drawn.
Status applyCommand(const ScriptStep& step, ViewerState& state, ScriptPlayer& player, Screenshot& screenshot) {
  return std::visit(
      [&](const auto& s) -> Status {
        using T = std::decay_t<decltype(s)>;
        auto light = [&](int index) -> Light& { return state.animation.base.at(static_cast<std::size_t>(index)); };
        if constexpr (std::is_same_v<T, DrawFrames>) {
          player.waiting = ScriptPlayer::Waiting::Frames;
          player.framesLeft = s.frames;
        } else if constexpr (std::is_same_v<T, WaitForSolution>) {
          player.waiting = ScriptPlayer::Waiting::Solution;
          player.timeout = s.timeoutSeconds;
          player.waitTimer = Timer();
        } else if constexpr (std::is_same_v<T, WaitForConvergence>) {
          player.waiting = ScriptPlayer::Waiting::Converged;
          player.timeout = s.timeoutSeconds;
          player.waitTimer = Timer();
        } else if constexpr (std::is_same_v<T, WaitForLightmaps>) {
          if (!state.display.lightmaps) return Error{"the lightmaps are off: 'lightmaps on' first"};
          player.waiting = ScriptPlayer::Waiting::Lightmaps;
          player.timeout = s.timeoutSeconds;
          player.waitTimer = Timer();
        } else if constexpr (std::is_same_v<T, WaitForProbes>) {
          if (!state.display.probes) return Error{"the probes are off: 'probes on' first"};
          player.waiting = ScriptPlayer::Waiting::Probes;
          player.timeout = s.timeoutSeconds;
          player.waitTimer = Timer();
        } else if constexpr (std::is_same_v<T, SetSphere>) {
          state.sphereCentre = s.centre;
        } else if constexpr (std::is_same_v<T, Screenshot>) {
          screenshot = s;
        } else if constexpr (std::is_same_v<T, SetCamera>) {
          state.camera.camera.eye = s.eye;
          state.camera.camera.target = s.target;
        } else if constexpr (std::is_same_v<T, OrbitCamera>) {
          state.camera.orbit(s.yawDegrees * kDegrees, s.pitchDegrees * kDegrees);
        } else if constexpr (std::is_same_v<T, SetLightPosition>) {
          light(s.light).position = s.position;
        } else if constexpr (std::is_same_v<T, SetLightDirection>) {
          light(s.light).direction = s.direction;
        } else if constexpr (std::is_same_v<T, AimLight>) {
          Light& l = light(s.light);
          if (l.kind == LightKind::Point) return Error{"light " + std::to_string(s.light) + " is a point light: it has no axis to aim"};
          if (length(s.target - l.position) <= 0) return Error{"the aim point is the light's own position"};
          l.direction = normalize(s.target - l.position);
        } else if constexpr (std::is_same_v<T, SetLightIntensity>) {
          Light& l = light(s.light);
          (l.kind == LightKind::Directional ? l.irradiance : l.intensity) = s.intensity;
        } else if constexpr (std::is_same_v<T, SetLightCone>) {
          Light& l = light(s.light);
          if (l.kind != LightKind::Spot) return Error{"light " + std::to_string(s.light) + " is not a spot: it has no cone"};
          l.coneAngleDegrees = s.coneDegrees;
          l.falloffDegrees = s.falloffDegrees;
        } else if constexpr (std::is_same_v<T, SetDisplay>) {
          DisplaySettings& d = state.display;
          const bool on = s.value == "on";
          if (s.setting == "lighting")
            d.lighting = s.value == "both" ? LightingMode::Both : s.value == "direct" ? LightingMode::Direct : LightingMode::Indirect;
          else if (s.setting == "shading") d.flat = s.value == "flat";
          else if (s.setting == "wireframe") d.wireframe = on;
          else if (s.setting == "false-colour") d.falseColour = on;
          else if (s.setting == "srgb") d.srgb = on;
          else if (s.setting == "ambient") d.ambient = on;
          else if (s.setting == "exposure") d.exposure = std::strtod(s.value.c_str(), nullptr), d.autoExposure = false;
          else if (s.setting == "lightmaps") {
            if (on && !state.lightmapsAvailable) return Error{"lightmaps need the hierarchical method (--method hierarchical)"};
            d.lightmaps = on;
          } else if (s.setting == "probes") d.probes = on;
        } else if constexpr (std::is_same_v<T, SelectLight>) {
          state.selectedLight = s.light;
        } else if constexpr (std::is_same_v<T, SetPlaying>) {
          setPlaying(state.animation, s.playing);
        }
        return Ok{};
      },
      step);
}

// The panel: what the solve is doing, the display toggles, the camera and the lights.
void drawPanel(ViewerState& state, const Snapshot& snapshot, const SolveWorker& worker, const ViewerOptions& options,
               const LightmapFrame* lightmaps, const ProbeFrame* probes, bool sphereLit) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::Begin("lambert", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%s", options.scene.name.c_str());
  ImGui::Text("%.0f frames/s (%.2f ms)", ImGui::GetIO().Framerate, 1000.0 / std::max(ImGui::GetIO().Framerate, 1e-3f));
  if (!worker.ready())
    ImGui::Text("meshing and form factors… %.1f s", worker.secondsSinceStart());
  else if (snapshot.preview)
    ImGui::Text("first solve…");
  else {
    ImGui::Text("%zu elements, %s", snapshot.elements,
                snapshot.settled ? "converged" : snapshot.converged ? "converged, gathering at the vertices…" : "solving…");
    if (options.radiosity.solver == SolverKind::Shooting)
      ImGui::Text("unshot power %.2e, %lld shots", snapshot.unshotFraction, snapshot.iterations);
    else
      ImGui::Text("%lld sweeps", snapshot.iterations);
  }

  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    DisplaySettings& d = state.display;
    int lighting = static_cast<int>(d.lighting);
    ImGui::RadioButton("both", &lighting, 0);
    ImGui::SameLine();
    ImGui::RadioButton("direct", &lighting, 1);
    ImGui::SameLine();
    ImGui::RadioButton("indirect", &lighting, 2);
    d.lighting = static_cast<LightingMode>(lighting);
    int shading = d.flat ? 1 : 0;
    ImGui::RadioButton("Gouraud", &shading, 0);
    ImGui::SameLine();
    ImGui::RadioButton("flat", &shading, 1);
    d.flat = shading == 1;
    ImGui::Checkbox("patch wireframe", &d.wireframe);
    ImGui::Checkbox("false colour of B", &d.falseColour);
    if (d.falseColour) ImGui::Text("blue %.3g … red %.3g W/m² (log)", snapshot.maxRadiosity / 1000, snapshot.maxRadiosity);
    ImGui::Checkbox("sRGB", &d.srgb);
    if (options.radiosity.solver == SolverKind::Shooting) ImGui::Checkbox("ambient term (Cohen et al. 1988)", &d.ambient);
    float exposure = static_cast<float>(d.exposure);
    if (ImGui::SliderFloat(d.autoExposure ? "exposure (stops, auto)" : "exposure (stops)", &exposure, -20, 20, "%.1f"))
      d.exposure = exposure, d.autoExposure = false;
    if (ImGui::Button("screenshot (F12)")) state.screenshotRequested = true;
  }
  if (ImGui::CollapsingHeader("Baked light", ImGuiTreeNodeFlags_DefaultOpen)) {
    DisplaySettings& d = state.display;
    const std::vector<Light> current = state.animation.lightsAt(steadyClockSeconds());
    if (state.lightmapsAvailable) {
      ImGui::Checkbox("lightmaps", &d.lightmaps);
      if (d.lightmaps && lightmaps)
        ImGui::Text("  %d atlas(es) of %d², baked in %.2f s%s", lightmaps->uvs->numAtlases, lightmaps->uvs->size, lightmaps->seconds,
                    lightmaps->lights == current ? "" : " (older lights)");
    } else {
      ImGui::TextDisabled("lightmaps: --method hierarchical only");
    }
    ImGui::Checkbox("probe sphere (arrows, PgUp/PgDn)", &d.probes);
    if (d.probes) {
      float c[3] = {static_cast<float>(state.sphereCentre.x), static_cast<float>(state.sphereCentre.y), static_cast<float>(state.sphereCentre.z)};
      const Bounds b = sceneBounds(options.scene);
      if (ImGui::DragFloat3("sphere", c, static_cast<float>(length(b.hi - b.lo) * 0.002))) state.sphereCentre = {c[0], c[1], c[2]};
      if (probes)
        ImGui::Text("  %zu probes (%zu valid), spacing %.3g%s", probes->volume.numProbes(), probes->volume.numValid, probes->volume.spacing,
                    probes->lights == current ? "" : " (older lights)");
      if (probes && !sphereLit) ImGui::Text("  no valid probe around the sphere: inside geometry");
    }
    if (std::string baking = worker.baking(); !baking.empty()) ImGui::Text("%s", baking.c_str());
    else if ((d.lightmaps && !lightmaps) || (d.probes && !probes)) ImGui::Text("waiting for a converged solution to bake...");
  }
  if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
    int mode = state.camera.fly ? 1 : 0;
    ImGui::RadioButton("orbit", &mode, 0);
    ImGui::SameLine();
    ImGui::RadioButton("fly (WASD, Q/E)", &mode, 1);
    state.camera.fly = mode == 1;
    float fov = static_cast<float>(state.camera.camera.verticalFovDegrees);
    ImGui::SliderFloat("field of view", &fov, 10, 120, "%.0f°");
    state.camera.camera.verticalFovDegrees = fov;
    if (ImGui::Button("scene camera")) state.camera.camera = options.scene.camera;
  }
  if (!state.animation.base.empty() && ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (ImGui::Button(state.animation.playing ? "pause (space)" : "play (space)")) setPlaying(state.animation, !state.animation.playing);
    ImGui::SameLine();
    ImGui::Text("t = %.2f s", state.animation.secondsAt(steadyClockSeconds()));
    for (std::size_t i = 0; i < state.animation.base.size(); ++i) {
      const Light& l = state.animation.base[i];
      const char* kind = l.kind == LightKind::Point ? "point" : l.kind == LightKind::Spot ? "spot" : l.kind == LightKind::Sky ? "sky"
                         : l.kind == LightKind::Directional ? "directional" : "luminaire";
      std::string label = std::to_string(i) + ": " + (l.name.empty() ? std::string(kind) : l.name + " (" + kind + ")");
      if (ImGui::Selectable(label.c_str(), state.selectedLight == static_cast<int>(i))) state.selectedLight = static_cast<int>(i);
    }
    if (state.selectedLight >= 0 && state.selectedLight < static_cast<int>(state.animation.base.size())) {
      Light& l = state.animation.base[static_cast<std::size_t>(state.selectedLight)];
      if (l.kind == LightKind::Sky) {  // a sky has no position, axis or colour to drag: its file sets it
        ImGui::Text("sky: edit it in the scene file");
        ImGui::End();
        return;
      }
      if (l.kind != LightKind::Directional) {
        float p[3] = {static_cast<float>(l.position.x), static_cast<float>(l.position.y), static_cast<float>(l.position.z)};
        const Bounds b = sceneBounds(options.scene);
        if (ImGui::DragFloat3("position", p, static_cast<float>(length(b.hi - b.lo) * 0.002))) {
          l.position = {p[0], p[1], p[2]};
        }
      }
      if (l.kind != LightKind::Point) {
        // The axis as azimuth about y and elevation from the horizontal plane, in degrees.
        const Vec3 d = normalize(l.direction);
        float azimuth = static_cast<float>(std::atan2(d.x, d.z) / kDegrees);
        float elevation = static_cast<float>(std::asin(std::clamp(d.y, -1.0, 1.0)) / kDegrees);
        bool turned = ImGui::SliderFloat("azimuth", &azimuth, -180, 180, "%.1f°");
        turned |= ImGui::SliderFloat("elevation", &elevation, -90, 90, "%.1f°");
        if (turned) {
          const double a = azimuth * kDegrees, e = elevation * kDegrees;
          l.direction = {std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a)};
        }
      }
      Rgb& power = l.kind == LightKind::Directional ? l.irradiance : l.intensity;
      const double strength = power.maxComponent();
      float colour[3] = {1, 1, 1};
      if (strength > 0) colour[0] = static_cast<float>(power.r / strength), colour[1] = static_cast<float>(power.g / strength), colour[2] = static_cast<float>(power.b / strength);
      float value = static_cast<float>(strength);
      bool recoloured = ImGui::ColorEdit3("colour", colour);
      recoloured |= ImGui::DragFloat(l.kind == LightKind::Directional ? "E (W/m²)" : l.kind == LightKind::Luminaire ? "colour × multiplier" : "I (W/sr)", &value, std::max(0.01f, value * 0.01f), 0,
                                     1e9f, "%.3g");
      if (recoloured) power = Rgb{colour[0], colour[1], colour[2]} * std::max(0.0f, value);
      if (l.kind == LightKind::Spot) {
        float cone = static_cast<float>(l.coneAngleDegrees), falloff = static_cast<float>(l.falloffDegrees);
        bool reshaped = ImGui::SliderFloat("cone half-angle", &cone, 1, 90, "%.1f°");
        reshaped |= ImGui::SliderFloat("soft edge", &falloff, 0, cone, "%.1f°");
        if (reshaped) {
          l.coneAngleDegrees = cone;
          l.falloffDegrees = std::min(falloff, cone);
        }
      }
    }
  }
  ImGui::End();
}

// The light whose marker is nearest the cursor, within 12 pixels; -1 for none.
int pickLight(const std::vector<Light>& lights, const Eigen::Matrix4f& viewProjection, double x, double y, int width, int height) {
  int best = -1;
  double bestDistance = 12;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    if (lights[i].kind == LightKind::Directional || lights[i].kind == LightKind::Sky) continue;
    Eigen::Vector4f clip = viewProjection * Eigen::Vector4f(toFloat(lights[i].position).homogeneous());
    if (clip.w() <= 0) continue;
    const double sx = (clip.x() / clip.w() * 0.5 + 0.5) * width, sy = (0.5 - clip.y() / clip.w() * 0.5) * height;
    const double d = std::hypot(sx - x, sy - y);
    if (d < bestDistance) bestDistance = d, best = static_cast<int>(i);
  }
  return best;
}

}  // namespace

Status runViewer(const ViewerOptions& options, Stats& stats) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    return Error{"no display: GLFW could not start (" + glfwMessage + "); run it in a desktop session, or headless under xvfb-run"};
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, options.msaaSamples);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, ("lambert — " + options.scene.name).c_str(), nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    return Error{"cannot open an OpenGL 3.3 core window (" + glfwMessage + ")"};
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.vsync ? 1 : 0);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  Status result = Ok{};
  {
    Result<std::unique_ptr<MeshRenderer>> renderer = MeshRenderer::create();
    Result<std::unique_ptr<BakedRenderer>> bakedRenderer = Error{"no OpenGL programs"};
    if (renderer) bakedRenderer = BakedRenderer::create(options.scene);
    if (!renderer) {
      result = renderer.error();
    } else if (!bakedRenderer) {
      result = bakedRenderer.error();
    } else {
      ViewerState state;
      state.camera.camera = options.scene.camera;
      state.display = options.display;
      state.animation.base = options.scene.lights;
      state.animation.setAt = steadyClockSeconds();
      state.sphereCentre = options.sphereCentre;
      state.lightmapsAvailable = options.radiosity.meshing == MeshStrategy::Hierarchical;
      if (!state.lightmapsAvailable) state.display.lightmaps = false;
      const Bounds bounds = sceneBounds(options.scene);
      const double diagonal = length(bounds.hi - bounds.lo);

      BakeSettings bake = options.bake;
      bake.lightmaps = state.display.lightmaps;
      bake.probes = state.display.probes;
      SolveWorker worker(options.scene, options.radiosity, options.budget, state.display.flat, bake);
      std::shared_ptr<const LightmapFrame> lightmaps;
      std::shared_ptr<const ProbeFrame> probes;
      // What the last frame showed (swapped): script waits end on what is on screen.
      std::shared_ptr<const LightmapFrame> lightmapsOnScreen;
      std::shared_ptr<const ProbeFrame> probesOnScreen;
      // From a change of the lights to the lightmaps (probes) baked for them on screen.
      double lightsChangedAt = -1;
      bool lightmapsAwaited = false, probesAwaited = false;
      struct Latency {
        long long count = 0;
        double sum = 0, max = 0;
        void add(double seconds) { count += 1, sum += seconds, max = std::max(max, seconds); }
      } lightmapLatency, probeLatency;
      double lightmapUploadSeconds = 0;
      std::shared_ptr<const Snapshot> shown = previewSnapshot(options.scene);
      ScriptPlayer player;
      player.script = options.script ? &*options.script : nullptr;
      LightAnimation sentAnimation = state.animation;

      FrameFigures all, playing, lightmapped;
      Timer clock;
      double lastTime = clock.seconds();
      bool firstSolutionShown = false;
      double firstSolutionSeconds = 0, convergedSeconds = 0;
      while (!glfwWindowShouldClose(window)) {
        const double frameStart = clock.seconds();
        const double dt = frameStart - lastTime;
        lastTime = frameStart;
        glfwPollEvents();
        Timer cpu;

        if (std::string error = worker.error(); !error.empty()) {
          result = Error{error};
          break;
        }
        if (std::shared_ptr<const Snapshot> latest = worker.latest(); latest && latest != shown) {
          shown = latest;
          if (!firstSolutionShown) firstSolutionShown = true, firstSolutionSeconds = clock.seconds();
        }
        if (state.display.autoExposure && !shown->preview) state.display.exposure = shown->autoExposureStops;
        const std::vector<Light> currentLights = state.animation.lightsAt(steadyClockSeconds());
        const bool upToDate = !shown->preview && shown->lights == currentLights;
        lightmaps = worker.latestLightmaps();
        probes = worker.latestProbes();
        const bool lightmapsUpToDate = lightmapsOnScreen && lightmapsOnScreen->lights == currentLights;
        const bool probesUpToDate = probesOnScreen && probesOnScreen->lights == currentLights;
        if (upToDate && shown->settled && convergedSeconds == 0) convergedSeconds = clock.seconds();

        // The script: run commands until one waits.
        Screenshot screenshot;  // asked for by the script in this frame
        if (player.active()) {
          using W = ScriptPlayer::Waiting;
          if (player.waiting == W::Frames && player.framesLeft <= 0) player.waiting = W::None;
          if (player.waiting == W::Solution && !shown->preview) player.waiting = W::None;
          if (player.waiting == W::Converged && upToDate && shown->settled) player.waiting = W::None;
          if (player.waiting == W::Lightmaps && lightmapsUpToDate) player.waiting = W::None;
          if (player.waiting == W::Probes && probesUpToDate) player.waiting = W::None;
          if (player.waiting != W::None && player.waiting != W::Frames && player.waitTimer.seconds() > player.timeout) {
            const char* what = player.waiting == W::Solution    ? "no solution"
                               : player.waiting == W::Converged ? "not converged"
                               : player.waiting == W::Lightmaps ? "no lightmaps for these lights"
                                                                : "no probes for these lights";
            result = Error{player.where() + ": " + what + " within " + std::to_string(player.timeout) + " s"};
            break;
          }
          while (player.waiting == W::None && screenshot.path.empty() && player.next < player.script->lines.size()) {
            player.current = player.next++;
            if (Status ok = applyCommand(player.script->lines[player.current].step, state, player, screenshot); !ok) {
              result = Error{player.where() + ": " + ok.error().message};
              break;
            }
          }
          if (!result) break;
          if (player.finished() && screenshot.path.empty()) break;
        }

        // Input the panel does not take: orbit/turn, pan, dolly, fly, pick a light.
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGuiIO& io = ImGui::GetIO();
        int fbWidth = 0, fbHeight = 0;
        glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
        fbWidth = std::max(fbWidth, 1), fbHeight = std::max(fbHeight, 1);
        const double aspect = static_cast<double>(fbWidth) / fbHeight;
        const Eigen::Matrix4f viewProjection = state.camera.projection(aspect, bounds.lo, bounds.hi) * state.camera.view();
        int winWidth = 0, winHeight = 0;
        glfwGetWindowSize(window, &winWidth, &winHeight);
        if (!io.WantCaptureMouse) {
          // ImGui's mouse state, which keeps a click shorter than a frame.
          const double scale = kPi / std::max(winHeight, 1);
          const bool moved = io.MouseDragMaxDistanceSqr[0] > 9 || io.MouseDragMaxDistanceSqr[1] > 9 || io.MouseDragMaxDistanceSqr[2] > 9;
          if (io.MouseDown[0] && moved) state.camera.turn(-io.MouseDelta.x * scale, -io.MouseDelta.y * scale);
          if ((io.MouseDown[1] || io.MouseDown[2]) && moved) state.camera.pan(io.MouseDelta.x / std::max(winHeight, 1), io.MouseDelta.y / std::max(winHeight, 1));
          if (ImGui::IsMouseReleased(0) && io.MouseDragMaxDistanceSqr[0] <= 9)
            state.selectedLight = pickLight(state.animation.base, viewProjection, io.MousePos.x, io.MousePos.y, winWidth, winHeight);
          if (io.MouseWheel != 0) state.camera.dolly(std::pow(0.9, io.MouseWheel));
        }
        const bool screenshotKey = std::exchange(state.screenshotRequested, false);
        if (!io.WantCaptureKeyboard) {
          const double speed = diagonal * 0.4 * dt * (glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4 : 1);
          const Vec3 f = state.camera.forward(), r = state.camera.right(), u = normalize(state.camera.camera.up);
          const std::pair<int, Vec3> keys[] = {{GLFW_KEY_W, f}, {GLFW_KEY_S, -f}, {GLFW_KEY_D, r}, {GLFW_KEY_A, -r}, {GLFW_KEY_E, u}, {GLFW_KEY_Q, -u}};
          for (const auto& [key, direction] : keys)
            if (glfwGetKey(window, key) == GLFW_PRESS) state.camera.move(direction * speed);
          if (state.display.probes) {
            // The probe sphere: arrows move it over the ground (right and forward as the camera
            // looks), Page Up and Page Down along the up axis.
            const Vec3 ahead = normalize(f - u * dot(f, u));
            const std::pair<int, Vec3> sphereKeys[] = {{GLFW_KEY_RIGHT, r}, {GLFW_KEY_LEFT, -r}, {GLFW_KEY_UP, ahead}, {GLFW_KEY_DOWN, -ahead},
                                                       {GLFW_KEY_PAGE_UP, u}, {GLFW_KEY_PAGE_DOWN, -u}};
            for (const auto& [key, direction] : sphereKeys)
              if (glfwGetKey(window, key) == GLFW_PRESS) state.sphereCentre += direction * (speed * 0.5);
          }
          if (ImGui::IsKeyPressed(GLFW_KEY_F12)) state.screenshotRequested = true;
          if (ImGui::IsKeyPressed(GLFW_KEY_SPACE) && !state.animation.base.empty()) setPlaying(state.animation, !state.animation.playing);
        }

        // Edited lights and play/pause go to the radiosity thread, which re-injects and re-solves
        // warm, and while playing moves the lights itself at its own rate.
        if (!(state.animation == sentAnimation)) {
          worker.setAnimation(state.animation);
          sentAnimation = state.animation;
          lightsChangedAt = clock.seconds();
          lightmapsAwaited = probesAwaited = true;
        }
        worker.setFlat(state.display.flat);
        worker.setBaking(state.display.lightmaps, state.display.probes);

        // The 3-D view; screenshots take it before the panel is drawn over it.
        glViewport(0, 0, fbWidth, fbHeight);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        DisplaySettings display = state.display;
        const bool capture = (!screenshot.path.empty() && !screenshot.withPanels) || screenshotKey;
        display.lightMarkers = !capture;
        Timer upload;
        renderer.value()->upload(*shown);
        const double uploadSeconds = upload.seconds();
        const Eigen::Vector3f eye = toFloat(state.camera.camera.eye);
        const bool drawLightmaps = display.lightmaps && lightmaps;
        if (drawLightmaps) {
          Timer lightmapUpload;
          bakedRenderer.value()->upload(*lightmaps);
          lightmapUploadSeconds = std::max(lightmapUploadSeconds, lightmapUpload.seconds());
          bakedRenderer.value()->drawLightmapped(*lightmaps, viewProjection, display);
        } else {
          DisplaySettings meshDisplay = display;
          meshDisplay.lightMarkers = false;  // drawn last, over the sphere too
          renderer.value()->draw(*shown, viewProjection, eye, meshDisplay, options.scene.metresPerUnit, state.selectedLight, diagonal * 0.004);
        }
        std::optional<ShRgb> sphereSh;
        if (display.probes && probes) {
          sphereSh = probes->volume.irradianceShAt(state.sphereCentre);
          if (sphereSh)
            bakedRenderer.value()->drawSphere(*sphereSh, state.sphereCentre, options.sphereRadius, options.sphereAlbedo, viewProjection, display);
        }
        if (display.lightMarkers) renderer.value()->drawLightMarkers(shown->lights, viewProjection, state.selectedLight, diagonal * 0.004);
        // F12 and `screenshot` take the 3-D view alone; `screenshot-window` the panels too.
        auto save = [&](const std::string& path) {
          if (Status saved = saveScreenshot(path, fbWidth, fbHeight); !saved)
            result = Error{(player.active() ? player.where() + ": " : "") + saved.error().message};
          else if (screenshotKey)
            std::fprintf(stderr, "lambert view: wrote %s\n", path.c_str());
        };
        if (capture) save(screenshot.path.empty() ? "lambert-screenshot.png" : screenshot.path);
        if (!result) break;

        drawPanel(state, *shown, worker, options, lightmaps.get(), probes.get(), sphereSh.has_value());
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (screenshot.withPanels) save(screenshot.path);
        if (!result) break;
        const double cpuSeconds = cpu.seconds();
        glfwSwapBuffers(window);
        // On screen once swapped: a light change's lightmaps and probes.
        lightmapsOnScreen = drawLightmaps ? lightmaps : nullptr;
        probesOnScreen = sphereSh ? probes : nullptr;
        // (The lights as they are now: a script may have changed them since the frame began.)
        if (lightmapsAwaited || probesAwaited) {
          const std::vector<Light> drawnFor = state.animation.lightsAt(steadyClockSeconds());
          if (lightmapsAwaited && drawLightmaps && lightmaps->lights == drawnFor)
            lightmapLatency.add(clock.seconds() - lightsChangedAt), lightmapsAwaited = false;
          if (probesAwaited && sphereSh && probes->lights == drawnFor) probeLatency.add(clock.seconds() - lightsChangedAt), probesAwaited = false;
        }

        for (FrameFigures* f : {&all, state.animation.playing ? &playing : nullptr, drawLightmaps ? &lightmapped : nullptr}) {
          if (!f) continue;
          f->frames += 1;
          f->seconds += clock.seconds() - frameStart;
          f->cpuSeconds += cpuSeconds;
          f->uploadSeconds += uploadSeconds;
        }
        if (player.active() && player.waiting == ScriptPlayer::Waiting::Frames) player.framesLeft -= 1;
        if (player.finished()) break;
      }

      WorkerFigures worker_;
      Stats engineStats = worker.finish(worker_);
      stats.append(engineStats);
      stats.add("frames", "frames drawn", static_cast<std::int64_t>(all.frames));
      stats.add("frames_per_second", "frames per second", all.seconds > 0 ? all.frames / all.seconds : 0.0, "/s");
      stats.add("frame_cpu_ms_mean", "viewer's own time per frame (input, upload, draw calls, panel)",
                all.frames ? 1e3 * all.cpuSeconds / all.frames : 0.0, "ms");
      stats.add("upload_ms_mean", "snapshot upload per frame", all.frames ? 1e3 * all.uploadSeconds / all.frames : 0.0, "ms");
      if (lightmapped.frames > 0) {
        stats.add("lightmap_frames", "frames drawn with lightmaps", static_cast<std::int64_t>(lightmapped.frames));
        stats.add("lightmap_frame_ms_mean", "frame time with lightmaps (mean)", 1e3 * lightmapped.seconds / lightmapped.frames, "ms");
        stats.add("lightmap_frame_cpu_ms_mean", "viewer's own time per frame with lightmaps", 1e3 * lightmapped.cpuSeconds / lightmapped.frames, "ms");
      }
      if (playing.frames > 0) {
        stats.add("playing_frames", "frames while the lights moved", static_cast<std::int64_t>(playing.frames));
        stats.add("playing_frames_per_second", "frames per second while the lights moved", playing.frames / playing.seconds, "/s");
        stats.add("playing_light_updates_per_second", "radiosity updates per second while the lights moved",
                  worker_.lightUpdates / playing.seconds, "/s");
      }
      stats.add("updates", "radiosity updates", static_cast<std::int64_t>(worker_.updates));
      stats.add("update_solve_ms_mean", "radiosity update: inject + solve (mean)",
                worker_.updates ? 1e3 * worker_.solveSeconds / worker_.updates : 0.0, "ms");
      stats.add("update_snapshot_ms_mean", "radiosity update: vertex values, shadows, draw arrays (mean)",
                worker_.updates ? 1e3 * worker_.snapshotSeconds / worker_.updates : 0.0, "ms");
      stats.add("update_ms_max", "radiosity update (max)", 1e3 * worker_.maxUpdateSeconds, "ms");
      stats.add("light_updates", "radiosity updates for moved lights", static_cast<std::int64_t>(worker_.lightUpdates));
      stats.add("light_update_ms_mean", "radiosity update for moved lights (mean)",
                worker_.lightUpdates ? 1e3 * worker_.lightUpdateSeconds / worker_.lightUpdates : 0.0, "ms");
      stats.add("first_solution_seconds", "first solution on screen after", firstSolutionSeconds, "s");
      if (worker_.lightmapBakes > 0) {
        stats.add("lightmap_bakes", "lightmap bakes", static_cast<std::int64_t>(worker_.lightmapBakes));
        stats.add("lightmap_bake_ms_mean", "lightmap bake (mean)", 1e3 * worker_.lightmapSeconds / worker_.lightmapBakes, "ms");
        stats.add("lightmap_upload_ms_max", "lightmap texture upload (max)", 1e3 * lightmapUploadSeconds, "ms");
      }
      if (lightmapLatency.count > 0) {
        stats.add("lightmap_light_moves", "light changes whose lightmaps reached the screen", static_cast<std::int64_t>(lightmapLatency.count));
        stats.add("lightmap_move_to_screen_ms_mean", "from a light change to its lightmaps on screen (mean)",
                  1e3 * lightmapLatency.sum / lightmapLatency.count, "ms");
        stats.add("lightmap_move_to_screen_ms_max", "from a light change to its lightmaps on screen (max)", 1e3 * lightmapLatency.max, "ms");
      }
      if (worker_.probeBakes > 0) {
        stats.add("probe_bakes", "probe volume bakes", static_cast<std::int64_t>(worker_.probeBakes));
        stats.add("probe_bake_ms_mean", "probe volume bake (mean)", 1e3 * worker_.probeSeconds / worker_.probeBakes, "ms");
      }
      if (probeLatency.count > 0)
        stats.add("probe_move_to_screen_ms_mean", "from a light change to its probes on screen (mean)", 1e3 * probeLatency.sum / probeLatency.count, "ms");
      stats.add("converged_seconds", "converged on screen after", convergedSeconds, "s");
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return result;
}

}  // namespace lambert::viewer
