#include "lambert/pipeline/compare.h"

#include <cmath>

#include "lambert/core/error.h"

namespace lambert {
namespace {

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  Vec3 ab = b - a;
  double t = std::fmin(std::fmax(dot(p - a, ab) / lengthSquared(ab), 0.0), 1.0);
  return length(p - (a + ab * t));
}

// Distance from p to a planar convex polygon (its interior or its edges).
double distanceToPolygon(const Vec3& p, const Surface& surface) {
  const auto& v = surface.vertices;
  Vec3 n = surfaceNormal(surface);
  double height = dot(p - v[0], n);
  Vec3 projected = p - n * height;
  bool inside = true;
  for (std::size_t k = 0; k < v.size(); ++k)
    inside &= dot(cross(v[(k + 1) % v.size()] - v[k], projected - v[k]), n) >= 0;
  if (inside) return std::fabs(height);
  double best = INFINITY;
  for (std::size_t k = 0; k < v.size(); ++k) best = std::fmin(best, distanceToSegment(p, v[k], v[(k + 1) % v.size()]));
  return best;
}

}  // namespace

RadianceError radianceError(std::span<const Rgb> value, std::span<const Rgb> reference, std::span<const char> include) {
  LAMBERT_CHECK(value.size() == reference.size());
  LAMBERT_CHECK(include.empty() || include.size() == value.size());
  RadianceError e;
  double largest = 0, sumSquares = 0, sum = 0;
  for (std::size_t i = 0; i < value.size(); ++i)
    if (include.empty() || include[i]) largest = std::fmax(largest, reference[i].maxComponent());
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!include.empty() && !include[i]) continue;
    for (int c = 0; c < 3; ++c) {
      double r = reference[i][c], d = std::fabs(value[i][c] - r);
      sum += r;
      sumSquares += d * d;
      e.maxAbsolute = std::fmax(e.maxAbsolute, d);
      if (r >= 0.01 * largest && r > 0) e.maxRelative = std::fmax(e.maxRelative, d / r);
      ++e.count;
    }
  }
  if (e.count == 0) return e;
  e.meanReference = sum / e.count;
  e.rmse = std::sqrt(sumSquares / e.count);
  e.relativeRmse = e.meanReference > 0 ? e.rmse / e.meanReference : 0;
  return e;
}

std::vector<char> awayFromEmitters(const Scene& scene, std::span<const Vec3> points, double distance) {
  std::vector<char> keep(points.size(), 1);
  for (const Surface& surface : scene.surfaces) {
    if (surface.emittedRadiance.maxComponent() <= 0) continue;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (distanceToPolygon(points[i], surface) < distance) keep[i] = 0;
  }
  return keep;
}

}  // namespace lambert
