#include "lambert/core/cie_colour.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace lambert {
namespace {

// g(λ; μ, σ1, σ2): a Gaussian with a different width on each side of its peak (Wyman et al.).
double lobe(double lambdaNm, double mu, double sigmaBelow, double sigmaAbove) {
  const double t = (lambdaNm - mu) / (lambdaNm < mu ? sigmaBelow : sigmaAbove);
  return std::exp(-0.5 * t * t);
}

// CIE 1931 2° colour matching functions, the multi-lobe fit of Wyman, Sloan & Shirley 2013.
Xyz colourMatching(double lambdaNm) {
  return {1.056 * lobe(lambdaNm, 599.8, 37.9, 31.0) + 0.362 * lobe(lambdaNm, 442.0, 16.0, 26.7) -
              0.065 * lobe(lambdaNm, 501.1, 20.4, 26.2),
          0.821 * lobe(lambdaNm, 568.8, 46.9, 40.5) + 0.286 * lobe(lambdaNm, 530.9, 16.3, 31.1),
          1.217 * lobe(lambdaNm, 437.0, 11.8, 36.0) + 0.681 * lobe(lambdaNm, 459.0, 26.0, 13.8)};
}

Rgb xyzToRec709(const Xyz& c) {
  return {3.2404542 * c.x - 1.5371385 * c.y - 0.4985314 * c.z,
          -0.9692660 * c.x + 1.8760108 * c.y + 0.0415560 * c.z,
          0.0556434 * c.x - 0.2040259 * c.y + 1.0572252 * c.z};
}

// The boundary of the chromaticities real spectra have: the convex hull of the CIE 1931 spectral
// locus (its chromaticities every 10 nm from 380 to 700 nm, from the CIE's table; beyond 700 nm
// it stays at the last point), closed by the purple line. Tabulated rather than taken from the
// colour matching functions' fit, whose far tails are too inexact for chromaticity.
// Counter-clockwise, by Andrew's monotone chain.
const std::vector<std::pair<double, double>>& realChromaticities() {
  static const std::vector<std::pair<double, double>> hull = [] {
    std::vector<std::pair<double, double>> points = {
        {0.1741, 0.0050}, {0.1738, 0.0049}, {0.1733, 0.0048}, {0.1726, 0.0048}, {0.1714, 0.0051}, {0.1689, 0.0069}, {0.1644, 0.0109},
        {0.1566, 0.0177}, {0.1440, 0.0297}, {0.1241, 0.0578}, {0.0913, 0.1327}, {0.0454, 0.2950}, {0.0082, 0.5384}, {0.0139, 0.7502},
        {0.0743, 0.8338}, {0.1547, 0.8059}, {0.2296, 0.7543}, {0.3016, 0.6923}, {0.3731, 0.6245}, {0.4441, 0.5547}, {0.5125, 0.4866},
        {0.5752, 0.4242}, {0.6270, 0.3725}, {0.6658, 0.3340}, {0.6915, 0.3083}, {0.7079, 0.2920}, {0.7190, 0.2809}, {0.7260, 0.2740},
        {0.7300, 0.2700}, {0.7320, 0.2680}, {0.7334, 0.2666}, {0.7344, 0.2656}, {0.7347, 0.2653}};
    std::sort(points.begin(), points.end());
    auto cross = [](const auto& o, const auto& a, const auto& b) {
      return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first);
    };
    std::vector<std::pair<double, double>> h(2 * points.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      while (k >= 2 && cross(h[k - 2], h[k - 1], points[i]) <= 0) --k;
      h[k++] = points[i];
    }
    for (std::size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
      while (k >= t && cross(h[k - 2], h[k - 1], points[i]) <= 0) --k;
      h[k++] = points[i];
    }
    h.resize(k - 1);
    return h;
  }();
  return hull;
}

// Where the segment from the equal-energy white (1/3, 1/3), inside the hull, to (x, y), outside
// it, leaves the hull: the most saturated real chromaticity of (x, y)'s hue.
std::pair<double, double> ontoRealChromaticities(double x, double y) {
  const std::vector<std::pair<double, double>>& hull = realChromaticities();
  const double ex = 1.0 / 3, ey = 1.0 / 3, dx = x - ex, dy = y - ey;
  double nearest = 1;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const auto& a = hull[i];
    const auto& b = hull[(i + 1) % hull.size()];
    const double mx = b.first - a.first, my = b.second - a.second;
    const double det = dx * -my - dy * -mx;
    if (det == 0) continue;
    const double rx = a.first - ex, ry = a.second - ey;
    const double t = (rx * -my - ry * -mx) / det, s = (dx * ry - dy * rx) / det;
    if (t > 0 && s >= 0 && s <= 1) nearest = std::min(nearest, t);
  }
  nearest *= 1 - 1e-9;  // just inside
  return {ex + nearest * dx, ey + nearest * dy};
}

}  // namespace

Xyz integrateSpectrum(const std::function<double(double)>& spectrum) {
  Xyz sum{0, 0, 0};
  for (double lambda = 360; lambda <= 830; lambda += 1) {
    const double s = spectrum(lambda);
    const Xyz cmf = colourMatching(lambda);
    sum.x += s * cmf.x;
    sum.y += s * cmf.y;
    sum.z += s * cmf.z;
  }
  return sum;
}

double planck(double lambdaNm, double kelvin) {
  constexpr double kC2 = 1.4387769e7;  // second radiation constant h·c/k in nm·K
  const double l = lambdaNm;
  return 1 / (l * l * l * l * l * (std::exp(kC2 / (l * kelvin)) - 1));
}

Xyz realColour(const Xyz& c, std::string& repair) {
  repair.clear();
  if (c.x >= 0 && c.y > 0 && c.z >= 0) return Xyz{c.x / c.y, 1, c.z / c.y};
  auto format = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return std::string(text);
  };
  const double x = std::fmax(0.0, c.x), y = std::fmax(0.0, c.y), z = std::fmax(0.0, c.z);
  const std::string xyz = "CIE XYZ ∝ (" + format(c.x) + ", " + format(c.y) + ", " + format(c.z) + ")";
  if (x + y + z == 0) {
    repair = "no real colour (" + xyz + ", nothing positive): read as white";
    return Xyz{1, 1, 1};
  }
  if (y > 0) {
    repair = "no real colour (" + xyz + "): negative components clipped to 0, giving chromaticity (" + format(x / (x + y + z)) + ", " +
             format(y / (x + y + z)) + ")";
    return Xyz{x / y, 1, z / y};
  }
  const auto [cx, cy] = ontoRealChromaticities(x / (x + z), 0);
  repair = "no real colour (" + xyz + ", no luminance): read as chromaticity (" + format(cx) + ", " + format(cy) +
           "), the most saturated real colour of its hue (toward white onto the spectral locus)";
  return Xyz{cx / cy, 1, (1 - cx - cy) / cy};
}

Rgb chromaticityToRgb(const Xyz& c) {
  const Rgb white = xyzToRec709(Xyz{});
  Rgb rgb = xyzToRec709(c);
  for (int k = 0; k < 3; ++k) rgb[k] = std::fmax(0.0, rgb[k] / white[k]);
  const double luminance = rgb.luminance();
  return luminance > 0 ? rgb / luminance : Rgb::gray(1);
}

}  // namespace lambert
