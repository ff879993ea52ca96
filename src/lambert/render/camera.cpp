#include "lambert/render/camera.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"

namespace lambert {

PinholeCamera::PinholeCamera(const Camera& camera, int width_, int height_)
    : eye(camera.eye), width(width_), height(height_) {
  LAMBERT_CHECK(width > 0 && height > 0);
  LAMBERT_CHECK(camera.verticalFovDegrees > 0 && camera.verticalFovDegrees < 180);
  Vec3 view = camera.target - camera.eye;
  double distance = length(view);
  // A degenerate camera (target on the eye, up along the view) still gets a valid basis, so a
  // bad scene file gives a bad picture rather than NaNs everywhere.
  forward = distance > 0 ? view / distance : Vec3{0, 0, 1};
  Vec3 side = cross(forward, camera.up);
  if (lengthSquared(side) < 1e-20 * std::max(1.0, lengthSquared(camera.up))) {
    Vec3 fallback = std::fabs(forward.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
    side = cross(forward, fallback);
  }
  right = normalize(side);
  up = cross(right, forward);
  tanHalfFovY = std::tan(camera.verticalFovDegrees * kPi / 360.0);
  tanHalfFovX = tanHalfFovY * width / height;
  focalPixels = 0.5 * height / tanHalfFovY;
  nearDistance = nearPlaneDistance(distance);
}

std::optional<ScreenPoint> PinholeCamera::project(const Vec3& world) const {
  Vec3 view = toView(world);
  if (!(view.z >= nearDistance)) return std::nullopt;
  return projectView(view);
}

}  // namespace lambert
