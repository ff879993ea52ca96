#include "lambert/io/png.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include "lambert/core/atomic_file.h"

namespace lambert {
namespace {

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

Result<std::vector<std::uint8_t>> encodePng(int width, int height, const std::vector<std::uint8_t>& rgb8) {
  if (width <= 0 || height <= 0 || rgb8.size() != static_cast<std::size_t>(width) * height * 3)
    return Error{"image is " + std::to_string(width) + "x" + std::to_string(height) + " but has " + std::to_string(rgb8.size()) +
                 " bytes of RGB"};
  std::vector<std::uint8_t> encoded;
  if (!stbi_write_png_to_func(appendBytes, &encoded, width, height, 3, rgb8.data(), width * 3)) return Error{"PNG encoding failed"};
  return encoded;
}

Status writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb8) {
  if (path.empty()) return Error{"writePng: empty path"};
  Result<std::vector<std::uint8_t>> encoded = encodePng(width, height, rgb8);
  if (!encoded) return Error{path + ": " + encoded.error().message};
  return writeFileAtomically(path, *encoded);
}

Result<PngImage> readPng(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (!data) {
    const char* why = stbi_failure_reason();
    return Error{path + ": cannot read PNG: " + (why ? why : "unknown error")};
  }
  PngImage image;
  image.width = width;
  image.height = height;
  image.rgb8.assign(data, data + static_cast<std::size_t>(width) * height * 3);
  stbi_image_free(data);
  return image;
}

}  // namespace lambert
