// Lightmap output, from lightmaps made by hand here (not baked): a small scene in millimetres whose
// faces are given lightmap coordinates at known texels of two atlases filled with a known
// irradiance pattern. The glb is read back with tinygltf and every vertex's lightmap texel,
// decoded as RGBM with the material's range, must be the pattern's irradiance there; the EXR must
// give the irradiance back within its precision, decoded by formulas written here.
#include "lambert/io/lightmap_export.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <set>
#include <tuple>

#include "lambert/core/warning.h"
#include "lambert/io/exr.h"
#include "lambert/io/png.h"
#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

constexpr int kAtlasSize = 16;

// The irradiance the test's atlases hold at texel (x, y) of atlas k, W/m²: every texel different,
// channels different, values over three decades.
Rgb patternAt(int atlas, int x, int y) {
  const double f = 0.05 * (1 + x + kAtlasSize * y) * (atlas + 1);
  return {f, 2 * f + 1, 0.5 * f};
}

// The lightmap coordinate of texel (x, y)'s centre.
Uv texelCentre(int x, int y) { return {(x + 0.5) / kAtlasSize, (y + 0.5) / kAtlasSize}; }

std::shared_ptr<Texture> checker() {
  auto texture = std::make_shared<Texture>();
  texture->path = "checker.png";
  texture->width = texture->height = 2;
  texture->pixels = {{0.8, 0.8, 0.8}, {0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}, {0.8, 0.8, 0.8}};
  texture->peak = 0.8;
  texture->mean = {0.5, 0.5, 0.5};
  return texture;
}

// The scene and its lightmaps. Surfaces:
//   0 floor (white): two triangles of a quad, face 0 in atlas 0 and face 1 in atlas 1, so white
//     needs one primitive per atlas;
//   1 wall (textured, with texture coordinates);
//   2 back wall (the same material, without texture coordinates: drawn with the texture's mean);
//   3 lamp (emitting 5 W/(m²·sr), beyond glTF's [0, 1] emissive factor);
//   4 step (white, atlas 0): a quad and a triangle sharing the edge 0–3, whose corner 0 has one
//     lightmap coordinate in both faces and corner 3 two (a seam): 4 + 2 vertices.
struct Fixture {
  Scene scene;
  BakedLightmaps baked;

  Fixture() {
    scene.name = "fixture";
    scene.metresPerUnit = 0.001;
    scene.materials = {{"white", {0.7, 0.7, 0.7}}, {"checker", {0.9, 0.8, 0.7}}, {"lamp", {0.5, 0.5, 0.5}}};
    scene.materials[1].texture = checker();
    scene.camera = {{500, 500, 2000}, {500, 500, 0}, {0, 1, 0}, 40};
    auto& s = scene.surfaces;
    s.push_back({"floor", {{0, 0, 0}, {0, 0, 1000}, {1000, 0, 1000}, {1000, 0, 0}}, 0, {}, {{0, 1, 2}, {0, 2, 3}}});
    s.push_back({"wall", {{0, 0, 0}, {1000, 0, 0}, {1000, 1000, 0}, {0, 1000, 0}}, 1, {}});
    s[1].faceUvs = {{{0, 1}, {2, 1}, {2, 0}, {0, 0}}};
    s.push_back({"back wall", {{0, 0, 1000}, {0, 1000, 1000}, {1000, 1000, 1000}, {1000, 0, 1000}}, 1, {}});
    s.push_back({"lamp", {{400, 990, 400}, {600, 990, 400}, {600, 990, 600}, {400, 990, 600}}, 2, {5, 5, 4}});
    s.push_back({"step", {{0, 200, 0}, {0, 200, 300}, {300, 200, 300}, {400, 200, 100}, {300, 200, -100}}, 0, {}, {{0, 1, 2, 3}, {0, 3, 4}}});

    LightmapUvs& uvs = baked.uvs;
    uvs.size = kAtlasSize;
    uvs.numAtlases = 2;
    uvs.texelSize = 1000.0 / kAtlasSize;
    auto at = [](std::initializer_list<std::array<int, 2>> texels) {
      std::vector<Uv> corners;
      for (const auto& [x, y] : texels) corners.push_back(texelCentre(x, y));
      return corners;
    };
    uvs.uv = {
        {at({{1, 1}, {1, 5}, {5, 5}}), at({{8, 1}, {12, 5}, {12, 1}})},  // floor: the shared corners 0, 2 differ
        {at({{1, 8}, {5, 8}, {5, 12}, {1, 12}})},
        {at({{8, 8}, {8, 12}, {12, 12}, {12, 8}})},
        {at({{14, 14}, {15, 14}, {15, 15}, {14, 15}})},
        {at({{1, 13}, {1, 15}, {4, 15}, {5, 13}}), at({{1, 13}, {7, 14}, {6, 12}})},  // step: corner 3 is (5, 13) and (7, 14)
    };
    uvs.atlas = {{0, 1}, {0}, {0}, {0}, {0, 0}};
    for (int k = 0; k < 2; ++k) {
      Image image;
      image.width = image.height = kAtlasSize;
      for (int y = 0; y < kAtlasSize; ++y)
        for (int x = 0; x < kAtlasSize; ++x) image.pixels.push_back(patternAt(k, x, y));
      baked.irradiance.push_back(image);
      baked.covered.push_back(std::vector<std::uint8_t>(kAtlasSize * kAtlasSize, 1));
    }
  }

  // S_k by its definition: the largest channel of the pattern over the atlas.
  static double scale(int atlas) {
    double largest = 0;
    for (int y = 0; y < kAtlasSize; ++y)
      for (int x = 0; x < kAtlasSize; ++x) largest = std::fmax(largest, patternAt(atlas, x, y).maxComponent());
    return largest;
  }
};

template <class T>
std::vector<T> values(const tinygltf::Model& model, int accessorIndex, int componentType) {
  const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(accessorIndex));
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  EXPECT_EQ(a.componentType, componentType);
  std::vector<T> out(a.count * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type))));
  std::memcpy(out.data(), model.buffers[0].data.data() + view.byteOffset + a.byteOffset, out.size() * sizeof(T));
  return out;
}
std::vector<float> floats(const tinygltf::Model& model, int accessor) { return values<float>(model, accessor, TINYGLTF_COMPONENT_TYPE_FLOAT); }
std::vector<std::uint32_t> indices(const tinygltf::Model& model, int accessor) {
  return values<std::uint32_t>(model, accessor, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
}

const tinygltf::Value& member(const tinygltf::Value& object, const std::string& name) {
  static const tinygltf::Value none;
  return object.IsObject() && object.Has(name) ? object.Get(name) : none;
}

TEST(LightmapExportTest, GlbCarriesTheInputMeshAndEachMaterialsLightmap) {
  Fixture fixture;
  const std::filesystem::path dir = testing::scratchDirectory("lightmap-export", "glb");
  const std::string path = (dir / "box.glb").string();
  Result<LightmapExport> written = writeLightmaps(path, fixture.scene, fixture.baked);
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_FALSE(testing::hasTemporaryFiles(dir));
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(written->atlases[k].exr, (dir / ("box-lightmap-" + std::to_string(k) + ".exr")).string());
    EXPECT_TRUE(std::filesystem::exists(written->atlases[k].exr));
    EXPECT_EQ(written->atlases[k].scale, Fixture::scale(static_cast<int>(k)));
  }

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warn, path)) << error;
  const std::set<std::string> used(model.extensionsUsed.begin(), model.extensionsUsed.end());
  EXPECT_EQ(used, (std::set<std::string>{"LAMBERT_lightmap", "KHR_materials_emissive_strength"}));
  EXPECT_TRUE(model.extensionsRequired.empty()) << "a reader without LAMBERT_lightmap still draws the mesh";
  ASSERT_EQ(model.meshes.size(), 1u);
  // white × 2 atlases, checker with and without coordinates, lamp.
  ASSERT_EQ(model.meshes[0].primitives.size(), 5u);
  EXPECT_EQ(written->primitives, 5u);

  // What the scene's faces say, independently of the writer: for each lightmap coordinate of a
  // corner, its position; and the corners' distinct (surface, vertex, coordinates) per atlas and
  // material, the vertices the writer must make.
  std::set<std::tuple<int, int, std::uint32_t, std::uint32_t, double, double>> expectedVertices;  // material, atlas, ...
  double area = 0;
  for (std::uint32_t s = 0; s < fixture.scene.surfaces.size(); ++s) {
    const Surface& surface = fixture.scene.surfaces[s];
    const auto faces = surfaceFaces(surface);
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (std::size_t c = 0; c < faces[f].size(); ++c) {
        const Uv uv = fixture.baked.uvs.uv[s][f][c];
        expectedVertices.insert({surface.material, fixture.baked.uvs.atlas[s][f], s, faces[f][c], uv.u, uv.v});
      }
    area += surfaceArea(surface) * 1e-6;  // mm² to m²
  }

  std::size_t vertices = 0;
  double exportedArea = 0;
  std::set<std::string> names;
  for (const tinygltf::Primitive& primitive : model.meshes[0].primitives) {
    const tinygltf::Material& material = model.materials.at(static_cast<std::size_t>(primitive.material));
    names.insert(material.name);
    // LAMBERT_lightmap: the atlas's texture through TEXCOORD_1, RGBM of range S_k.
    ASSERT_TRUE(material.extensions.count("LAMBERT_lightmap")) << material.name;
    const tinygltf::Value& lightmap = material.extensions.at("LAMBERT_lightmap");
    EXPECT_EQ(member(lightmap, "texCoord").GetNumberAsInt(), 1) << material.name;
    EXPECT_EQ(member(lightmap, "encoding").Get<std::string>(), "RGBM") << material.name;
    const tinygltf::Texture& texture = model.textures.at(static_cast<std::size_t>(member(lightmap, "index").GetNumberAsInt()));
    const tinygltf::Image& image = model.images.at(static_cast<std::size_t>(texture.source));
    EXPECT_EQ(image.mimeType, "image/png");
    EXPECT_GE(image.bufferView, 0) << "embedded";
    EXPECT_TRUE(image.uri.empty());
    ASSERT_EQ(image.width, kAtlasSize);
    ASSERT_EQ(image.component, 4);  // RGBA
    const tinygltf::Sampler& sampler = model.samplers.at(static_cast<std::size_t>(texture.sampler));
    EXPECT_EQ(sampler.wrapS, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE);
    EXPECT_EQ(sampler.minFilter, TINYGLTF_TEXTURE_FILTER_LINEAR);
    const int atlas = material.name.find("(lightmap 1)") != std::string::npos ? 1 : 0;
    const double range = member(lightmap, "range").GetNumberAsDouble();
    EXPECT_EQ(range, Fixture::scale(atlas)) << material.name;
    EXPECT_EQ(material.pbrMetallicRoughness.metallicFactor, 0);
    EXPECT_FALSE(material.extensions.count("KHR_materials_unlit"));

    ASSERT_TRUE(primitive.attributes.count("TEXCOORD_1")) << material.name;
    const std::vector<float> position = floats(model, primitive.attributes.at("POSITION"));
    const std::vector<float> normal = floats(model, primitive.attributes.at("NORMAL"));
    const std::vector<float> uv1 = floats(model, primitive.attributes.at("TEXCOORD_1"));
    const std::size_t count = position.size() / 3;
    ASSERT_EQ(uv1.size(), 2 * count);
    vertices += count;
    for (std::size_t v = 0; v < count; ++v) {
      // The lightmap texel under the vertex, decoded with the range: the pattern there.
      const int x = static_cast<int>(std::floor(uv1[2 * v] * kAtlasSize)), y = static_cast<int>(std::floor(uv1[2 * v + 1] * kAtlasSize));
      ASSERT_TRUE(x >= 0 && x < kAtlasSize && y >= 0 && y < kAtlasSize) << material.name;
      const Rgb expected = patternAt(atlas, x, y);
      const unsigned char* rgbm = &image.image[4 * static_cast<std::size_t>(y * kAtlasSize + x)];
      for (int c = 0; c < 3; ++c) {
        const double decoded = range * (rgbm[c] / 255.0) * (rgbm[3] / 255.0);
        EXPECT_NEAR(decoded, expected[c], 0.5 / 255 * (expected.maxComponent() + range / 255) + 1e-12)
            << material.name << " texel " << x << ", " << y;
      }
      EXPECT_NEAR(std::hypot(normal[3 * v], normal[3 * v + 1], normal[3 * v + 2]), 1, 1e-6);
    }
    // Every corner of the scene in this primitive's group (material, atlas, and for the checker
    // whether its surface has texture coordinates), found by position (metres back to
    // millimetres) and lightmap coordinate: one vertex each, and no other vertex.
    const bool textured = material.pbrMetallicRoughness.baseColorTexture.index >= 0;
    std::size_t inGroup = 0, found = 0;
    for (const auto& [m, a, s, vertex, u, w] : expectedVertices) {
      const Surface& surface = fixture.scene.surfaces[s];
      if (!material.name.starts_with(fixture.scene.materials[static_cast<std::size_t>(m)].name + " ") || a != atlas ||
          (m == 1 && surface.faceUvs.empty() == textured))
        continue;
      ++inGroup;
      const Vec3 p = surface.vertices[vertex];
      std::size_t matches = 0;
      for (std::size_t v = 0; v < count; ++v)
        matches += std::fabs(position[3 * v] / 1e-3 - p.x) < 1e-3 && std::fabs(position[3 * v + 1] / 1e-3 - p.y) < 1e-3 &&
                   std::fabs(position[3 * v + 2] / 1e-3 - p.z) < 1e-3 && uv1[2 * v] == static_cast<float>(u) &&
                   uv1[2 * v + 1] == static_cast<float>(w);
      EXPECT_EQ(matches, 1u) << material.name << " surface " << s << " vertex " << vertex;
      found += matches == 1;
    }
    EXPECT_EQ(count, inGroup) << material.name;
    EXPECT_EQ(found, inGroup) << material.name;
    const std::vector<std::uint32_t> triangles = indices(model, primitive.indices);
    ASSERT_EQ(triangles.size() % 3, 0u);
    for (std::size_t t = 0; t < triangles.size(); t += 3) {
      auto at = [&](std::uint32_t i) { return Vec3{position[3 * i], position[3 * i + 1], position[3 * i + 2]}; };
      const Vec3 n = cross(at(triangles[t + 1]) - at(triangles[t]), at(triangles[t + 2]) - at(triangles[t]));
      exportedArea += 0.5 * length(n);
      // Counter-clockwise seen from the front: the triangle faces the way its vertices' normals do.
      EXPECT_GT(dot(n, Vec3{normal[3 * triangles[t]], normal[3 * triangles[t] + 1], normal[3 * triangles[t] + 2]}), 0);
    }

    // TEXCOORD_0: the texture's coordinates, else the lightmap's again (glTF's sets start at 0).
    ASSERT_TRUE(primitive.attributes.count("TEXCOORD_0")) << material.name;
    if (!textured) {
      EXPECT_EQ(floats(model, primitive.attributes.at("TEXCOORD_0")), uv1) << material.name;
    }
    const auto& base = material.pbrMetallicRoughness.baseColorFactor;
    if (material.name.starts_with("checker") && textured) {
      EXPECT_EQ(base, (std::vector<double>{0.9, 0.8, 0.7, 1}));
      const std::vector<float> uv0 = floats(model, primitive.attributes.at("TEXCOORD_0"));
      std::set<std::pair<float, float>> corners;
      for (std::size_t v = 0; v < count; ++v) corners.insert({uv0[2 * v], uv0[2 * v + 1]});
      EXPECT_EQ(corners, (std::set<std::pair<float, float>>{{0, 1}, {2, 1}, {2, 0}, {0, 0}}));
    } else if (material.name.starts_with("checker")) {
      EXPECT_NEAR(base[0], 0.9 * 0.5, 1e-12) << "the texture's mean where there are no coordinates";
    }
    if (material.name == "lamp (lightmap 0) (emitting)") {
      ASSERT_EQ(material.emissiveFactor.size(), 3u);
      const double strength = member(material.extensions.at("KHR_materials_emissive_strength"), "emissiveStrength").GetNumberAsDouble();
      EXPECT_NEAR(material.emissiveFactor[0] * strength, 5, 1e-12);
      EXPECT_NEAR(material.emissiveFactor[2] * strength, 4, 1e-12);
    } else {
      EXPECT_FALSE(material.extensions.count("KHR_materials_emissive_strength")) << material.name;
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{"white (lightmap 0)", "white (lightmap 1)", "checker (lightmap 0)", "lamp (lightmap 0) (emitting)"}))
      << "the two checker groups share a name";
  // Distinct corners: floor 3 + 3 (one per atlas), wall 4, back wall 4, lamp 4, step 4 + 2 (corner
  // 0 shared, corner 3 split at the seam).
  EXPECT_EQ(expectedVertices.size(), 24u);
  EXPECT_EQ(vertices, 24u);
  EXPECT_EQ(written->vertices, 24u);
  EXPECT_EQ(written->triangles, 2u + 2 + 2 + 2 + 3);
  EXPECT_NEAR(exportedArea, area, 1e-6 * area);

  // The Khronos validator finds nothing wrong (LAMBERT_lightmap is an extension it does not know).
  if (const std::string skip = testing::gltfValidatorSkipReason(LAMBERT_SOURCE_DIR); !skip.empty()) GTEST_SKIP() << skip;
  testing::CommandResult report = testing::validateGlb(LAMBERT_SOURCE_DIR, path);
  EXPECT_EQ(report.exitCode, 0) << report.output;
}

// RGBM decoded by its formula, written out here: E' = S · (t/255) · (a/255), within the bound the
// 8-bit rounding allows, over six decades; texels a thousandth of S, which linear 8 bits (S/255
// a step) would round to 0 or one step, within 2%.
TEST(LightmapExportTest, RgbmRoundTripsWithinItsQuantisation) {
  Image image;
  image.width = 40;
  image.height = 30;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double e = 100 * std::pow(10.0, -6.0 * (y * image.width + x) / (image.width * image.height));  // 100 .. 1e-4 W/m²
      image.pixels.push_back({e, e * (0.3 + 0.7 * (x % 3) / 2.0), (x + y) % 5 == 0 ? 0.0 : e * 0.05});
    }
  const double scale = lightmapScale(image);
  EXPECT_EQ(scale, 100);
  const std::vector<std::uint8_t> rgbm = encodeRgbm(image, scale);
  ASSERT_EQ(rgbm.size(), 4 * image.pixels.size());
  std::size_t darkTexels = 0;
  for (std::size_t p = 0; p < image.pixels.size(); ++p) {
    const Rgb& e = image.pixels[p];
    const double bound = 0.5 / 255 * (e.maxComponent() + scale / 255);
    for (int c = 0; c < 3; ++c) {
      const double decoded = scale * (rgbm[4 * p + static_cast<std::size_t>(c)] / 255.0) * (rgbm[4 * p + 3] / 255.0);
      EXPECT_NEAR(decoded, e[c], bound + 1e-15) << p << " " << c;
      EXPECT_NEAR(decodeRgbm(&rgbm[4 * p], scale)[c], decoded, 1e-12 * scale);
    }
    if (e.r >= scale / 2000 && e.r <= scale / 1000) {
      ++darkTexels;
      EXPECT_LT(std::fabs(scale * (rgbm[4 * p] / 255.0) * (rgbm[4 * p + 3] / 255.0) - e.r), 0.02 * e.r) << p;
    }
  }
  EXPECT_GT(darkTexels, 50u);
  // The brightest texel uses the whole range; black is all zero.
  EXPECT_EQ(rgbm[3], 255);
  EXPECT_EQ(rgbm[0], 255);
}

// Each file of an export holds the lightmap: the EXR within half precision, and the glb's atlas
// images exactly what asCarriedByGlb gives (what `solve --image` draws), which is the irradiance
// within RGBM's rounding. A non-finite texel is written as 0 with a warning.
TEST(LightmapExportTest, ExrAndGlbHoldTheIrradianceAndImageDrawsWhatTheGlbCarries) {
  Fixture fixture;
  fixture.baked.irradiance[1].pixels[3].g = std::nan("");
  const std::filesystem::path dir = testing::scratchDirectory("lightmap-export", "files");
  WarningCapture warnings;
  Result<LightmapExport> written = writeLightmaps((dir / "scene.glb").string(), fixture.scene, fixture.baked);
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_EQ(written->repairedTexels, 1u);
  EXPECT_EQ(warnings.count("were not a finite irradiance"), 1);
  const BakedLightmaps carried = asCarriedByGlb(fixture.baked);
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warn, (dir / "scene.glb").string())) << error;
  for (int k = 0; k < 2; ++k) {
    Result<Image> exr = readExr(written->atlases[static_cast<std::size_t>(k)].exr);
    ASSERT_TRUE(exr.ok()) << exr.error().message;
    ASSERT_EQ(exr->width, kAtlasSize);
    ASSERT_EQ(exr->height, kAtlasSize);
    // The atlas's image in the glb, by its name.
    const auto image = std::find_if(model.images.begin(), model.images.end(),
                                    [&](const tinygltf::Image& i) { return i.name == "scene-lightmap-" + std::to_string(k); });
    ASSERT_NE(image, model.images.end());
    const double scale = written->atlases[static_cast<std::size_t>(k)].scale;
    for (int y = 0; y < kAtlasSize; ++y)
      for (int x = 0; x < kAtlasSize; ++x) {
        Rgb expected = patternAt(k, x, y);
        if (k == 1 && y == 0 && x == 3) expected.g = 0;
        const std::size_t p = static_cast<std::size_t>(y * kAtlasSize + x);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(exr->pixels[p][c], expected[c], std::ldexp(expected[c], -11)) << k << " " << x << ", " << y;
          const double rgbm = scale * (image->image[4 * p + static_cast<std::size_t>(c)] / 255.0) * (image->image[4 * p + 3] / 255.0);
          EXPECT_NEAR(rgbm, expected[c], 0.5 / 255 * (expected.maxComponent() + scale / 255) + 1e-12);
          EXPECT_NEAR(carried.irradiance[static_cast<std::size_t>(k)].pixels[p][c], rgbm, 1e-12 * scale) << k << " " << x << ", " << y;
        }
      }
  }
  // Only what is asked for.
  const std::filesystem::path only = testing::scratchDirectory("lightmap-export", "glb-only");
  Result<LightmapExport> glbOnly = writeLightmaps((only / "scene.glb").string(), fixture.scene, fixture.baked, {.exr = false});
  ASSERT_TRUE(glbOnly.ok()) << glbOnly.error().message;
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(only), std::filesystem::directory_iterator()), 1);
  EXPECT_TRUE(glbOnly->atlases[0].exr.empty());
}

// A failed write leaves none of the export's files: the glb's place is taken by a directory, so
// its rename fails after the lightmaps were written, and they are removed again.
TEST(LightmapExportTest, AFailedExportLeavesNoFiles) {
  Fixture fixture;
  const std::filesystem::path dir = testing::scratchDirectory("lightmap-export", "atomic");
  std::filesystem::create_directories(dir / "scene.glb" / "occupied");
  Result<LightmapExport> written = writeLightmaps((dir / "scene.glb").string(), fixture.scene, fixture.baked);
  ASSERT_FALSE(written.ok());
  EXPECT_TRUE(testing::contains(written.error().message, (dir / "scene.glb").string())) << written.error().message;
  EXPECT_FALSE(testing::hasTemporaryFiles(dir));
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) left.push_back(entry.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"scene.glb"}) << "only the directory that was there";

  // Lightmaps of another scene (a surface more) are refused before anything is written.
  fixture.scene.surfaces.push_back(fixture.scene.surfaces[1]);
  const std::filesystem::path other = testing::scratchDirectory("lightmap-export", "mismatch");
  Result<LightmapExport> refused = writeLightmaps((other / "scene.glb").string(), fixture.scene, fixture.baked);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(testing::contains(refused.error().message, "do not match the scene")) << refused.error().message;
  EXPECT_TRUE(std::filesystem::is_empty(other));
}

// Faces as loaders may leave them: one that repeats a corner (its fan's triangle of two corners is
// not drawn, glTF validators call it degenerate) and a surface of no area (collinear corners: its
// vertices take a unit normal all the same). The file validates.
TEST(LightmapExportTest, DegenerateFacesGiveValidTrianglesAndNormals) {
  Fixture fixture;
  Surface repeated{"repeated", {{0, 0, 0}, {0, 0, 100}, {100, 0, 100}, {100, 0, 0}}, 0, {}, {{0, 1, 1, 2, 3}}};
  Surface line{"line", {{0, 500, 0}, {100, 500, 0}, {200, 500, 0}}, 0, {}};
  fixture.scene.surfaces = {repeated, line};
  fixture.baked.uvs.uv = {{std::vector<Uv>(5, texelCentre(2, 2))}, {{texelCentre(4, 4), texelCentre(5, 4), texelCentre(6, 4)}}};
  fixture.baked.uvs.uv[0][0][2] = texelCentre(3, 3);  // the repeated corner with a coordinate of its own
  fixture.baked.uvs.atlas = {{0}, {0}};
  const std::filesystem::path dir = testing::scratchDirectory("lightmap-export", "degenerate");
  const std::string path = (dir / "degenerate.glb").string();
  Result<LightmapExport> written = writeLightmaps(path, fixture.scene, fixture.baked, {.exr = false});
  ASSERT_TRUE(written.ok()) << written.error().message;
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warn, path)) << error;
  ASSERT_EQ(model.meshes.at(0).primitives.size(), 1u);
  const tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
  const std::vector<std::uint32_t> triangles = indices(model, primitive.indices);
  // The repeated face fans into (0,1,1') (1' the repeated corner with its own coordinate, so
  // drawn), (0,1',2), (0,2,3); the line into one triangle of no area.
  EXPECT_EQ(triangles.size(), 3u * 4);
  for (std::size_t t = 0; t < triangles.size(); t += 3)
    EXPECT_TRUE(triangles[t] != triangles[t + 1] && triangles[t + 1] != triangles[t + 2] && triangles[t] != triangles[t + 2]);
  const std::vector<float> normal = floats(model, primitive.attributes.at("NORMAL"));
  for (std::size_t v = 0; v < normal.size(); v += 3) EXPECT_NEAR(std::hypot(normal[v], normal[v + 1], normal[v + 2]), 1, 1e-6) << v;

  // The same corner twice with one coordinate is one vertex: its fan triangle is dropped.
  fixture.baked.uvs.uv[0][0][2] = fixture.baked.uvs.uv[0][0][1];
  written = writeLightmaps(path, fixture.scene, fixture.baked, {.exr = false});
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_EQ(written->triangles, 3u);

  if (const std::string skip = testing::gltfValidatorSkipReason(LAMBERT_SOURCE_DIR); !skip.empty()) GTEST_SKIP() << skip;
  testing::CommandResult report = testing::validateGlb(LAMBERT_SOURCE_DIR, path);
  EXPECT_EQ(report.exitCode, 0) << report.output;
}

TEST(LightmapExportTest, FilesAreNamedAfterTheGlb) {
  EXPECT_EQ(lightmapExrPath("out/room.glb", 0), "out/room-lightmap-0.exr");
  EXPECT_EQ(lightmapExrPath("room.glb", 12), "room-lightmap-12.exr");
}

}  // namespace
}  // namespace lambert
