#pragma once
// From linear radiance to displayable 8-bit sRGB.
#include <cstdint>
#include <vector>

#include "lambert/core/image.h"
#include "lambert/core/srgb.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Scales radiance by 2^exposureStops (so radiance 1 W/(m²·sr) is white at 0 stops), clamps to
// [0, 1], applies the sRGB transfer function and rounds to 8 bits: RGB interleaved, row-major,
// top row first. Negative or NaN values become black.
std::vector<std::uint8_t> toSrgb8(const Image& image, double exposureStops);

// Automatic exposure (Reinhard, Stark, Shirley and Ferwerda 2002, "Photographic tone reproduction
// for digital images", eq. 1): the exposure that maps the image's log-average luminance
// L̄ = exp(mean log(δ + L)) to the middle-grey key 0.18, in stops: log2(0.18 / L̄). Pixels that see
// nothing (luminance exactly 0: the background) are left out, so an object before the black
// background is exposed for itself; δ = 10⁻⁴ × their mean luminance keeps near-black pixels from
// dominating, and makes the result scale exactly with the image (radiance × 2^k gives −k stops).
// An image with no lit pixel gives 0.
double autoExposureStops(const Image& image);

// The exposure a scene's images are taken at: the scene's own (Scene::exposureStops, the
// calibrated built-in scenes' 0) where it sets one, else autoExposureStops of the image.
double sceneExposureStops(const Scene& scene, const Image& image);

}  // namespace lambert
