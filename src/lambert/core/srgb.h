#pragma once
// The sRGB transfer function (IEC 61966-2-1), for images and for the 8-bit colours of vertex files.
#include <cmath>

namespace lambert {

// The exact piecewise sRGB OETF, for a linear value in [0, 1].
inline double srgbEncode(double linear) {
  if (linear <= 0.0031308) return 12.92 * linear;
  return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// Its inverse: the linear value of an sRGB-encoded one in [0, 1] (texture texels).
inline double srgbDecode(double encoded) {
  if (encoded <= 0.04045) return encoded / 12.92;
  return std::pow((encoded + 0.055) / 1.055, 2.4);
}

}  // namespace lambert
