#include "lambert/scene/scene.h"

#include <cmath>

namespace lambert {

std::vector<std::vector<std::uint32_t>> surfaceFaces(const Surface& surface) {
  if (!surface.faces.empty()) return surface.faces;
  std::vector<std::uint32_t> all(surface.vertices.size());
  for (std::uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  return {all};
}

std::vector<Vec3> facePositions(const Surface& surface, const std::vector<std::uint32_t>& face) {
  std::vector<Vec3> positions;
  positions.reserve(face.size());
  for (std::uint32_t k : face) positions.push_back(surface.vertices[k]);
  return positions;
}

namespace {

// Newell's vector: twice the polygon's area along its normal.
Vec3 newell(const std::vector<Vec3>& v) {
  Vec3 n;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    n += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return n;
}

}  // namespace

Vec3 polygonNormal(const std::vector<Vec3>& polygon) { return normalize(newell(polygon)); }

Vec3 surfaceNormal(const Surface& surface) {
  Vec3 n;
  for (const auto& face : surfaceFaces(surface)) n += newell(facePositions(surface, face));
  return normalize(n);
}

double surfaceArea(const Surface& surface) {
  double area = 0;
  for (const auto& face : surfaceFaces(surface)) {
    const std::vector<Vec3> v = facePositions(surface, face);
    for (std::size_t i = 1; i + 1 < v.size(); ++i) area += 0.5 * length(cross(v[i] - v[0], v[i + 1] - v[0]));
  }
  return area;
}

Camera cameraViewingScene(const Scene& scene) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
  for (const Surface& s : scene.surfaces)
    for (const Vec3& p : s.vertices) {
      lo = componentMin(lo, p);
      hi = componentMax(hi, p);
    }
  Camera camera;
  const Vec3 centre = (lo + hi) * 0.5;
  camera.target = centre;
  camera.eye = centre - Vec3{0, 0, 1.5 * length(hi - lo)};
  return camera;
}

}  // namespace lambert
