#pragma once
// An image of linear radiance, as the rasterizer and the reference path tracer produce it.
#include <cstddef>
#include <vector>

#include "lambert/core/rgb.h"

namespace lambert {

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // linear radiance L in W/(m²·sr), row-major, top row first

  Rgb& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const Rgb& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

}  // namespace lambert
