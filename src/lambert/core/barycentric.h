#pragma once
// Barycentric coordinates in a triangle in space.
#include <array>

#include "lambert/core/vec3.h"

namespace lambert {

// The barycentric weights (of a, b, c) of p, projected into the plane of triangle (a, b, c): the
// least-squares solution over the triangle's two edges. (1, 0, 0) for a degenerate triangle.
inline std::array<double, 3> barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e0 = b - a, e1 = c - a, d = p - a;
  const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(d, e0), d21 = dot(d, e1);
  const double denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 0)) return {1, 0, 0};
  const double v = (d11 * d20 - d01 * d21) / denominator, w = (d00 * d21 - d01 * d20) / denominator;
  return {1 - v - w, v, w};
}

}  // namespace lambert
