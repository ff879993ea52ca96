#pragma once
// Points on a convex polygon drawn uniformly in the solid angle it subtends at a point x
// (Arvo, "Stratified Sampling of Spherical Triangles", SIGGRAPH 1995; the triangle's solid
// angle by Van Oosterom & Strackee, "The Solid Angle of a Plane Triangle", 1983).
//
// Why not uniform in area: the share of a polygon that x sees unoccluded, weighted as light
// arrives (by cos θ_x dω), is what a link's visibility must be. Points uniform in area weigh a
// large source's far, often hidden, part as much as its near, visible one: a desk leg's side saw
// the floor under its desk, all eight rays went to the far floor behind the other legs, and the
// leg got none of the floor's light (a furnished closed furnace's furniture came out 3.8% dark).
// Uniform in solid angle, the weight left is cos θ_x, bounded.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>

#include "lambert/core/rgb.h"  // kPi
#include "lambert/core/vec3.h"

namespace lambert {

// The solid angle (sr) of the triangle a, b, c seen from the origin (the corners as vectors from
// it): tan(Ω/2) = |a·(b×c)| / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|).
inline double triangleSolidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = length(a), lb = length(b), lc = length(c);
  const double numerator = std::fabs(dot(a, cross(b, c)));
  const double denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2 * std::atan2(numerator, denominator);
}

// A unit direction uniform in the spherical triangle of unit vectors A, B, C, from (u, v) ∈ [0,1)²
// (Arvo 1995, the stratification of the square kept). `area` is the triangle's solid angle.
inline Vec3 sampleSphericalTriangle(const Vec3& A, const Vec3& B, const Vec3& C, double area, double u, double v) {
  // The interior angles from the planes' normals (the angle at A lies between planes OAB and OAC).
  const Vec3 nAB = normalize(cross(A, B)), nCA = normalize(cross(C, A));
  const double alpha = std::acos(std::clamp(-dot(nAB, nCA), -1.0, 1.0));
  // The sub-triangle A B Ĉ of area u · area: Ĉ on the arc from A to C.
  const double areaHat = u * area;
  const double s = std::sin(areaHat - alpha), t = std::cos(areaHat - alpha);
  const double cosAlpha = std::cos(alpha), sinAlpha = std::sin(alpha);
  const double uu = t - cosAlpha, vv = s + sinAlpha * dot(A, B);
  const double denominator = (vv * s + uu * t) * sinAlpha;
  const double q = denominator != 0 ? std::clamp(((vv * t - uu * s) * cosAlpha - vv) / denominator, -1.0, 1.0) : 1.0;
  const Vec3 alongAC = C - A * dot(C, A);
  const double alongACLength = length(alongAC);
  const Vec3 cHat = alongACLength > 0 ? A * q + alongAC * (std::sqrt(std::fmax(0.0, 1 - q * q)) / alongACLength) : A;
  // Then a point on the arc from B to Ĉ, uniform in the area it sweeps.
  const double z = 1 - v * (1 - dot(cHat, B));
  const Vec3 alongBC = cHat - B * dot(cHat, B);
  const double alongBCLength = length(alongBC);
  return alongBCLength > 0 ? normalize(B * z + alongBC * (std::sqrt(std::fmax(0.0, 1 - z * z)) / alongBCLength)) : B;
}

struct SolidAngleSample {
  Vec3 point;        // on the polygon
  Vec3 direction;    // unit, from x to point
  double solidAngle; // of the whole polygon seen from x, sr
};

// A point on a convex polygon of 3 to 5 corners, uniform in the solid angle it subtends at x:
// u picks a fan triangle in proportion to its solid angle and is reused, rescaled, within it.
// None where x lies in the polygon's plane (it subtends nothing).
inline std::optional<SolidAngleSample> sampleBySolidAngle(const Vec3& x, std::span<const Vec3> polygon, double u, double v) {
  const std::size_t fans = std::min<std::size_t>(polygon.size() - 2, 4);
  std::array<double, 4> angles{};
  double total = 0;
  for (std::size_t k = 0; k < fans; ++k)
    total += angles[k] = triangleSolidAngle(polygon[0] - x, polygon[k + 1] - x, polygon[k + 2] - x);
  if (!(total > 1e-12)) return std::nullopt;
  const double pick = u * total;
  std::size_t chosen = fans - 1;
  double start = 0;
  for (std::size_t k = 0; k < fans; ++k) {
    if (pick < start + angles[k] || k + 1 == fans) {
      chosen = k;
      break;
    }
    start += angles[k];
  }
  if (!(angles[chosen] > 0)) return std::nullopt;
  const double within = std::clamp((pick - start) / angles[chosen], 0.0, std::nextafter(1.0, 0.0));
  const Vec3 a = polygon[0], b = polygon[chosen + 1], c = polygon[chosen + 2];
  const Vec3 direction = sampleSphericalTriangle(normalize(a - x), normalize(b - x), normalize(c - x), angles[chosen], within, v);
  // Where the direction meets the polygon's plane.
  const Vec3 normal = cross(b - a, c - a);
  const double along = dot(direction, normal);
  if (along == 0) return std::nullopt;
  const double distance = dot(a - x, normal) / along;
  if (!(distance > 0)) return std::nullopt;
  return SolidAngleSample{x + direction * distance, direction, total};
}

}  // namespace lambert
