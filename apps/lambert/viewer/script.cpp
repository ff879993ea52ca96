#include "viewer/script.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace lambert::viewer {
namespace {

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> result;
  std::istringstream in(line.substr(0, line.find('#')));
  for (std::string word; in >> word;) result.push_back(word);
  return result;
}

// Reads a finite number; the error says which argument of which command is wrong.
Result<double> number(const std::string& word, const std::string& what) {
  double value = 0;
  auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(value))
    return Error{what + " must be a finite number, not '" + word + "'"};
  return value;
}

struct Parser {
  const std::vector<std::string>& w;
  std::size_t next = 1;

  Result<double> take(const std::string& what) {
    if (next >= w.size()) return Error{"'" + w[0] + "' needs " + what};
    return number(w[next++], what);
  }
  Result<Vec3> takeVec3(const std::string& what) {
    Vec3 v;
    for (double* c : {&v.x, &v.y, &v.z}) {
      Result<double> x = take(what + " (three numbers)");
      if (!x) return x.error();
      *c = *x;
    }
    return v;
  }
  Result<int> takeLight() {
    Result<double> index = take("a light index");
    if (!index) return index.error();
    if (*index < 0 || *index != std::floor(*index) || *index > 1e6)
      return Error{"the light index must be a whole number from 0, not " + w[next - 1]};
    return static_cast<int>(*index);
  }
  Status done() const {
    if (next < w.size()) return Error{"'" + w[0] + "' takes " + std::to_string(next - 1) + " argument(s); '" + w[next] + "' is one too many"};
    return Ok{};
  }
};

Result<ScriptStep> parseStep(const std::vector<std::string>& w) {
  Parser p{w};
  const std::string& command = w[0];
  auto finish = [&p](ScriptStep step) -> Result<ScriptStep> {
    if (Status ok = p.done(); !ok) return ok.error();
    return step;
  };
  auto timeout = [&p, &w](double& seconds) -> Status {
    if (w.size() < 2) return Ok{};
    Result<double> t = p.take("a timeout in seconds");
    if (!t) return t.error();
    if (*t <= 0) return Error{"the timeout must be positive"};
    seconds = *t;
    return Ok{};
  };
  if (command == "frames") {
    Result<double> n = p.take("a frame count");
    if (!n) return n.error();
    if (*n < 1 || *n > 1e7 || *n != std::floor(*n)) return Error{"the frame count must be a whole number from 1 to 10^7"};
    return finish(DrawFrames{static_cast<int>(*n)});
  }
  if (command == "wait-solution") {
    WaitForSolution step;
    if (Status ok = timeout(step.timeoutSeconds); !ok) return ok.error();
    return finish(step);
  }
  if (command == "wait-converged") {
    WaitForConvergence step;
    if (Status ok = timeout(step.timeoutSeconds); !ok) return ok.error();
    return finish(step);
  }
  if (command == "wait-lightmaps") {
    WaitForLightmaps step;
    if (Status ok = timeout(step.timeoutSeconds); !ok) return ok.error();
    return finish(step);
  }
  if (command == "wait-probes") {
    WaitForProbes step;
    if (Status ok = timeout(step.timeoutSeconds); !ok) return ok.error();
    return finish(step);
  }
  if (command == "sphere") {
    Result<Vec3> centre = p.takeVec3("the sphere's centre");
    if (!centre) return centre.error();
    return finish(SetSphere{*centre});
  }
  if (command == "screenshot" || command == "screenshot-window") {
    if (w.size() != 2) return Error{"'" + command + "' takes one PNG path"};
    if (w[1].size() < 5 || w[1].substr(w[1].size() - 4) != ".png") return Error{"a screenshot is a .png, not '" + w[1] + "'"};
    return ScriptStep{Screenshot{w[1], command == "screenshot-window"}};
  }
  if (command == "camera") {
    SetCamera step;
    Result<Vec3> eye = p.takeVec3("the eye position");
    if (!eye) return eye.error();
    Result<Vec3> target = p.takeVec3("the target position");
    if (!target) return target.error();
    if (length(*eye - *target) <= 0) return Error{"the eye and the target must differ"};
    return finish(SetCamera{*eye, *target});
  }
  if (command == "orbit") {
    Result<double> yaw = p.take("a yaw angle in degrees");
    if (!yaw) return yaw.error();
    Result<double> pitch = p.take("a pitch angle in degrees");
    if (!pitch) return pitch.error();
    return finish(OrbitCamera{*yaw, *pitch});
  }
  if (command == "play" || command == "pause") return finish(SetPlaying{command == "play"});
  if (command == "select") {
    Result<int> light = p.takeLight();
    if (!light) return light.error();
    return finish(SelectLight{*light});
  }
  if (command == "light") {
    Result<int> light = p.takeLight();
    if (!light) return light.error();
    if (w.size() < 3) return Error{"'light N' needs a property: position, direction, aim, intensity or cone"};
    const std::string property = w[p.next++];
    if (property == "position" || property == "direction" || property == "aim") {
      Result<Vec3> v = p.takeVec3("the " + property);
      if (!v) return v.error();
      if (property == "position") return finish(SetLightPosition{*light, *v});
      if (property == "aim") return finish(AimLight{*light, *v});
      if (length(*v) <= 0) return Error{"a direction must not be zero"};
      return finish(SetLightDirection{*light, normalize(*v)});
    }
    if (property == "intensity") {
      Result<Vec3> v = p.takeVec3("the intensity R G B");
      if (!v) return v.error();
      if (v->x < 0 || v->y < 0 || v->z < 0) return Error{"an intensity must not be negative"};
      return finish(SetLightIntensity{*light, Rgb{v->x, v->y, v->z}});
    }
    if (property == "cone") {
      Result<double> cone = p.take("the cone half-angle in degrees");
      if (!cone) return cone.error();
      Result<double> falloff = p.take("the falloff width in degrees");
      if (!falloff) return falloff.error();
      if (*cone <= 0 || *cone > 90) return Error{"the cone half-angle must be in (0, 90] degrees"};
      if (*falloff < 0 || *falloff > *cone) return Error{"the falloff must be from 0 to the cone half-angle"};
      return finish(SetLightCone{*light, *cone, *falloff});
    }
    return Error{"unknown light property '" + property + "' (position, direction, aim, intensity or cone)"};
  }
  if (command == "lighting" || command == "shading" || command == "wireframe" || command == "false-colour" ||
      command == "srgb" || command == "ambient" || command == "exposure" || command == "lightmaps" || command == "probes") {
    if (w.size() != 2) return Error{"'" + command + "' takes one value"};
    if (Status ok = checkDisplaySetting(command, w[1]); !ok) return ok.error();
    return ScriptStep{SetDisplay{command, w[1]}};
  }
  return Error{"unknown command '" + command +
               "' (frames, wait-solution, wait-converged, wait-lightmaps, wait-probes, sphere, screenshot, screenshot-window, camera, orbit, light, select, play, pause, lighting, shading, "
               "wireframe, false-colour, srgb, ambient, exposure, lightmaps, probes)"};
}

}  // namespace

Status checkDisplaySetting(const std::string& setting, const std::string& value) {
  auto oneOf = [&](std::initializer_list<const char*> allowed) -> Status {
    std::string list;
    for (const char* a : allowed) {
      if (value == a) return Ok{};
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    return Error{"'" + setting + "' is one of " + list + ", not '" + value + "'"};
  };
  if (setting == "lighting") return oneOf({"both", "direct", "indirect"});
  if (setting == "shading") return oneOf({"gouraud", "flat"});
  if (setting == "exposure") {
    Result<double> stops = number(value, "the exposure in stops");
    if (!stops) return stops.error();
    if (std::fabs(*stops) > 64) return Error{"the exposure must be within ±64 stops"};
    return Ok{};
  }
  return oneOf({"on", "off"});
}

Result<Script> parseScript(const std::string& text, const std::string& path) {
  Script script{path, {}};
  std::istringstream in(text);
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    std::vector<std::string> w = words(line);
    if (w.empty()) continue;
    Result<ScriptStep> step = parseStep(w);
    if (!step) return Error{path + ":" + std::to_string(number) + ": " + step.error().message};
    script.lines.push_back({number, std::move(*step)});
  }
  return script;
}

Result<Script> readScript(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{path + ": cannot open the script"};
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) return Error{path + ": cannot read the script"};
  return parseScript(text.str(), path);
}

Status checkScriptLights(const Script& script, std::size_t lightCount) {
  for (const ScriptLine& line : script.lines) {
    int light = std::visit(
        [](const auto& step) -> int {
          if constexpr (requires { step.light; }) return step.light;
          return -1;
        },
        line.step);
    if (light >= 0 && static_cast<std::size_t>(light) >= lightCount)
      return Error{script.path + ":" + std::to_string(line.line) + ": light " + std::to_string(light) + " does not exist: the scene has " +
                   std::to_string(lightCount) + " point, spot or directional light(s)"};
  }
  return Ok{};
}

}  // namespace lambert::viewer
