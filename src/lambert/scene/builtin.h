#pragma once
// Scenes built into lambert, available by name without a file.
#include <optional>
#include <string>
#include <vector>

#include "lambert/scene/scene.h"

namespace lambert {

// The Cornell Box as published by the Cornell Program of Computer Graphics (geometry in
// millimetres, linear-RGB albedos, an area light of radiance (17, 12, 4) W/(m²·sr)).
Scene cornellBox();

// The Cornell box lit only by two coloured spotlights (the ceiling light is dark), each turning
// with its own angular velocity: a scene of moving lights.
Scene cornellBoxWithSpots();

std::optional<Scene> builtinScene(const std::string& name);
std::vector<std::string> builtinSceneNames();

}  // namespace lambert
