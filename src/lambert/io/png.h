#pragma once
// PNG files: written atomically (a reader never sees a partial image), read back for tests.
#include <cstdint>
#include <string>
#include <vector>

#include "lambert/core/error.h"

namespace lambert {

// Writes 8-bit RGB (interleaved, row-major, top row first) as a PNG. Missing parent directories
// are created. The image goes to "<path>.tmp-<pid>" first and is renamed over path, so path
// holds either its old content or the whole new image; on failure the temporary is removed and
// the error names path.
Status writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb8);

// The PNG encoding of 8-bit RGB, in memory (for images inside other files: .glb).
Result<std::vector<std::uint8_t>> encodePng(int width, int height, const std::vector<std::uint8_t>& rgb8);

// The same for 8-bit RGBA (an encoding that uses the fourth channel: io/lightmap_export.h's RGBM).
// Alpha is stored as given (not premultiplied).
Result<std::vector<std::uint8_t>> encodePngRgba(int width, int height, const std::vector<std::uint8_t>& rgba8);

struct PngImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb8;  // interleaved RGB, row-major, top row first
};

// Reads any PNG as 8-bit RGB (grey and alpha are converted).
Result<PngImage> readPng(const std::string& path);

}  // namespace lambert
