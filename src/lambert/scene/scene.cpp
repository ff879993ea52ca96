#include "lambert/scene/scene.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"

namespace lambert {

std::vector<std::vector<std::uint32_t>> surfaceFaces(const Surface& surface) {
  if (!surface.faces.empty()) return surface.faces;
  return {surfaceFace(surface, 0)};
}

std::vector<std::uint32_t> surfaceFace(const Surface& surface, std::size_t index) {
  if (!surface.faces.empty()) return surface.faces[index];
  std::vector<std::uint32_t> all(surface.vertices.size());
  for (std::uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  return all;
}

std::vector<Vec3> facePositions(const Surface& surface, const std::vector<std::uint32_t>& face) {
  std::vector<Vec3> positions;
  positions.reserve(face.size());
  for (std::uint32_t k : face) positions.push_back(surface.vertices[k]);
  return positions;
}

Vec3 polygonAreaVector(const std::vector<Vec3>& v) {
  Vec3 n;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    n += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return n;
}

Vec3 polygonNormal(const std::vector<Vec3>& polygon) { return normalize(polygonAreaVector(polygon)); }

double polygonExtent(const std::vector<Vec3>& v) {
  Vec3 lo = v[0], hi = v[0];
  for (const Vec3& p : v) {
    lo = componentMin(lo, p);
    hi = componentMax(hi, p);
  }
  return length(hi - lo);
}

std::size_t firstConcaveCorner(const std::vector<Vec3>& v, const Vec3& normal) {
  Vec3 tangent, bitangent;
  orthonormalBasis(normal, tangent, bitangent);
  const double size = polygonExtent(v);
  double turning = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const Vec3 a = v[k], b = v[(k + 1) % v.size()], c = v[(k + 2) % v.size()];
    const double inX = dot(b - a, tangent), inY = dot(b - a, bitangent);
    const double outX = dot(c - b, tangent), outY = dot(c - b, bitangent);
    const double sine = inX * outY - inY * outX;
    if (sine < -1e-12 * size * size) return (k + 1) % v.size();
    turning += std::atan2(sine, inX * outX + inY * outY);
  }
  return std::fabs(turning - 2 * kPi) < 1e-6 ? v.size() : 0;
}

Vec3 surfaceNormal(const Surface& surface) {
  Vec3 n;
  for (const auto& face : surfaceFaces(surface)) n += polygonAreaVector(facePositions(surface, face));
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

bool anyEmits(const Scene& scene) {
  return std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [](const Surface& s) { return s.emittedRadiance.maxComponent() > 0; });
}

Bounds sceneBounds(const Scene& scene) {
  Bounds b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (const Surface& s : scene.surfaces)
    for (const Vec3& p : s.vertices) {
      b.lo = componentMin(b.lo, p);
      b.hi = componentMax(b.hi, p);
    }
  return b;
}

Vec3 FileFrame::filePoint(const Vec3& scenePoint) const {
  // Solve [a0 a1 a2]·p = q by Cramer's rule.
  const Vec3 q = scenePoint - offset;
  const double det = dot(axes[0], cross(axes[1], axes[2]));
  LAMBERT_CHECK(det != 0);
  return {dot(q, cross(axes[1], axes[2])) / det, dot(axes[0], cross(q, axes[2])) / det, dot(axes[0], cross(axes[1], q)) / det};
}

Camera cameraViewingScene(const Scene& scene) {
  const auto [lo, hi] = sceneBounds(scene);
  Camera camera;
  const Vec3 centre = (lo + hi) * 0.5;
  camera.target = centre;
  camera.eye = centre - Vec3{0, 0, 1.5 * length(hi - lo)};
  return camera;
}

}  // namespace lambert

namespace lambert {

void addTwins(Scene& scene) {
  const std::size_t count = scene.surfaces.size();
  for (std::size_t s = 0; s < count; ++s) {
    if (scene.surfaces[s].twin >= 0 || !scene.materials[static_cast<std::size_t>(scene.surfaces[s].material)].twoSided) continue;
    Surface back = scene.surfaces[s];
    back.name += " (back)";
    back.faces = surfaceFaces(back);
    for (auto& face : back.faces) std::reverse(face.begin() + 1, face.end());
    for (auto& uvs : back.faceUvs) std::reverse(uvs.begin() + 1, uvs.end());
    for (auto& uvs : back.faceLightmapUvs) std::reverse(uvs.begin() + 1, uvs.end());
    if (scene.surfaces[s].faces.empty()) {  // keep a lone polygon a lone polygon (the quad-tree meshes those)
      std::vector<Vec3> reversed{back.vertices.front()};
      reversed.insert(reversed.end(), back.vertices.rbegin(), back.vertices.rend() - 1);
      back.vertices = std::move(reversed);
      back.faces.clear();
    }
    back.twin = static_cast<int>(s);
    scene.surfaces[s].twin = static_cast<int>(scene.surfaces.size());
    scene.surfaces.push_back(std::move(back));
  }
}

Rgb Texture::sample(double u, double v) const {
  if (width <= 0 || height <= 0) return Rgb::gray(1);
  // Repeat first (a non-finite coordinate from a broken file reads the first texel), then pixel
  // centres sit at (i + ½)/width; both neighbours wrap, so the filter repeats across edges.
  auto repeat = [](double t) {
    const double f = t - std::floor(t);
    return std::isfinite(f) ? f : 0.0;
  };
  const double x = repeat(u) * width - 0.5, y = repeat(v) * height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  auto wrap = [](double i, int n) { return static_cast<int>(((static_cast<long long>(i) % n) + n) % n); };
  const int x0 = wrap(fx, width), x1 = wrap(fx + 1, width), y0 = wrap(fy, height), y1 = wrap(fy + 1, height);
  auto at = [this](int px, int py) { return pixels[static_cast<std::size_t>(py) * width + px]; };
  return (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) + (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
}

}  // namespace lambert
