#include "lambert/formfactor/kernels.h"

#include <cmath>

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

double pointToPolygonFormFactor(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon,
                                const Vec3& polygonNormal) {
  if (polygon.size() < 3) return 0;
  // Only the polygon's front side emits: x must lie in front of its plane.
  if (dot(x - polygon[0], polygonNormal) <= 0) return 0;

  // Clip to the half-space above x's tangent plane (Sutherland–Hodgman against one plane).
  constexpr std::size_t kMaxVertices = 16;
  Vec3 clipped[kMaxVertices];
  std::size_t count = 0;
  const std::size_t n = polygon.size();
  for (std::size_t k = 0; k < n && count + 2 <= kMaxVertices; ++k) {
    const Vec3& a = polygon[k];
    const Vec3& b = polygon[(k + 1) % n];
    double ha = dot(a - x, xNormal), hb = dot(b - x, xNormal);
    if (ha > 0) clipped[count++] = a;
    if ((ha > 0) != (hb > 0)) clipped[count++] = a + (b - a) * (ha / (ha - hb));
  }
  if (count < 3) return 0;

  Vec3 directions[kMaxVertices];
  for (std::size_t k = 0; k < count; ++k) directions[k] = normalize(clipped[k] - x);
  double sum = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const Vec3& a = directions[k];
    const Vec3& b = directions[(k + 1) % count];
    Vec3 c = cross(a, b);
    double sinTheta = length(c);
    if (sinTheta < 1e-15) continue;  // an edge seen end-on subtends no angle
    double theta = std::atan2(sinTheta, dot(a, b));
    sum += theta * dot(c, xNormal) / sinTheta;
  }
  // The winding seen from x fixes the sign; the clipped polygon lies wholly above the tangent
  // plane and is seen from its front, so the magnitude is the form factor.
  return std::fabs(sum) / (2 * kPi);
}

Vec3 sampleTriangle(const std::array<Vec3, 3>& triangle, double u, double v) {
  double su = std::sqrt(u);
  double b0 = 1 - su, b1 = v * su;
  return triangle[0] * b0 + triangle[1] * b1 + triangle[2] * (1 - b0 - b1);
}

Vec3 incenter(const std::array<Vec3, 3>& triangle) {
  const auto& [a, b, c] = triangle;
  double la = length(b - c), lb = length(c - a), lc = length(a - b);
  return (a * la + b * lb + c * lc) / (la + lb + lc);
}

}  // namespace lambert
