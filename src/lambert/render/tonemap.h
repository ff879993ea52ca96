#pragma once
// From linear radiance to displayable 8-bit sRGB.
#include <cstdint>
#include <vector>

#include "lambert/core/image.h"
#include "lambert/core/srgb.h"

namespace lambert {

// Scales radiance by 2^exposureStops (so radiance 1 W/(m²·sr) is white at 0 stops), clamps to
// [0, 1], applies the sRGB transfer function and rounds to 8 bits: RGB interleaved, row-major,
// top row first. Negative or NaN values become black.
std::vector<std::uint8_t> toSrgb8(const Image& image, double exposureStops);

}  // namespace lambert
