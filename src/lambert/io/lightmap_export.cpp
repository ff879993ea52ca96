#include "lambert/io/lightmap_export.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

#include "lambert/core/atomic_file.h"
#include "lambert/core/warning.h"
#include "lambert/io/exr.h"
#include "lambert/io/gltf_model.h"
#include "lambert/io/png.h"

namespace lambert {
namespace {

bool usable(double x) { return std::isfinite(x) && x >= 0; }

std::uint8_t byteOf(double unit) { return static_cast<std::uint8_t>(std::lround(255 * std::clamp(unit, 0.0, 1.0))); }

// The lightmap with every unusable channel (non-finite, negative) set to 0; counts them.
Image repaired(const Image& image, std::size_t& repairs) {
  Image out = image;
  for (Rgb& p : out.pixels)
    for (int c = 0; c < 3; ++c)
      if (!usable(p[c])) p[c] = 0, ++repairs;
  return out;
}

// Checks that the lightmaps were baked for this scene: one coordinate per face corner, every
// atlas index and image in range.
Status checkMatches(const Scene& scene, const BakedLightmaps& baked) {
  const LightmapUvs& uvs = baked.uvs;
  auto mismatch = [](const std::string& what) {
    return Error{"the lightmaps do not match the scene (" + what + "): bake them from this scene's solution"};
  };
  if (uvs.numAtlases <= 0 || uvs.size <= 0) return mismatch("no atlas");
  if (baked.irradiance.size() != static_cast<std::size_t>(uvs.numAtlases))
    return mismatch(std::to_string(uvs.numAtlases) + " atlases but " + std::to_string(baked.irradiance.size()) + " images");
  for (const Image& image : baked.irradiance)
    if (image.width != uvs.size || image.height != uvs.size || image.pixels.size() != static_cast<std::size_t>(uvs.size) * uvs.size)
      return mismatch("an image is not " + std::to_string(uvs.size) + " texels square");
  if (uvs.uv.size() != scene.surfaces.size() || uvs.atlas.size() != scene.surfaces.size())
    return mismatch(std::to_string(scene.surfaces.size()) + " surfaces, coordinates for " + std::to_string(uvs.uv.size()));
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const std::vector<std::vector<std::uint32_t>> faces = surfaceFaces(scene.surfaces[s]);
    if (uvs.uv[s].size() != faces.size() || uvs.atlas[s].size() != faces.size())
      return mismatch("surface " + std::to_string(s) + " has " + std::to_string(faces.size()) + " faces");
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (uvs.uv[s][f].size() != faces[f].size()) return mismatch("surface " + std::to_string(s) + " face " + std::to_string(f));
      if (uvs.atlas[s][f] >= uvs.numAtlases) return mismatch("surface " + std::to_string(s) + " face " + std::to_string(f) + "'s atlas");
    }
  }
  return Ok{};
}

// What a glTF material and its primitive are made of: faces of one scene material, one atlas and
// one emission, whose base colour (and emission) textures are drawn through texture coordinates
// or, where the surface has none, by their mean (as lambert's solve takes them).
struct Group {
  int material;
  int atlas;
  bool textured;  // a texture of the material is drawn through TEXCOORD_0
  Rgb emitted;    // L_e, W/(m²·sr)
  auto key() const { return std::tuple(material, atlas, textured, emitted.r, emitted.g, emitted.b); }
  bool operator<(const Group& other) const { return key() < other.key(); }
};

struct Face {
  std::uint32_t surface, face;
};

tinygltf::Value number(double x) { return tinygltf::Value(x); }

}  // namespace

double lightmapScale(const Image& irradiance) {
  double largest = 0;
  for (const Rgb& p : irradiance.pixels)
    for (int c = 0; c < 3; ++c)
      if (usable(p[c])) largest = std::fmax(largest, p[c]);
  return largest > 0 ? largest : 1;
}

std::vector<std::uint8_t> encodeRgbm(const Image& irradiance, double scale) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(irradiance.pixels.size() * 4);
  for (const Rgb& p : irradiance.pixels) {
    double c[3];
    for (int k = 0; k < 3; ++k) c[k] = usable(p[k]) ? std::fmin(p[k] / scale, 1.0) : 0;
    const double m = std::fmax(c[0], std::fmax(c[1], c[2]));
    // The smallest multiplier a/255 at or above m, so that every channel's c / M is at most 1.
    const int a = static_cast<int>(std::clamp(std::ceil(255 * m), 0.0, 255.0));
    for (int k = 0; k < 3; ++k) bytes.push_back(a > 0 ? byteOf(c[k] * 255 / a) : 0);
    bytes.push_back(static_cast<std::uint8_t>(a));
  }
  return bytes;
}

Rgb decodeRgbm(const std::uint8_t* rgba, double scale) {
  const double multiplier = scale * rgba[3] / 255.0;
  return {multiplier * rgba[0] / 255.0, multiplier * rgba[1] / 255.0, multiplier * rgba[2] / 255.0};
}

BakedLightmaps asCarriedByGlb(const BakedLightmaps& baked) {
  BakedLightmaps carried = baked;
  for (Image& atlas : carried.irradiance) {
    const double scale = lightmapScale(atlas);
    const std::vector<std::uint8_t> bytes = encodeRgbm(atlas, scale);
    for (std::size_t p = 0; p < atlas.pixels.size(); ++p) atlas.pixels[p] = decodeRgbm(&bytes[4 * p], scale);
  }
  return carried;
}

std::string lightmapExrPath(const std::string& glbPath, std::size_t atlas) {
  std::filesystem::path path(glbPath);
  return (path.parent_path() / (path.stem().string() + "-lightmap-" + std::to_string(atlas) + ".exr")).string();
}

Result<LightmapExport> writeLightmaps(const std::string& glbPath, const Scene& scene, const BakedLightmaps& baked,
                                      const LightmapExportOptions& options) {
  if (Status matches = checkMatches(scene, baked); !matches) return Error{glbPath + ": " + matches.error().message};
  const LightmapUvs& uvs = baked.uvs;
  const std::size_t numAtlases = static_cast<std::size_t>(uvs.numAtlases);
  LightmapExport result;
  result.glb = glbPath;

  // The lightmaps as written: unusable channels repaired, and each atlas's scale.
  std::vector<Image> lightmaps;
  for (const Image& image : baked.irradiance) lightmaps.push_back(repaired(image, result.repairedTexels));
  if (result.repairedTexels > 0)
    warning(glbPath + ": " + std::to_string(result.repairedTexels) +
            " lightmap texel channels were not a finite irradiance of at least 0 and are written as 0");
  result.atlases.resize(numAtlases);
  for (std::size_t k = 0; k < numAtlases; ++k) {
    result.atlases[k].scale = lightmapScale(lightmaps[k]);
    if (k < baked.covered.size())
      result.atlases[k].coveredTexels = static_cast<std::size_t>(std::count(baked.covered[k].begin(), baked.covered[k].end(), 1));
  }

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "lambert";
  model.buffers.resize(1);
  model.extensionsUsed = {"LAMBERT_lightmap"};

  // Each atlas's image, RGBM, once for all the materials on it (and only for an atlas
  // some face lies in: an unused texture is no part of the model).
  const std::string stem = std::filesystem::path(glbPath).stem().string();
  std::vector<int> lightmapTexture(numAtlases, -1);
  auto lightmapTextureOf = [&](std::size_t k) -> Result<int> {
    if (lightmapTexture[k] >= 0) return lightmapTexture[k];
    Result<std::vector<std::uint8_t>> png = encodePngRgba(uvs.size, uvs.size, encodeRgbm(lightmaps[k], result.atlases[k].scale));
    if (!png) return png.error();
    const int image = gltf::addPngImage(model, *png, stem + "-lightmap-" + std::to_string(k));
    return lightmapTexture[k] = gltf::addTexture(model, image, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE, TINYGLTF_TEXTURE_FILTER_LINEAR);
  };

  // The faces of each group, in scene order.
  std::map<Group, std::vector<Face>> groups;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    const Material& material = scene.materials.at(static_cast<std::size_t>(surface.material));
    const bool hasUvs = !surface.faceUvs.empty();
    const bool emits = surface.emittedRadiance.maxComponent() > 0;
    const bool textured = hasUvs && (material.texture || (emits && material.emissionTexture));
    for (std::uint32_t f = 0; f < uvs.atlas[s].size(); ++f)
      groups[{surface.material, uvs.atlas[s][f], textured, emits ? surface.emittedRadiance : Rgb{}}].push_back({s, f});
  }

  // Per-vertex normals of every surface: its faces' area vectors summed at their corners.
  std::vector<std::vector<Vec3>> normals(scene.surfaces.size());
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    normals[s].assign(surface.vertices.size(), Vec3{});
    for (const std::vector<std::uint32_t>& face : surfaceFaces(surface)) {
      const Vec3 area = polygonAreaVector(facePositions(surface, face));
      for (std::uint32_t v : face) normals[s][v] += area;
    }
  }

  bool emissiveStrength = false;
  std::map<const Texture*, int> colourTexture;
  auto textureOf = [&](const Texture& texture) {
    auto [it, inserted] = colourTexture.try_emplace(&texture, 0);
    if (inserted) it->second = gltf::addColourTexture(model, texture);
    return it->second;
  };
  tinygltf::Mesh out;
  out.name = scene.name;
  for (const auto& [group, faces] : groups) {
    // One vertex per distinct (surface, vertex, texture coordinate, lightmap coordinate).
    std::map<std::tuple<std::uint32_t, std::uint32_t, double, double, double, double>, std::uint32_t> local;
    std::vector<float> position, normal, texcoord0, texcoord1;
    std::vector<std::uint32_t> indices;
    auto vertex = [&](std::uint32_t s, std::uint32_t v, const Uv& uv0, const Uv& uv1) {
      auto [it, inserted] = local.try_emplace(std::tuple(s, v, uv0.u, uv0.v, uv1.u, uv1.v), static_cast<std::uint32_t>(local.size()));
      if (inserted) {
        const Surface& surface = scene.surfaces[s];
        const Vec3 p = surface.vertices[v] * scene.metresPerUnit;
        // A vertex of zero-area faces only takes its surface's normal (any unit vector for a
        // surface of no area): glTF normals are unit vectors.
        Vec3 n = normals[s][v];
        if (!(length(n) > 0)) n = surfaceNormal(surface);
        n = length(n) > 0 ? normalize(n) : Vec3{0, 1, 0};
        for (double x : {p.x, p.y, p.z}) position.push_back(static_cast<float>(x));
        for (double x : {n.x, n.y, n.z}) normal.push_back(static_cast<float>(x));
        for (double x : {uv0.u, uv0.v}) texcoord0.push_back(static_cast<float>(x));
        for (double x : {uv1.u, uv1.v}) texcoord1.push_back(static_cast<float>(x));
      }
      return it->second;
    };
    for (const Face& face : faces) {
      const Surface& surface = scene.surfaces[face.surface];
      const std::vector<std::uint32_t> corners = surfaceFace(surface, face.face);
      const std::vector<Uv>& lightmapUvs = uvs.uv[face.surface][face.face];
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        std::uint32_t triangle[3];
        for (std::size_t i = 0; i < 3; ++i) {
          const std::size_t c = i == 0 ? 0 : k + i - 1;
          // glTF numbers coordinate sets from 0 without gaps: without a texture to draw, set 0
          // repeats the lightmap's.
          const Uv uv0 = group.textured ? surface.faceUvs[face.face][c] : lightmapUvs[c];
          triangle[i] = vertex(face.surface, corners[c], uv0, lightmapUvs[c]);
        }
        // A face that repeats a corner fans into a triangle of two corners: nothing to draw.
        if (triangle[0] != triangle[1] && triangle[1] != triangle[2] && triangle[0] != triangle[2])
          indices.insert(indices.end(), triangle, triangle + 3);
      }
    }
    if (indices.empty()) continue;  // faces of fewer than three corners only: nothing to draw

    const Material& material = scene.materials.at(static_cast<std::size_t>(group.material));
    tinygltf::Material m;
    m.name = material.name + (numAtlases > 1 ? " (lightmap " + std::to_string(group.atlas) + ")" : "") +
             (group.emitted.maxComponent() > 0 ? " (emitting)" : "");
    // ρ = albedo × texture: the texture drawn through TEXCOORD_0, or its mean where there are none.
    Rgb base = material.albedo;
    if (material.texture && !group.textured) base = base * material.texture->mean;
    m.pbrMetallicRoughness.baseColorFactor = {base.r, base.g, base.b, 1};
    if (material.texture && group.textured) m.pbrMetallicRoughness.baseColorTexture.index = textureOf(*material.texture);
    m.pbrMetallicRoughness.metallicFactor = 0;
    m.pbrMetallicRoughness.roughnessFactor = 1;
    if (group.emitted.maxComponent() > 0) {
      Rgb emitted = group.emitted;
      if (material.emissionTexture && group.textured)
        m.emissiveTexture.index = textureOf(*material.emissionTexture);
      else if (material.emissionTexture)
        emitted = emitted * material.emissionTexture->mean;
      // glTF's emissiveFactor lies in [0, 1]; KHR_materials_emissive_strength carries the rest.
      const double strength = std::fmax(1.0, emitted.maxComponent());
      m.emissiveFactor = {emitted.r / strength, emitted.g / strength, emitted.b / strength};
      if (strength > 1) {
        m.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(tinygltf::Value::Object{{"emissiveStrength", number(strength)}});
        emissiveStrength = true;
      }
    }
    Result<int> lightmapIndex = lightmapTextureOf(static_cast<std::size_t>(group.atlas));
    if (!lightmapIndex) return Error{glbPath + ": " + lightmapIndex.error().message};
    m.extensions["LAMBERT_lightmap"] = tinygltf::Value(tinygltf::Value::Object{
        {"index", tinygltf::Value(*lightmapIndex)},
        {"texCoord", tinygltf::Value(1)},
        {"encoding", tinygltf::Value(std::string("RGBM"))},
        {"range", number(result.atlases[static_cast<std::size_t>(group.atlas)].scale)}});
    model.materials.push_back(m);

    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = static_cast<int>(model.materials.size() - 1);
    primitive.attributes["POSITION"] = gltf::addVec3(model, position, true);
    primitive.attributes["NORMAL"] = gltf::addVec3(model, normal, false);
    primitive.attributes["TEXCOORD_0"] = gltf::addVec2(model, texcoord0);
    primitive.attributes["TEXCOORD_1"] = gltf::addVec2(model, texcoord1);
    primitive.indices = gltf::addIndices(model, indices);
    out.primitives.push_back(primitive);
    result.vertices += local.size();
    result.triangles += indices.size() / 3;
  }
  if (emissiveStrength) model.extensionsUsed.push_back("KHR_materials_emissive_strength");
  result.primitives = out.primitives.size();
  if (out.primitives.empty()) return Error{glbPath + ": the scene has no face to draw"};
  model.meshes.push_back(out);
  gltf::addSceneWithCamera(model, scene);

  // Every file's bytes before any is written: an encoding error leaves nothing behind.
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> files;
  for (std::size_t k = 0; k < numAtlases; ++k) {
    LightmapAtlasFiles& atlas = result.atlases[k];
    if (options.exr) {
      atlas.exr = lightmapExrPath(glbPath, k);
      for (const Rgb& p : lightmaps[k].pixels)
        for (int c = 0; c < 3; ++c) result.clampedTexels += static_cast<float>(p[c]) > 65504.0f;
      Result<std::vector<std::uint8_t>> exr = encodeExr(lightmaps[k], ExrPixelType::Half);
      if (!exr) return Error{atlas.exr + ": " + exr.error().message};
      files.emplace_back(atlas.exr, std::move(*exr));
    }
  }
  if (result.clampedTexels > 0)
    warning(glbPath + ": " + std::to_string(result.clampedTexels) +
            " lightmap texel channels exceed half float's 65504 W/m² and are written as 65504 in the EXR files (the glb keeps them)");
  Result<std::vector<std::uint8_t>> glb = gltf::encodeGlb(model);
  if (!glb) return Error{glbPath + ": " + glb.error().message};
  files.emplace_back(glbPath, std::move(*glb));  // last: a reader that sees the glb sees its lightmaps

  for (std::size_t i = 0; i < files.size(); ++i) {
    Status written = writeFileAtomically(files[i].first, files[i].second);
    if (!written) {
      for (std::size_t j = 0; j < i; ++j) {
        std::error_code ignored;
        std::filesystem::remove(files[j].first, ignored);
      }
      return written.error();
    }
  }
  return result;
}

Stats lightmapStats(const Scene& scene, const BakedLightmaps& baked, const LightmapExport& files) {
  const LightmapUvs& uvs = baked.uvs;
  const char* origin = uvs.origin == LightmapUvs::Origin::FileLightmapSet ? "file lightmap coordinates"
                       : uvs.origin == LightmapUvs::Origin::FileFirstSet  ? "file texture coordinates"
                                                                          : "generated charts";
  Stats stats;
  stats.add("lightmap_atlases", "lightmap atlases", static_cast<std::int64_t>(uvs.numAtlases));
  stats.add("lightmap_size", "lightmap texels per side", static_cast<std::int64_t>(uvs.size));
  stats.add("lightmap_texel_size_m", "lightmap texel size", uvs.texelSize * scene.metresPerUnit, "m");
  stats.add("lightmap_uv_origin", "lightmap coordinates", std::string(origin));
  stats.add("lightmap_charts", "lightmap charts", static_cast<std::int64_t>(uvs.charts));
  stats.add("lightmap_efficiency", "lightmap packing efficiency", uvs.efficiency);
  stats.add("lightmap_texels_baked", "lightmap texels baked", static_cast<std::int64_t>(baked.texelsBaked));
  stats.add("lightmap_texels_gathered", "lightmap texels gathered (the rest interpolated)", static_cast<std::int64_t>(baked.texelsGathered));
  stats.add("lightmap_bake_seconds", "lightmap bake time", baked.seconds, "s");
  stats.add("lightmap_glb_vertices", "lightmapped glb vertices", static_cast<std::int64_t>(files.vertices));
  stats.add("lightmap_glb_triangles", "lightmapped glb triangles", static_cast<std::int64_t>(files.triangles));
  stats.add("lightmap_glb_primitives", "lightmapped glb primitives", static_cast<std::int64_t>(files.primitives));
  for (std::size_t k = 0; k < files.atlases.size(); ++k) {
    const std::string key = "lightmap_" + std::to_string(k), label = "lightmap " + std::to_string(k);
    if (!files.atlases[k].exr.empty()) stats.add(key + "_exr", label + " EXR written to", files.atlases[k].exr);
    stats.add(key + "_scale", label + " range (the glb's RGBM, LAMBERT_lightmap)", files.atlases[k].scale, "W/m²");
  }
  return stats;
}

}  // namespace lambert
