#include "lambert/scene/texture.h"

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <filesystem>

#include "lambert/core/srgb.h"

namespace lambert {

Result<std::shared_ptr<const Texture>> textureFromSrgb8(std::span<const std::uint8_t> pixels, int width, int height,
                                                       int channels, const std::string& path) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      pixels.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels))
    return Error{path + ": not an 8-bit image of 1 to 4 channels"};
  // One decode per 8-bit level, not per texel.
  std::array<double, 256> linear;
  for (int i = 0; i < 256; ++i) linear[static_cast<std::size_t>(i)] = srgbDecode(i / 255.0);
  auto texture = std::make_shared<Texture>();
  texture->path = path;
  texture->width = width;
  texture->height = height;
  texture->pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  const bool grey = channels < 3;
  for (std::size_t i = 0; i < texture->pixels.size(); ++i) {
    const std::uint8_t* p = pixels.data() + i * static_cast<std::size_t>(channels);
    texture->pixels[i] = grey ? Rgb::gray(linear[p[0]]) : Rgb{linear[p[0]], linear[p[1]], linear[p[2]]};
    texture->peak = std::max(texture->peak, texture->pixels[i].maxComponent());
    texture->mean += texture->pixels[i];
  }
  texture->mean = texture->mean * (1.0 / static_cast<double>(texture->pixels.size()));
  return std::shared_ptr<const Texture>(std::move(texture));
}

Result<std::shared_ptr<const Texture>> readTexture(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such texture file"};
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 0);
  if (!data) return Error{path + ": cannot read the texture (" + std::string(stbi_failure_reason()) + ")"};
  auto texture = textureFromSrgb8({data, static_cast<std::size_t>(width) * height * channels}, width, height, channels, path);
  stbi_image_free(data);
  return texture;
}

Rgb boundedAlbedo(Rgb factor, const Texture& texture, const std::string& where) {
  if (!(texture.peak > 0)) return factor;
  return boundedAlbedo(factor * texture.peak, where) * (1 / texture.peak);
}

Rgb meanTextureOver(const Texture& texture, std::span<const Vec3> corners, std::span<const Uv> uvs) {
  constexpr int kStrata = 4;
  Rgb sum;
  double totalArea = 0;
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    const double area = 0.5 * length(cross(corners[k] - corners[0], corners[k + 1] - corners[0]));
    if (!(area > 0)) continue;
    // Midpoints of a 4 × 4 grid on the unit square, the half beyond the diagonal folded back onto
    // the triangle's barycentric domain (a + b ≤ 1).
    Rgb triangle;
    for (int i = 0; i < kStrata; ++i)
      for (int j = 0; j < kStrata; ++j) {
        double a = (i + 0.5) / kStrata, b = (j + 0.5) / kStrata;
        if (a + b > 1) a = 1 - a, b = 1 - b;
        const double u = uvs[0].u + a * (uvs[k].u - uvs[0].u) + b * (uvs[k + 1].u - uvs[0].u);
        const double v = uvs[0].v + a * (uvs[k].v - uvs[0].v) + b * (uvs[k + 1].v - uvs[0].v);
        triangle += texture.sample(u, v);
      }
    sum += triangle * (area / (kStrata * kStrata));
    totalArea += area;
  }
  return totalArea > 0 ? sum * (1 / totalArea) : texture.sample(uvs[0].u, uvs[0].v);
}

}  // namespace lambert
