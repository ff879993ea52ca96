#include "lambert/core/transform.h"

#include <cmath>

#include "lambert/core/rgb.h"

namespace lambert {

Transform Transform::operator*(const Transform& o) const {
  Transform r;
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += m[k * 4 + row] * o.m[col * 4 + k];
      r.m[col * 4 + row] = s;
    }
  return r;
}

Transform Transform::power(int n) const {
  Transform r;
  for (int i = 0; i < n; ++i) r = *this * r;
  return r;
}

Transform Transform::translation(const Vec3& d) {
  Transform r;
  r.m[12] = d.x, r.m[13] = d.y, r.m[14] = d.z;
  return r;
}

Transform Transform::rotation(int axis, double degrees) {
  const double rad = degrees * kPi / 180, c = std::cos(rad), s = std::sin(rad);
  Transform r;
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane turned counter-clockwise
  r.m[i * 4 + i] = c;
  r.m[j * 4 + i] = -s;
  r.m[i * 4 + j] = s;
  r.m[j * 4 + j] = c;
  return r;
}

Transform Transform::scaling(double f) { return scaling(Vec3{f, f, f}); }

Transform Transform::scaling(const Vec3& f) {
  Transform r;
  r.m[0] = f.x, r.m[5] = f.y, r.m[10] = f.z;
  return r;
}

Transform Transform::mirror(int axis) {
  Transform r;
  r.m[axis * 5] = -1;
  return r;
}

}  // namespace lambert
