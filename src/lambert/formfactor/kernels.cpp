#include "lambert/formfactor/kernels.h"

#include <cmath>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"

namespace lambert {

double pointToPointKernel(const Vec3& x, const Vec3& xNormal, const Vec3& y, const Vec3& yNormal) {
  Vec3 d = y - x;
  double r2 = lengthSquared(d);
  double cosX = dot(xNormal, d);
  double cosY = -dot(yNormal, d);
  if (cosX <= 0 || cosY <= 0 || r2 <= 0) return 0;
  return cosX * cosY / (kPi * r2 * r2);  // both cosines carry a factor r
}

std::size_t clipAbovePlane(std::span<const Vec3> polygon, const Vec3& point, const Vec3& normal, Vec3* out) {
  std::size_t count = 0;
  const std::size_t n = polygon.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& a = polygon[k];
    const Vec3& b = polygon[(k + 1) % n];
    double ha = dot(a - point, normal), hb = dot(b - point, normal);
    if (ha > 0) out[count++] = a;
    if ((ha > 0) != (hb > 0)) out[count++] = a + (b - a) * (ha / (ha - hb));
  }
  return count;
}

double contourFormFactor(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> clippedPolygon) {
  const std::size_t count = clippedPolygon.size();
  if (count < 3) return 0;
  double sum = 0;
  Vec3 first = normalize(clippedPolygon[0] - x);
  Vec3 a = first;
  for (std::size_t k = 0; k < count; ++k) {
    Vec3 b = k + 1 < count ? normalize(clippedPolygon[k + 1] - x) : first;
    Vec3 c = cross(a, b);
    double sinTheta = length(c);
    if (sinTheta > 1e-15) sum += std::atan2(sinTheta, dot(a, b)) * dot(c, xNormal) / sinTheta;  // else seen end-on
    a = b;
  }
  // The winding seen from x fixes the sign; the clipped polygon lies wholly above the tangent
  // plane and is seen from its front, so the magnitude is the form factor.
  return std::fabs(sum) / (2 * kPi);
}

double pointToPolygonFormFactor(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon,
                                const Vec3& polygonNormal) {
  if (polygon.size() < 3) return 0;
  // Only the polygon's front side emits: x must lie in front of its plane by more than 1e-10 of
  // the sizes involved, far above what the rounding of coordinates (1e-15 of them) can put it
  // there and far below any gap a scene models. A point in the polygon's own plane (on a two-sided face's back twin, on a duplicate of the
  // face, on a face lying on another) sees none of it; counted as in front, the contour integral
  // from a point inside the polygon is the whole hemisphere, F = 1.
  const double height = dot(x - polygon[0], polygonNormal);
  if (!(height > 1e-10 * (length(polygon[1] - polygon[0]) + length(x - polygon[0])))) return 0;
  // Patches are triangles, so the common case stays on the stack.
  constexpr std::size_t kStackVertices = 8;
  Vec3 stackBuffer[kStackVertices];
  std::vector<Vec3> heapBuffer;
  Vec3* clipped = stackBuffer;
  if (polygon.size() + 1 > kStackVertices) {
    heapBuffer.resize(polygon.size() + 1);
    clipped = heapBuffer.data();
  }
  std::size_t count = clipAbovePlane(polygon, x, xNormal, clipped);
  return contourFormFactor(x, xNormal, std::span<const Vec3>(clipped, count));
}

Vec3 incenter(const std::array<Vec3, 3>& triangle) {
  const auto& [a, b, c] = triangle;
  double la = length(b - c), lb = length(c - a), lc = length(a - b);
  return (a * la + b * lb + c * lc) / (la + lb + lc);
}

namespace {
// A cell is split while its bounding radius exceeds this share of its distance from x, down to
// kCornerDepth levels (cells of 2⁻¹² of the polygon's side).
constexpr double kCornerCellRatio = 0.5;
constexpr int kCornerDepth = 12;
}  // namespace

// φ is bilinear in the cell parameters, so a cell's centre and edge midpoints have the means of
// its corners' φ.
std::array<double, 4> cornerFormFactors(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon, const Vec3& polygonNormal) {
  using Weights = std::array<double, 4>;
  struct Cell {
    std::array<Weights, 4> corner;
    int depth;
  };
  const std::size_t m = polygon.size();
  LAMBERT_CHECK(m == 3 || m == 4);
  const auto mix = [](const Weights& a, const Weights& b) {
    return Weights{(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5, (a[2] + b[2]) * 0.5, (a[3] + b[3]) * 0.5};
  };
  std::array<double, 4> out{0, 0, 0, 0};
  thread_local std::vector<Cell> stack;
  stack.clear();
  Cell whole{{}, 0};
  for (std::size_t c = 0; c < m; ++c) whole.corner[c][c] = 1;
  stack.push_back(whole);
  while (!stack.empty()) {
    const Cell cell = stack.back();
    stack.pop_back();
    std::array<Vec3, 4> point{};
    Weights centre{0, 0, 0, 0};
    for (std::size_t k = 0; k < m; ++k) {
      for (std::size_t c = 0; c < m; ++c) {
        point[k] += polygon[c] * cell.corner[k][c];
        centre[c] += cell.corner[k][c] / static_cast<double>(m);
      }
    }
    Vec3 middle{};
    for (std::size_t c = 0; c < m; ++c) middle += polygon[c] * centre[c];
    double radius = 0;
    for (std::size_t k = 0; k < m; ++k) radius = std::fmax(radius, length(point[k] - middle));
    if (cell.depth < kCornerDepth && radius > kCornerCellRatio * length(middle - x)) {
      const auto& w = cell.corner;
      const int d = cell.depth + 1;
      if (m == 3) {
        const Weights a = mix(w[0], w[1]), b = mix(w[1], w[2]), c = mix(w[2], w[0]);
        stack.push_back({{w[0], a, c, {}}, d});
        stack.push_back({{a, w[1], b, {}}, d});
        stack.push_back({{c, b, w[2], {}}, d});
        stack.push_back({{a, b, c, {}}, d});
      } else {
        const Weights a = mix(w[0], w[1]), b = mix(w[1], w[2]), c = mix(w[2], w[3]), e = mix(w[3], w[0]), o = mix(a, c);
        stack.push_back({{w[0], a, o, e}, d});
        stack.push_back({{a, w[1], b, o}, d});
        stack.push_back({{o, b, w[2], c}, d});
        stack.push_back({{e, o, c, w[3]}, d});
      }
      continue;
    }
    const double factor = pointToPolygonFormFactor(x, xNormal, std::span<const Vec3>(point.data(), m), polygonNormal);
    if (!(factor > 0)) continue;
    for (std::size_t c = 0; c < m; ++c) out[c] += factor * centre[c];
  }
  return out;
}


}  // namespace lambert
