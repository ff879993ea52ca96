#include "viewer/view_camera.h"

#include <algorithm>
#include <cmath>

#include "lambert/render/camera.h"

namespace lambert::viewer {

void ViewCamera::turn(double yaw, double pitch) {
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

void ViewCamera::orbit(double yaw, double pitch) {
  const bool wasFly = fly;
  fly = false;
  turn(yaw, pitch);
  fly = wasFly;
}

void ViewCamera::pan(double dx, double dy) {
  const double distance = length(camera.target - camera.eye);
  const Vec3 upOnScreen = cross(right(), forward());
  const Vec3 shift = (right() * -dx + upOnScreen * dy) * distance;
  camera.eye += shift;
  camera.target += shift;
}

Eigen::Matrix4f ViewCamera::view() const {
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

Eigen::Matrix4f ViewCamera::projection(double aspect, const Vec3& lo, const Vec3& hi) const {
  double far = 0;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
    far = std::max(far, dot(p - camera.eye, forward()));
  }
  far = std::max(far * 1.01, 1e-6);
  const double near = std::max(nearPlaneDistance(length(camera.target - camera.eye)), far * 1e-5);
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

}  // namespace lambert::viewer
