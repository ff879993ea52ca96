#include "lambert/render/tonemap.h"

#include <algorithm>
#include <cmath>

namespace lambert {

std::vector<std::uint8_t> toSrgb8(const Image& image, double exposureStops) {
  const double scale = std::exp2(exposureStops);
  std::vector<std::uint8_t> out;
  out.reserve(image.pixels.size() * 3);
  for (const Rgb& pixel : image.pixels) {
    for (int c = 0; c < 3; ++c) {
      double v = pixel[c] * scale;
      // Written so NaN (which fails every comparison) lands on 0.
      v = v > 0 ? std::min(v, 1.0) : 0.0;
      out.push_back(static_cast<std::uint8_t>(std::lround(srgbEncode(v) * 255.0)));
    }
  }
  return out;
}

}  // namespace lambert
