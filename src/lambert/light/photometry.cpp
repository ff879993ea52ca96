#include "lambert/light/photometry.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/rgb.h"

namespace lambert {
namespace {

// Steffen's slope at the middle of three points (M. Steffen, "A simple method for monotonic
// interpolation in one dimension", Astron. Astrophys. 239, 1990, eqs. 11 and 13): zero at a local
// extremum, else the parabola's slope limited to twice the smaller secant, so that the cubic
// Hermite interpolant never overshoots its data (and so never goes negative between positive
// candela values).
double steffenSlope(double xa, double ya, double xb, double yb, double xc, double yc) {
  const double ha = xb - xa, hb = xc - xb;
  const double sa = (yb - ya) / ha, sb = (yc - yb) / hb;
  if (!(sa * sb > 0)) return 0;
  const double p = (sa * hb + sb * ha) / (ha + hb);
  const double limited = std::min({std::fabs(sa), std::fabs(sb), 0.5 * std::fabs(p)});
  return (sa > 0 ? 2 : -2) * limited;
}

// The cubic Hermite interpolant on [x1, x2] with end slopes d1, d2.
double hermite(double x, double x1, double y1, double d1, double x2, double y2, double d2) {
  const double h = x2 - x1, t = (x - x1) / h, t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * y1 + (t3 - 2 * t2 + t) * h * d1 + (-2 * t3 + 3 * t2) * y2 + (t3 - t2) * h * d2;
}

// A monotone cubic through (x0..x3, y0..y3) evaluated on [x1, x2]; a missing outer point
// (hasLeft/hasRight false) gives its end the interval's secant, which keeps it monotone.
double monotoneCubic(double x, bool hasLeft, double x0, double y0, double x1, double y1, double x2, double y2, bool hasRight,
                     double x3, double y3) {
  const double secant = (y2 - y1) / (x2 - x1);
  const double d1 = hasLeft ? steffenSlope(x0, y0, x1, y1, x2, y2) : secant;
  const double d2 = hasRight ? steffenSlope(x1, y1, x2, y2, x3, y3) : secant;
  return hermite(x, x1, y1, d1, x2, y2, d2);
}

}  // namespace

double TiltTable::factor(double tiltDegrees) const {
  if (degrees.empty()) return 1;
  if (tiltDegrees <= degrees.front()) return factors.front();
  if (tiltDegrees >= degrees.back()) return factors.back();
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(degrees.begin(), degrees.end(), tiltDegrees) - degrees.begin());
  const double t = (tiltDegrees - degrees[k - 1]) / (degrees[k] - degrees[k - 1]);
  return factors[k - 1] + t * (factors[k] - factors[k - 1]);
}

double Photometry::rowValue(std::size_t row, double c) const {
  const std::size_t nV = verticalDegrees.size(), nC = horizontalDegrees.size();
  if (nC == 1) return candelaGrid[row];
  c = std::fmod(c, 360.0);
  if (c < 0) c += 360;
  const auto n = static_cast<long>(nC);
  // Plane k of the periodic sequence: horizontalDegrees[k mod n] + 360·floor(k / n).
  auto wrap = [&](long k) { return static_cast<std::size_t>(((k % n) + n) % n); };
  auto angle = [&](long k) { return horizontalDegrees[wrap(k)] + 360.0 * static_cast<double>(k >= 0 ? k / n : -((-k + n - 1) / n)); };
  auto value = [&](long k) { return candelaGrid[wrap(k) * nV + row]; };
  long j = static_cast<long>(std::upper_bound(horizontalDegrees.begin(), horizontalDegrees.end(), c) - horizontalDegrees.begin()) - 1;
  return std::fmax(0.0, monotoneCubic(c, true, angle(j - 1), value(j - 1), angle(j), value(j), angle(j + 1), value(j + 1), true,
                                      angle(j + 2), value(j + 2)));
}

double Photometry::candela(double cDegrees, double gammaDegrees) const {
  const std::size_t nV = verticalDegrees.size();
  if (nV < 2 || horizontalDegrees.empty() || !std::isfinite(cDegrees) || !std::isfinite(gammaDegrees)) return 0;
  const std::vector<double>& v = verticalDegrees;
  if (gammaDegrees < v.front() - 1e-9 || gammaDegrees > v.back() + 1e-9) return 0;
  std::size_t k = static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), gammaDegrees) - v.begin());
  k = std::min(std::max<std::size_t>(k, 1), nV - 1) - 1;
  // Beyond a pole the neighbour lies in the opposite half plane, C + 180°: I(C, −γ) = I(C + 180°, γ).
  bool hasLeft = true, hasRight = true;
  double x0 = 0, y0 = 0, x3 = 0, y3 = 0;
  if (k >= 1) {
    x0 = v[k - 1], y0 = rowValue(k - 1, cDegrees);
  } else if (v[0] == 0) {
    x0 = -v[1], y0 = rowValue(1, cDegrees + 180);
  } else {
    hasLeft = false;
  }
  if (k + 2 < nV) {
    x3 = v[k + 2], y3 = rowValue(k + 2, cDegrees);
  } else if (v[nV - 1] == 180) {
    x3 = 360 - v[nV - 2], y3 = rowValue(nV - 2, cDegrees + 180);
  } else {
    hasRight = false;
  }
  const double value = monotoneCubic(gammaDegrees, hasLeft, x0, y0, v[k], rowValue(k, cDegrees), v[k + 1], rowValue(k + 1, cDegrees),
                                     hasRight, x3, y3);
  return std::fmax(0.0, value);
}

double Photometry::maxCandela() const {
  double m = 0;
  for (double c : candelaGrid) m = std::fmax(m, c);
  return m;
}

void Photometry::integrateFlux() {
  // Φ = ∫₀^{2π} ∫₀^{π} I(C, γ) sin γ dγ dC. Each 0.5° band of γ is weighted by its exact
  // ∫ sin γ dγ = cos γa − cos γb, so the only error is the interpolant's variation in the cell.
  constexpr int kBands = 360, kPlanes = 180;
  const bool rotational = horizontalDegrees.size() == 1;
  double sum = 0;
  for (int b = 0; b < kBands; ++b) {
    const double ga = 180.0 * b / kBands, gb = 180.0 * (b + 1) / kBands, gm = 0.5 * (ga + gb);
    if (verticalDegrees.empty() || gm < verticalDegrees.front() || gm > verticalDegrees.back()) continue;
    const double weight = std::cos(ga * kPi / 180) - std::cos(gb * kPi / 180);
    if (rotational) {
      sum += candela(0, gm) * weight * 2 * kPi;
      continue;
    }
    for (int p = 0; p < kPlanes; ++p) sum += candela(360.0 * (p + 0.5) / kPlanes, gm) * weight * (2 * kPi / kPlanes);
  }
  flux_ = sum;
}

}  // namespace lambert
