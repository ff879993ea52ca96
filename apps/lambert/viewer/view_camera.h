#pragma once
// The viewer's camera: orbit about the target or fly about the eye, pan, dolly, and the OpenGL
// view and projection matrices of it.
#include <Eigen/Core>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert::viewer {

inline constexpr double kDegrees = kPi / 180;

inline Eigen::Vector3f toFloat(const Vec3& v) { return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; }

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
  void turn(double yaw, double pitch);
  void orbit(double yaw, double pitch);
  void pan(double dx, double dy);
  void dolly(double factor) { camera.eye = camera.target + (camera.eye - camera.target) * factor; }
  void move(const Vec3& step) {
    camera.eye += step;
    camera.target += step;
  }

  Eigen::Matrix4f view() const;
  // Near and far planes from the scene's bounds, so the depth buffer spans what can be seen.
  Eigen::Matrix4f projection(double aspect, const Vec3& lo, const Vec3& hi) const;
};

}  // namespace lambert::viewer
