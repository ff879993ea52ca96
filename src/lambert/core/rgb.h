#pragma once
// Linear RGB triple. What it holds (radiosity B in W/m², radiance L in W/(m²·sr), albedo ρ,
// dimensionless) is said by the name of the variable, never by the type.
#include <algorithm>
#include <cmath>

namespace lambert {

struct Rgb {
  double r = 0, g = 0, b = 0;

  constexpr Rgb() = default;
  constexpr Rgb(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}
  static constexpr Rgb gray(double v) { return {v, v, v}; }

  constexpr double operator[](int c) const { return c == 0 ? r : c == 1 ? g : b; }
  constexpr double& operator[](int c) { return c == 0 ? r : c == 1 ? g : b; }
  constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
  constexpr Rgb& operator+=(const Rgb& o) { r += o.r; g += o.g; b += o.b; return *this; }
  constexpr Rgb& operator-=(const Rgb& o) { r -= o.r; g -= o.g; b -= o.b; return *this; }
  constexpr Rgb& operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
  constexpr bool operator==(const Rgb&) const = default;

  constexpr double sum() const { return r + g + b; }
  constexpr double maxComponent() const { return std::max({r, g, b}); }
  // Rec. 709 luminance weights, for choosing and reporting, never for transport.
  constexpr double luminance() const { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }
};

constexpr Rgb operator*(double s, const Rgb& c) { return c * s; }

// Each channel clamped at zero from below (a gather's sum of weighted terms can dip under it).
inline Rgb nonNegative(const Rgb& e) { return {std::fmax(0.0, e.r), std::fmax(0.0, e.g), std::fmax(0.0, e.b)}; }

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace lambert
