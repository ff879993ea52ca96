#pragma once
// OpenEXR images of linear radiance (tinyexr): what a compositor or an HDR viewer reads without
// lambert's tone mapping. Three 32-bit float channels B, G, R (EXR's order), ZIP-compressed,
// values L in W/(m²·sr) exactly as rendered.
#include <string>

#include "lambert/core/error.h"
#include "lambert/core/image.h"

namespace lambert {

// Written atomically (a temporary file renamed over path); errors name the path.
Status writeExr(const std::string& path, const Image& image);
// Reads an EXR's R, G and B; errors name the path.
Result<Image> readExr(const std::string& path);

}  // namespace lambert
