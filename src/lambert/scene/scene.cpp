#include "lambert/scene/scene.h"

namespace lambert {

Vec3 surfaceNormal(const Surface& surface) {
  // Newell's method: robust for slightly non-planar quads and any vertex count.
  Vec3 n;
  const auto& v = surface.vertices;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    n += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return normalize(n);
}

double surfaceArea(const Surface& surface) {
  double area = 0;
  const auto& v = surface.vertices;
  for (std::size_t i = 1; i + 1 < v.size(); ++i) area += 0.5 * length(cross(v[i] - v[0], v[i + 1] - v[0]));
  return area;
}

}  // namespace lambert
