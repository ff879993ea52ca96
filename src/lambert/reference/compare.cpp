#include "lambert/reference/compare.h"

#include <cmath>

#include "lambert/geometry/coverage.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/emission.h"

namespace lambert {
namespace {

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  Vec3 ab = b - a;
  double t = std::fmin(std::fmax(dot(p - a, ab) / lengthSquared(ab), 0.0), 1.0);
  return length(p - (a + ab * t));
}

// Distance from p to a planar convex polygon (its interior or its edges).
double distanceToPolygon(const Vec3& p, const std::vector<Vec3>& v) {
  Vec3 n = polygonNormal(v);
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
  double largest = 0, sumSquares = 0, sum = 0, sumValue = 0;
  for (std::size_t i = 0; i < value.size(); ++i)
    if (include.empty() || include[i]) largest = std::fmax(largest, reference[i].maxComponent());
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!include.empty() && !include[i]) continue;
    for (int c = 0; c < 3; ++c) {
      double r = reference[i][c], d = std::fabs(value[i][c] - r);
      sum += r;
      sumValue += value[i][c];
      sumSquares += d * d;
      e.maxAbsolute = std::fmax(e.maxAbsolute, d);
      if (r >= 0.01 * largest && r > 0) e.maxRelative = std::fmax(e.maxRelative, d / r);
      ++e.count;
    }
  }
  if (e.count == 0) return e;
  e.meanReference = sum / e.count;
  e.meanValue = sumValue / e.count;
  e.rmse = std::sqrt(sumSquares / e.count);
  e.relativeRmse = e.meanReference > 0 ? e.rmse / e.meanReference : 0;
  return e;
}

std::vector<char> awayFromEmitters(const Scene& scene, std::span<const Vec3> points, double distance) {
  std::vector<char> keep(points.size(), 1);
  for (const Surface& surface : scene.surfaces) {
    if (meanEmittedRadiance(scene, surface).maxComponent() <= 0) continue;  // an emission texture black all over it
    for (const std::vector<std::uint32_t>& face : surfaceFaces(surface)) {
      const std::vector<Vec3> polygon = facePositions(surface, face);
      for (std::size_t i = 0; i < points.size(); ++i)
        if (distanceToPolygon(points[i], polygon) < distance) keep[i] = 0;
    }
  }
  return keep;
}

Result<VertexComparison> compareVertices(const Scene& scene, std::span<const VertexSample> value,
                                         std::span<const VertexSample> reference, double rimDistance) {
  if (value.size() != reference.size())
    return Error{"the solution has " + std::to_string(value.size()) + " vertices but the reference " +
                 std::to_string(reference.size()) + ": use the same scene and mesh options"};
  const double diagonal = sceneDiagonal(scene);
  std::vector<Vec3> positions;
  std::vector<Rgb> mine, truth;
  for (std::size_t v = 0; v < value.size(); ++v) {
    if (length(value[v].position - reference[v].position) > 1e-6 * diagonal)
      return Error{"vertex " + std::to_string(v) + " lies at different places in the two: use the same mesh options"};
    positions.push_back(value[v].position);
    mine.push_back(value[v].radiance);
    truth.push_back(reference[v].radiance);
  }
  VertexComparison result;
  std::vector<char> keep = awayFromEmitters(scene, positions, rimDistance >= 0 ? rimDistance : 0.05 * diagonal);
  for (char k : keep) result.nearEmitters += !k;
  Mesh geometry = subdivideScene(scene, 2 * diagonal);
  auto caster = makeEmbreeRayCaster(geometry);
  const double epsilon = rayEpsilon(geometry);
  for (std::size_t v = 0; v < keep.size(); ++v)
    if (keep[v] && isCovered(*caster, value[v].position, value[v].normal, epsilon)) {
      keep[v] = 0;
      ++result.covered;
    }
  result.error = radianceError(mine, truth, keep);
  result.everywhere = radianceError(mine, truth);
  return result;
}

}  // namespace lambert
