#pragma once
// An affine transform of points and directions, p' = A·p + t, as glTF writes one: a column-major
// 4 × 4 matrix whose bottom row is (0, 0, 0, 1) for every transform built here (a file's own
// matrix is taken as it is). The readers place what they read with it: MGF's xf contexts, a scene
// file's mesh transforms, glTF's node hierarchy.
//
// Products are accumulated from 0 over the four terms of each entry, in index order, so that a
// product rounds the same wherever it is taken; a point is A's rows dotted with it, then t added.
#include <array>

#include "lambert/core/vec3.h"

namespace lambert {

struct Transform {
  std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

  // This after o: (this · o).point(p) = this->point(o.point(p)).
  Transform operator*(const Transform& o) const;
  Vec3 point(const Vec3& p) const {
    return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
            m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
  }
  // A (no translation): for directions, not normals (the transforms here have no shear, and
  // uniform scale where normals are turned).
  Vec3 direction(const Vec3& d) const {
    return {m[0] * d.x + m[4] * d.y + m[8] * d.z, m[1] * d.x + m[5] * d.y + m[9] * d.z, m[2] * d.x + m[6] * d.y + m[10] * d.z};
  }
  double determinant() const {  // of A
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
  }
  // A mirroring transform turns a counter-clockwise polygon clockwise: faces are reversed.
  bool mirrors() const { return determinant() < 0; }
  // This applied n times (the identity for n = 0).
  Transform power(int n) const;

  static Transform translation(const Vec3& d);
  // About coordinate axis 0 (x), 1 (y) or 2 (z), counter-clockwise looking down the axis toward
  // the origin.
  static Transform rotation(int axis, double degrees);
  static Transform scaling(double f);
  static Transform scaling(const Vec3& f);  // per axis
  static Transform mirror(int axis);        // the axis's coordinate negated
};

}  // namespace lambert
