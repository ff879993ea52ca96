#pragma once
// Picking a light in the viewer: the light whose marker lies nearest a click on the screen.
#include <vector>

#include <Eigen/Core>

#include "lambert/scene/scene.h"

namespace lambert::viewer {

// The light whose marker is nearest the cursor, within 12 pixels; -1 for none.
int pickLight(const std::vector<Light>& lights, const Eigen::Matrix4f& viewProjection, double x, double y, int width, int height);

}  // namespace lambert::viewer
