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

namespace {

// Only a polygon's front side emits: x must lie in front of its plane by more than 1e-10 of the
// sizes involved, far above what the rounding of coordinates (1e-15 of them) can put it there and
// far below any gap a scene models. A point in the polygon's own plane (on a two-sided face's back
// twin, on a duplicate of the face, on a face lying on another) sees none of it; counted as in
// front, the contour integral from a point inside the polygon is the whole hemisphere, F = 1.
bool inFrontOf(const Vec3& x, std::span<const Vec3> polygon, const Vec3& polygonNormal) {
  const double height = dot(x - polygon[0], polygonNormal);
  return height > 1e-10 * (length(polygon[1] - polygon[0]) + length(x - polygon[0]));
}

}  // namespace

double pointToPolygonFormFactor(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon,
                                const Vec3& polygonNormal) {
  if (polygon.size() < 3 || !inFrontOf(x, polygon, polygonNormal)) return 0;
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

double pointToPolygonFormFactorFast(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon, const Vec3& polygonNormal) {
  const std::size_t m = polygon.size();
  if (m == 3 || m == 4) {
    Vec3 centre;
    for (const Vec3& p : polygon) centre += p;
    centre = centre / static_cast<double>(m);
    double radius2 = 0;
    bool above = true;
    for (const Vec3& p : polygon) {
      radius2 = std::fmax(radius2, lengthSquared(p - centre));
      above = above && dot(p - x, xNormal) > 0;
    }
    const double distance2 = lengthSquared(centre - x);
    if (above && dot(x - centre, polygonNormal) > 0 && radius2 < kQuadratureRatio * kQuadratureRatio * distance2) {
      // pointToPointKernel is zero where either side faces away: x in front and every point above
      // its plane, it never is here.
      if (m == 4) {
        constexpr double kLow = 0.5 - 0.5 / 1.7320508075688772, kHigh = 0.5 + 0.5 / 1.7320508075688772;
        double sum = 0;
        for (const double u : {kLow, kHigh})
          for (const double v : {kLow, kHigh}) {
            const Vec3 y = polygon[0] * ((1 - u) * (1 - v)) + polygon[1] * (u * (1 - v)) + polygon[2] * (u * v) + polygon[3] * ((1 - u) * v);
            const Vec3 du = (polygon[1] - polygon[0]) * (1 - v) + (polygon[2] - polygon[3]) * v;
            const Vec3 dv = (polygon[3] - polygon[0]) * (1 - u) + (polygon[2] - polygon[1]) * u;
            sum += pointToPointKernel(x, xNormal, y, polygonNormal) * length(cross(du, dv));
          }
        return 0.25 * sum;
      }
      const double area = 0.5 * length(cross(polygon[1] - polygon[0], polygon[2] - polygon[0]));
      double sum = 0;
      for (int k = 0; k < 3; ++k) {
        const Vec3 y = polygon[k] * (2.0 / 3.0) + (polygon[(k + 1) % 3] + polygon[(k + 2) % 3]) * (1.0 / 6.0);
        sum += pointToPointKernel(x, xNormal, y, polygonNormal);
      }
      return sum * area / 3;
    }
  }
  return pointToPolygonFormFactor(x, xNormal, polygon, polygonNormal);
}

Vec3 incenter(const std::array<Vec3, 3>& triangle) {
  const auto& [a, b, c] = triangle;
  double la = length(b - c), lb = length(c - a), lc = length(a - b);
  return (a * la + b * lb + c * lc) / (la + lb + lc);
}

namespace {

// ∫_a^b log1p((d² + t²)/h²)/(d² + t²) dt for 0 ≤ a ≤ b, the one term of the first moment with
// no elementary antiderivative (Chen & Arvo 2000 reach it as Clausen's integral). The integrand
// is even, analytic on the real line and varies on the scale max(t, q), q = √(d² + h²), decaying
// as ln t / t² beyond q: 4-point Gauss–Legendre over intervals growing fourfold from a (or q).
double logMomentIntegral(double d, double h, double a, double b) {
  static constexpr double kNode[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static constexpr double kWeight[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  const double d2 = d * d, h2 = h * h, q = std::sqrt(d2 + h2);
  double sum = 0;
  for (double lo = a; lo < b;) {
    const double hi = std::fmin(b, std::fmax(4 * lo, lo + q));
    const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    for (int i = 0; i < 4; ++i) {
      const double t = mid + half * kNode[i], rho2 = d2 + t * t;
      sum += kWeight[i] * half * (rho2 > 0 ? std::log1p(rho2 / h2) / rho2 : 1 / h2);
    }
    lo = hi;
  }
  return sum;
}

// The same over any ta ≤ tb.
double logMomentIntegralOver(double d, double h, double ta, double tb) {
  if (ta >= 0) return logMomentIntegral(d, h, ta, tb);
  if (tb <= 0) return logMomentIntegral(d, h, -tb, -ta);
  return logMomentIntegral(d, h, 0, -ta) + logMomentIntegral(d, h, 0, tb);
}

// The form factor F and the first moment ∫ y k(x, y) dA_y (as F times the kernel-weighted
// centroid ȳ) of a planar convex polygon already clipped to the hemisphere above x, by boundary
// integrals (Green's theorem in the polygon's plane, as Chen & Arvo 2000 convert the surface
// integral). With o the foot of x on the plane, h > 0 its height, s = y − o and ρ = |s|, the
// kernel is k = (n∥·s − h c) h / (π (h² + ρ²)²), c = n_x·n_p, n∥ = n_x − c n_p; so
//   F = h/π (n∥·J1 − h c J0),  ∫ s k dA = h/π (J2 n∥ − h c J1),
// with J0 = ∫ dA/r⁴, J1 = ∫ s dA/r⁴, J2 n∥ = ∫ s (s·n∥) dA/r⁴ (r² = h² + ρ²), each a sum over
// the edges (outward normal n̂, distance d = s·n̂, tangent ê, t = s·ê, q² = h² + d²):
//   J0 = Σ d/(2h²) ∫dt/(q² + t²),  J1 = −½ Σ n̂ ∫dt/(q² + t²),
//   J2 n∥ = −½ Σ n̂ (d (n̂·n∥) ∫dt/(q² + t²) + (ê·n∥) ∫t dt/(q² + t²)) + ¼ n∥ Σ d ∫ln(1 + ρ²/h²)/ρ² dt.
struct PolygonMoment {
  double factor = 0;
  Vec3 centroid;  // ȳ, where factor > 0
};

PolygonMoment polygonMoment(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> clipped, const Vec3& polygonNormal) {
  const std::size_t m = clipped.size();
  if (m < 3) return {};
  const double h = dot(x - clipped[0], polygonNormal);
  const Vec3 o = x - polygonNormal * h;
  const double c = dot(xNormal, polygonNormal);
  const Vec3 along = xNormal - polygonNormal * c;  // n∥
  // The winding about polygonNormal fixes which side of each edge is outside.
  Vec3 area;
  for (std::size_t k = 0; k < m; ++k) area += cross(clipped[k] - o, clipped[(k + 1) % m] - o);
  const double winding = dot(area, polygonNormal) >= 0 ? 1.0 : -1.0;
  double j0 = 0, logSum = 0;
  Vec3 j1, j2;
  for (std::size_t k = 0; k < m; ++k) {
    const Vec3 a = clipped[k] - o, b = clipped[(k + 1) % m] - o;
    const double edgeLength = length(b - a);
    if (!(edgeLength > 0)) continue;
    const Vec3 tangent = (b - a) / edgeLength;
    const Vec3 outward = cross(tangent, polygonNormal) * winding;
    const double d = dot(a, outward), ta = dot(a, tangent), tb = dot(b, tangent);
    const double q2 = h * h + d * d, q = std::sqrt(q2);
    const double arc = (std::atan(tb / q) - std::atan(ta / q)) / q;  // ∫ dt/(q² + t²)
    const double logRatio = 0.5 * std::log((q2 + tb * tb) / (q2 + ta * ta));  // ∫ t dt/(q² + t²)
    const double logPart = logMomentIntegralOver(d, h, ta, tb);
    j0 += d * arc;
    j1 -= outward * (0.5 * arc);
    j2 -= outward * (0.5 * (d * dot(outward, along) * arc + dot(tangent, along) * logRatio));
    logSum += d * logPart;
  }
  j0 /= 2 * h * h;
  j2 += along * (0.25 * logSum);
  PolygonMoment moment;
  moment.factor = h / kPi * (dot(along, j1) - h * c * j0);
  if (!(moment.factor > 0)) return {};
  moment.centroid = o + (j2 - j1 * (h * c)) * (h / kPi / moment.factor);
  return moment;
}

}  // namespace

// The corners' weights are affine in y over each fan triangle (0, k, k + 1), the radiosity drawn
// linear over each (as the rasterizer and the glb draw a face), so ∫ φ_c k dA = F_T φ_c(ȳ_T) per
// triangle T: its factor and its kernel-weighted centroid give every weight exactly.
std::array<double, 4> cornerFormFactors(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon, const Vec3& polygonNormal) {
  const std::size_t m = polygon.size();
  LAMBERT_CHECK(m == 3 || m == 4);
  std::array<double, 4> out{0, 0, 0, 0};
  if (!inFrontOf(x, polygon, polygonNormal)) return out;
  for (std::size_t k = 1; k + 1 < m; ++k) {
    const std::array<Vec3, 3> triangle{polygon[0], polygon[k], polygon[k + 1]};
    Vec3 clipped[4];
    const std::size_t count = clipAbovePlane(triangle, x, xNormal, clipped);
    const PolygonMoment moment = polygonMoment(x, xNormal, std::span<const Vec3>(clipped, count), polygonNormal);
    if (!(moment.factor > 0)) continue;
    // ȳ's barycentric coordinates in the triangle (inside it: a weighted mean of its points).
    const Vec3 n = cross(triangle[1] - triangle[0], triangle[2] - triangle[0]);
    const double whole = dot(n, n);
    const double w1 = dot(cross(moment.centroid - triangle[0], triangle[2] - triangle[0]), n) / whole;
    const double w2 = dot(cross(triangle[1] - triangle[0], moment.centroid - triangle[0]), n) / whole;
    out[0] += moment.factor * (1 - w1 - w2);
    out[k] += moment.factor * w1;
    out[k + 1] += moment.factor * w2;
  }
  return out;
}

}  // namespace lambert
