#include "viewer/picking.h"

#include <cmath>

#include <Eigen/Geometry>

#include "viewer/view_camera.h"

namespace lambert::viewer {

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

}  // namespace lambert::viewer
