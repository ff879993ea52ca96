#pragma once
// A pinhole camera that maps world points to pixel coordinates of one image size.
#include <optional>

#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert {

// A projected point: pixel coordinates (x to the right, y downward, the centre of pixel (i, j) at
// (i + 0.5, j + 0.5)) and the distance in front of the eye along the view axis (scene units).
struct ScreenPoint {
  double x = 0, y = 0;
  double depth = 0;
};

// The near plane for a camera whose eye stands `eyeTargetDistance` from its target: a hundredth
// of that, as RenderPark clips for a camera inside the scene. Its scripts stand cameras a few
// centimetres outside a room's wall (the hospital's, 4.5 cm in front of the corridor wall's outer
// face, which faces it), and RenderPark's picture shows the room through it. The rasterizer, the
// path tracer's camera rays and the viewer all start here.
inline double nearPlaneDistance(double eyeTargetDistance) { return 1e-2 * (eyeTargetDistance > 0 ? eyeTargetDistance : 1.0); }

// View space: x to the right of the image, y up the image, z along the view direction (depth).
// The basis is right-handed in world terms (right = forward × up), which is what puts the red wall
// of the Cornell box (x ≈ 555) on the left of the published view from z = -800.
struct PinholeCamera {
  PinholeCamera(const Camera& camera, int width, int height);

  Vec3 eye;
  Vec3 right, up, forward;      // orthonormal, world space
  int width = 0, height = 0;    // pixels
  double focalPixels = 0;       // distance to the image plane, in pixels
  double tanHalfFovX = 0, tanHalfFovY = 0;
  // Points closer than this (along the view axis) are not projected: nearPlaneDistance.
  double nearDistance = 0;

  Vec3 toView(const Vec3& world) const {
    Vec3 d = world - eye;
    return {dot(d, right), dot(d, up), dot(d, forward)};
  }
  // Projects a view-space point; its z must be positive.
  ScreenPoint projectView(const Vec3& view) const {
    double s = focalPixels / view.z;
    return {0.5 * width + view.x * s, 0.5 * height - view.y * s, view.z};
  }
  // Empty when the point is not in front of the near plane.
  std::optional<ScreenPoint> project(const Vec3& world) const;
};

}  // namespace lambert
