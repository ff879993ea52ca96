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

Result<std::vector<std::uint8_t>> encode(int width, int height, const std::vector<std::uint8_t>& bytes, int channels) {
  if (width <= 0 || height <= 0 || bytes.size() != static_cast<std::size_t>(width) * height * channels)
    return Error{"image is " + std::to_string(width) + "x" + std::to_string(height) + " but has " + std::to_string(bytes.size()) +
                 " bytes of " + (channels == 4 ? "RGBA" : "RGB")};
  std::vector<std::uint8_t> encoded;
  if (!stbi_write_png_to_func(appendBytes, &encoded, width, height, channels, bytes.data(), width * channels))
    return Error{"PNG encoding failed"};
  return encoded;
}

}  // namespace

Result<std::vector<std::uint8_t>> encodePng(int width, int height, const std::vector<std::uint8_t>& rgb8) {
  return encode(width, height, rgb8, 3);
}

Result<std::vector<std::uint8_t>> encodePngRgba(int width, int height, const std::vector<std::uint8_t>& rgba8) {
  return encode(width, height, rgba8, 4);
}

Status writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb8) {
  if (path.empty()) return Error{"writePng: empty path"};
  Result<std::vector<std::uint8_t>> encoded = encodePng(width, height, rgb8);
  if (!encoded) return Error{path + ": " + encoded.error().message};
  return writeFileAtomically(path, *encoded);
}

namespace {

// The file's pixels with `channels` 8-bit channels each, or why not.
Result<std::vector<std::uint8_t>> load(const std::string& path, int channels, int& width, int& height) {
  int stored = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &stored, channels);
  if (!data) {
    const char* why = stbi_failure_reason();
    return Error{path + ": cannot read PNG: " + (why ? why : "unknown error")};
  }
  std::vector<std::uint8_t> bytes(data, data + static_cast<std::size_t>(width) * height * channels);
  stbi_image_free(data);
  return bytes;
}

}  // namespace

Result<PngImage> readPng(const std::string& path) {
  PngImage image;
  Result<std::vector<std::uint8_t>> bytes = load(path, 3, image.width, image.height);
  if (!bytes) return bytes.error();
  image.rgb8 = std::move(*bytes);
  return image;
}

}  // namespace lambert
