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

double autoExposureStops(const Image& image) {
  constexpr double kKey = 0.18;
  double sum = 0;
  std::size_t lit = 0;
  for (const Rgb& pixel : image.pixels) {
    const double l = pixel.luminance();
    if (l > 0 && std::isfinite(l)) sum += l, ++lit;
  }
  if (lit == 0) return 0;
  const double delta = 1e-4 * sum / static_cast<double>(lit);
  double logSum = 0;
  for (const Rgb& pixel : image.pixels) {
    const double l = pixel.luminance();
    if (l > 0 && std::isfinite(l)) logSum += std::log(delta + l);
  }
  const double logAverage = std::exp(logSum / static_cast<double>(lit));
  return std::log2(kKey / logAverage);
}

double sceneExposureStops(const Scene& scene, const Image& image) {
  return scene.exposureStops ? *scene.exposureStops : autoExposureStops(image);
}

}  // namespace lambert
