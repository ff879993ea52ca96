#pragma once
// OpenEXR images of linear values (tinyexr): what a compositor or an HDR viewer reads without
// lambert's tone mapping. Three channels B, G, R (EXR's order), ZIP-compressed, the image's
// values as they are: radiance L in W/(m²·sr) for a render, irradiance E in W/m² for a lightmap
// (io/lightmap_export.h). 32-bit float keeps them exactly (to float precision); 16-bit half
// float, what engines load lightmaps as, keeps 11 significant bits (relative error at most
// 2^-11) from 6.1e-5 up to 65504, and its larger values are written as 65504.
#include <cstdint>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/image.h"

namespace lambert {

enum class ExrPixelType { Float, Half };

// The EXR file's bytes, in memory.
Result<std::vector<std::uint8_t>> encodeExr(const Image& image, ExrPixelType type = ExrPixelType::Float);
// Written atomically (a temporary file renamed over path); errors name the path.
Status writeExr(const std::string& path, const Image& image, ExrPixelType type = ExrPixelType::Float);
// Reads an EXR's R, G and B (float or half); errors name the path.
Result<Image> readExr(const std::string& path);

}  // namespace lambert
