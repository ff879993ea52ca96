#pragma once
// Low-discrepancy points in the unit square: the (0,2)-sequence of van der Corput (base 2) and the
// second Sobol' dimension, randomised by an XOR scramble (Kollig & Keller, "Efficient
// Multidimensional Sampling", 2002). Every power-of-two prefix is a (0,m,2)-net: one point in each
// of the N elementary rectangles of every shape, which plain per-axis stratification (N-rooks)
// does not give. The scramble keeps that property and makes estimates unbiased.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include "lambert/core/rgb.h"  // kPi
#include "lambert/core/vec3.h"

namespace lambert {

inline std::uint32_t reverseBits(std::uint32_t v) {
  v = (v << 16) | (v >> 16);
  v = ((v & 0x00ff00ffu) << 8) | ((v & 0xff00ff00u) >> 8);
  v = ((v & 0x0f0f0f0fu) << 4) | ((v & 0xf0f0f0f0u) >> 4);
  v = ((v & 0x33333333u) << 2) | ((v & 0xccccccccu) >> 2);
  return ((v & 0x55555555u) << 1) | ((v & 0xaaaaaaaau) >> 1);
}

inline std::uint32_t vanDerCorput(std::uint32_t index, std::uint32_t scramble) { return reverseBits(index) ^ scramble; }

inline std::uint32_t sobolSecondDimension(std::uint32_t index, std::uint32_t scramble) {
  for (std::uint32_t v = 1u << 31; index; index >>= 1, v ^= v >> 1)
    if (index & 1u) scramble ^= v;
  return scramble;
}

struct UnitSquarePoint {
  double u, v;
};

// A random permutation of sample indices by nested uniform (Owen) scrambling of their bits
// (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020). Two point sets drawn with the same
// index k are correlated even under different XOR scrambles (the radical inverse is linear in
// XOR); drawing the second with shuffledIndex(k) pairs them at random. For k < 2^m the result is
// a permutation of one aligned block of 2^m indices, so power-of-two prefixes stay (0,m,2)-nets.
inline std::uint32_t shuffledIndex(std::uint32_t index, std::uint32_t seed) {
  std::uint32_t x = reverseBits(index);
  x += seed;  // Laine–Karras permutation: each bit depends only on the bits below it
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return reverseBits(x);
}

// Point `index` of the scrambled (0,2)-sequence, in [0,1)².
inline UnitSquarePoint scrambledZeroTwo(std::uint32_t index, std::uint32_t scrambleU, std::uint32_t scrambleV) {
  return {vanDerCorput(index, scrambleU) * 0x1p-32, sobolSecondDimension(index, scrambleV) * 0x1p-32};
}

// Shirley & Chiu's concentric map of (u, v) ∈ [0,1)² onto the unit disc: area-preserving, and it
// keeps cells compact and neighbours neighbours, so a stratified pattern stays stratified. Lifted
// onto the hemisphere (z = √(1 − x² − y²), Malley's method) it gives cosine-weighted directions.
inline UnitSquarePoint concentricDisk(double u, double v) {
  const double a = 2 * u - 1, b = 2 * v - 1;
  double r = 0, phi = 0;
  if (a != 0 || b != 0) {
    if (std::fabs(a) > std::fabs(b)) {
      r = a;
      phi = (kPi / 4) * (b / a);
    } else {
      r = b;
      phi = kPi / 2 - (kPi / 4) * (a / b);
    }
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// Cosine-weighted unit direction about n (pdf cosθ/π): the concentric disc lifted onto the
// hemisphere, which keeps the (0,2)-sequence's stratification.
inline Vec3 cosineDirection(const Vec3& n, UnitSquarePoint s) {
  const auto [dx, dy] = concentricDisk(s.u, s.v);
  const double dz = std::sqrt(std::fmax(0.0, 1 - dx * dx - dy * dy));
  Vec3 t, bt;
  orthonormalBasis(n, t, bt);
  return normalize(t * dx + bt * dy + n * dz);
}

// Maps (u, v) ∈ [0,1)² onto the triangle with equal area (Shirley & Chiu's warp, which keeps the
// square's stratification).
inline Vec3 sampleTriangle(const std::array<Vec3, 3>& triangle, double u, double v) {
  double su = std::sqrt(u);
  double b0 = 1 - su, b1 = v * su;
  return triangle[0] * b0 + triangle[1] * b1 + triangle[2] * (1 - b0 - b1);
}

// Maps (u, v) ∈ [0,1)² onto a convex polygon of 3 to 5 vertices with equal area: u picks a fan
// triangle in proportion to its area and is reused, rescaled, within it.
inline Vec3 sampleConvexPolygon(std::span<const Vec3> polygon, double u, double v) {
  if (polygon.size() == 3) return sampleTriangle({polygon[0], polygon[1], polygon[2]}, u, v);
  double areas[4], total = 0;
  const std::size_t fans = std::min<std::size_t>(polygon.size() - 2, 4);
  for (std::size_t k = 0; k < fans; ++k) total += areas[k] = length(cross(polygon[k + 1] - polygon[0], polygon[k + 2] - polygon[0]));
  double start = 0;
  for (std::size_t k = 0; k < fans; ++k) {
    double share = areas[k] / total;
    if (u < start + share || k + 1 == fans)
      return sampleTriangle({polygon[0], polygon[k + 1], polygon[k + 2]}, std::fmin((u - start) / share, 1.0), v);
    start += share;
  }
  return polygon[0];
}

}  // namespace lambert
