#include "viewer/script_player.h"

#include <cstdlib>
#include <type_traits>
#include <variant>

#include "lambert/light/lights.h"

namespace lambert::viewer {

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

}  // namespace lambert::viewer
