#pragma once
// Albedo and emission textures: 8-bit image files decoded from sRGB to linear factors (stb_image),
// so a texture's mean is the physical mean albedo (or the mean fraction of the emission factor).
// Used by the OBJ (map_Kd, map_Ke), glTF (baseColorTexture, emissiveTexture) and scene-file
// (texture, emissionTexture) loaders.
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "lambert/core/error.h"
#include "lambert/scene/regions.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Reads a PNG, JPEG, TGA or BMP file; an error names the file and why it cannot be read.
Result<std::shared_ptr<const Texture>> readTexture(const std::string& path);

// A texture from 8-bit sRGB pixels already decoded (glTF images), 1–4 channels: grey, grey +
// alpha, RGB or RGBA (alpha is ignored: lambert's surfaces are opaque).
Result<std::shared_ptr<const Texture>> textureFromSrgb8(std::span<const std::uint8_t> pixels, int width, int height,
                                                       int channels, const std::string& path);

// A factor made physical for a texture it multiplies: lowered (with boundedAlbedo's warning) so that
// factor × the brightest texel stays below 1. (A white factor over a texture that never reaches
// white is left as it is.)
Rgb boundedAlbedo(Rgb factor, const Texture& texture, const std::string& where);

// The mean of the texture over a patch: bilinear samples at 16 stratified points of each fan
// triangle of `corners`, whose texture coordinates are `uvs`, weighted by area.
Rgb meanTextureOver(const Texture& texture, std::span<const Vec3> corners, std::span<const Uv> uvs);

}  // namespace lambert
