#include "viewer/panel.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <imgui.h>

namespace lambert::viewer {

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

}  // namespace lambert::viewer
