#pragma once
// A cone that holds a set of unit normals: an axis and a half angle (Shirley's, as lightcuts and
// many-light trees bound their lights' orientations; Walter et al. 2005, "Lightcuts", §4.1), and
// whether anything facing one way can face a region seen from another. The union of two cones is
// the smallest cone holding both (Barringer's "Bounding normal cones", 2017, merge rule).
#include <algorithm>
#include <cmath>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"

namespace lambert {

struct NormalCone {
  Vec3 axis{};             // unit; meaningless where empty or whole
  double halfAngle = -1;   // radians: < 0 holds nothing, ≥ π every direction

  static NormalCone of(const Vec3& unitNormal) { return {unitNormal, 0}; }
  static NormalCone everyDirection() { return {{0, 0, 1}, kPi}; }
  bool empty() const { return halfAngle < 0; }
  bool whole() const { return halfAngle >= kPi; }
};

// The angle between two unit vectors, accurate near 0 and π too (acos is not).
inline double angleBetween(const Vec3& a, const Vec3& b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// The smallest cone that holds both (rounding pads the angle by a few ulps' worth).
inline NormalCone mergeCones(const NormalCone& a, const NormalCone& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  if (a.whole() || b.whole()) return NormalCone::everyDirection();
  const double between = angleBetween(a.axis, b.axis);
  if (between + b.halfAngle <= a.halfAngle) return a;
  if (between + a.halfAngle <= b.halfAngle) return b;
  const double half = 0.5 * (between + a.halfAngle + b.halfAngle) + 1e-9;
  if (half >= kPi) return NormalCone::everyDirection();
  // Turn a's axis toward b's by (half − a.halfAngle) in their common plane.
  const Vec3 across = b.axis - a.axis * dot(a.axis, b.axis);
  const double acrossLength = length(across);
  if (!(acrossLength > 1e-12)) return {a.axis, half};  // opposite axes: any plane holds them
  const double turn = half - a.halfAngle;
  return {normalize(a.axis * std::cos(turn) + across * (std::sin(turn) / acrossLength)), half};
}

// Whether a face with a normal in the cone, at a point within `fromRadius` of `from`, may have a
// point within `toRadius` of `to` strictly in front of its plane. The directions from one ball
// to the other lie within asin((r₁ + r₂)/d) of the centres' line; a normal within the cone's
// half angle of its axis makes an angle of at least (angle(axis, line) − half − spread) with
// each, and faces none of them when that is a right angle or more.
inline bool coneMayFace(const NormalCone& cone, const Vec3& from, double fromRadius, const Vec3& to, double toRadius) {
  if (cone.empty()) return false;
  if (cone.whole()) return true;
  const Vec3 line = to - from;
  const double distance = length(line), reach = fromRadius + toRadius;
  if (!(distance > reach)) return true;
  const double spread = std::asin(std::min(1.0, reach / distance));
  const double toLine = angleBetween(cone.axis, line / distance);
  return toLine - cone.halfAngle - spread < 0.5 * kPi + 1e-9;
}

}  // namespace lambert
