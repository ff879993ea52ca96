#include "lambert/io/exr.h"

#include <tinyexr.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "lambert/core/atomic_file.h"

namespace lambert {
namespace {

constexpr float kHalfMax = 65504.0f;  // the largest finite half float

std::string takeMessage(const char* message) {
  std::string text = message ? message : "unknown error";
  if (message) FreeEXRErrorMessage(message);
  return text;
}

}  // namespace

Result<std::vector<std::uint8_t>> encodeExr(const Image& image, ExrPixelType type) {
  if (image.width <= 0 || image.height <= 0 || image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    return Error{"cannot write an empty image"};
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::vector<float> channels[3];  // EXR viewers expect the channels sorted by name: B, G, R
  for (auto& c : channels) c.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    channels[0][p] = static_cast<float>(image.pixels[p].b);
    channels[1][p] = static_cast<float>(image.pixels[p].g);
    channels[2][p] = static_cast<float>(image.pixels[p].r);
  }
  float* planes[3] = {channels[0].data(), channels[1].data(), channels[2].data()};

  EXRHeader header;
  InitEXRHeader(&header);
  EXRImage exr;
  InitEXRImage(&exr);
  exr.num_channels = 3;
  exr.images = reinterpret_cast<unsigned char**>(planes);
  exr.width = image.width;
  exr.height = image.height;
  EXRChannelInfo info[3] = {};
  // The planes given are float; tinyexr converts them to half where that is asked for (rounding
  // to nearest, values beyond half's range to infinity: clamped here first).
  int given[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  const int stored = type == ExrPixelType::Half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT;
  int types[3] = {stored, stored, stored};
  if (type == ExrPixelType::Half)
    for (auto& c : channels)
      for (float& x : c)
        if (x > kHalfMax) x = kHalfMax;
  const char* names[3] = {"B", "G", "R"};
  for (int c = 0; c < 3; ++c) std::snprintf(info[c].name, sizeof info[c].name, "%s", names[c]);
  header.num_channels = 3;
  header.channels = info;
  header.pixel_types = given;
  header.requested_pixel_types = types;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

  unsigned char* memory = nullptr;
  const char* message = nullptr;
  const std::size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &message);
  if (size == 0) return Error{"cannot encode EXR: " + takeMessage(message)};
  std::vector<std::uint8_t> bytes(memory, memory + size);
  std::free(memory);
  return bytes;
}

Status writeExr(const std::string& path, const Image& image, ExrPixelType type) {
  Result<std::vector<std::uint8_t>> bytes = encodeExr(image, type);
  if (!bytes) return Error{path + ": " + bytes.error().message};
  return writeFileAtomically(path, *bytes);
}

Result<Image> readExr(const std::string& path) {
  float* rgba = nullptr;
  int width = 0, height = 0;
  const char* message = nullptr;
  if (LoadEXR(&rgba, &width, &height, path.c_str(), &message) != TINYEXR_SUCCESS)
    return Error{path + ": " + takeMessage(message)};
  Image image;
  image.width = width;
  image.height = height;
  image.pixels.resize(static_cast<std::size_t>(width) * height);
  for (std::size_t p = 0; p < image.pixels.size(); ++p) image.pixels[p] = {rgba[4 * p], rgba[4 * p + 1], rgba[4 * p + 2]};
  std::free(rgba);
  return image;
}

}  // namespace lambert
