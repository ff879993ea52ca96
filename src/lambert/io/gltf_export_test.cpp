// The .glb export, read back with tinygltf: geometry in metres, unlit materials, and COLOR_0 such
// that base colour × COLOR_0 is the solved radiance (× exposure) at every vertex.
#include "lambert/io/gltf_export.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "lambert/engine/radiosity.h"
#include "lambert/scene/builtin.h"
#include "lambert/scene/scene_file.h"
#include "tests/support/emissive_strip.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

std::vector<float> floats(const tinygltf::Model& model, int accessorIndex) {
  const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(accessorIndex));
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  EXPECT_EQ(view.byteOffset % 4, 0u);
  std::vector<float> values(a.count * 3);
  std::memcpy(values.data(), model.buffers[0].data.data() + view.byteOffset + a.byteOffset, values.size() * sizeof(float));
  return values;
}

std::vector<std::uint32_t> indices(const tinygltf::Model& model, int accessorIndex) {
  const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(accessorIndex));
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  std::vector<std::uint32_t> values(a.count);
  std::memcpy(values.data(), model.buffers[0].data.data() + view.byteOffset + a.byteOffset, values.size() * 4);
  return values;
}

tinygltf::Model exportAndRead(const SolutionView& solution, const GltfExportOptions& options, const std::string& name) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf-export", name);
  const std::string path = (dir / "scene.glb").string();
  EXPECT_TRUE(writeGlb(path, solution, options).ok());
  EXPECT_FALSE(testing::hasTemporaryFiles(dir));
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warn;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warn, path)) << error;
  return model;
}

TEST(GltfExportTest, BaseColourTimesColourIsTheSolvedRadiance) {
  RadiosityOptions options;
  options.uniform.targetPatches = 300;
  options.formFactors.showProgress = false;
  auto engine = Radiosity::create(cornellBox(), options);
  ASSERT_TRUE(engine.ok());
  ASSERT_TRUE((*engine)->solve().ok());
  const SolutionView& solution = (*engine)->solution();
  double meshArea = 0;
  for (const Patch& p : solution.vertexMesh().patches) meshArea += p.area;

  for (GltfBake bake : {GltfBake::Irradiance, GltfBake::Radiance}) {
    const double exposure = 1.5;
    tinygltf::Model model = exportAndRead(solution, {bake, exposure}, bake == GltfBake::Irradiance ? "irradiance" : "radiance");
    ASSERT_EQ(model.meshes.size(), 1u);
    EXPECT_EQ(model.extensionsUsed, std::vector<std::string>{"KHR_materials_unlit"});
    double area = 0;
    int emitters = 0;
    for (const tinygltf::Primitive& primitive : model.meshes[0].primitives) {
      const tinygltf::Material& material = model.materials.at(static_cast<std::size_t>(primitive.material));
      EXPECT_TRUE(material.extensions.count("KHR_materials_unlit")) << material.name;
      const bool emitting = material.name.find("(emitting)") != std::string::npos;
      emitters += emitting;
      const auto& base = material.pbrMetallicRoughness.baseColorFactor;
      if (bake == GltfBake::Radiance || emitting) {
        EXPECT_EQ(base, (std::vector<double>{1, 1, 1, 1}));
      }

      const std::vector<float> position = floats(model, primitive.attributes.at("POSITION"));
      const std::vector<float> colour = floats(model, primitive.attributes.at("COLOR_0"));
      const std::vector<float> radiance = floats(model, primitive.attributes.at("_RADIANCE"));
      const std::vector<float> normal = floats(model, primitive.attributes.at("NORMAL"));
      const tinygltf::Accessor& positions = model.accessors.at(static_cast<std::size_t>(primitive.attributes.at("POSITION")));
      ASSERT_EQ(positions.minValues.size(), 3u);  // glTF requires POSITION bounds
      for (std::size_t v = 0; v < position.size() / 3; ++v) {
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(position[3 * v + c], positions.minValues[c]);
          EXPECT_LE(position[3 * v + c], positions.maxValues[c]);
          // base × COLOR_0 = L × 2^exposure, to float precision, where COLOR_0 (in [0, 1], as
          // glTF requires) is not clipped; the exposure here clips the light's brightest parts.
          EXPECT_LE(colour[3 * v + c], 1.0f);
          const double expected = std::fmin(radiance[3 * v + c] * std::exp2(exposure), base[c]);
          EXPECT_NEAR(base[c] * colour[3 * v + c], expected, 1e-5 * expected + 1e-9) << material.name << " vertex " << v;
        }
        EXPECT_NEAR(std::hypot(normal[3 * v], normal[3 * v + 1], normal[3 * v + 2]), 1, 1e-5);
      }
      const std::vector<std::uint32_t> triangles = indices(model, primitive.indices);
      ASSERT_EQ(triangles.size() % 3, 0u);
      for (std::size_t t = 0; t < triangles.size(); t += 3) {
        auto at = [&](std::uint32_t i) { return Vec3{position[3 * i], position[3 * i + 1], position[3 * i + 2]}; };
        area += 0.5 * length(cross(at(triangles[t + 1]) - at(triangles[t]), at(triangles[t + 2]) - at(triangles[t])));
      }
    }
    EXPECT_EQ(emitters, 1);
    // Positions are in metres: the mesh's mm² × 1e-6.
    EXPECT_NEAR(area, meshArea * 1e-6, 1e-5 * meshArea * 1e-6);
  }
}

// What a glTF validator checks of the buffers: every view inside the buffer and 4-byte aligned,
// every accessor inside its view, POSITION's min and max its data's, indices in range.
void expectValidBuffers(const tinygltf::Model& model) {
  ASSERT_EQ(model.buffers.size(), 1u);
  for (const tinygltf::BufferView& view : model.bufferViews) {
    EXPECT_EQ(view.byteOffset % 4, 0u);
    EXPECT_LE(view.byteOffset + view.byteLength, model.buffers[0].data.size());
  }
  for (const tinygltf::Accessor& a : model.accessors) {
    const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
    const std::size_t size = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType))) *
                             static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
    EXPECT_LE(a.byteOffset + a.count * size, view.byteLength);
  }
  for (const tinygltf::Mesh& mesh : model.meshes)
    for (const tinygltf::Primitive& primitive : mesh.primitives) {
      const tinygltf::Accessor& position = model.accessors.at(static_cast<std::size_t>(primitive.attributes.at("POSITION")));
      const std::vector<float> xyz = floats(model, primitive.attributes.at("POSITION"));
      ASSERT_EQ(position.minValues.size(), 3u);
      for (int c = 0; c < 3; ++c) {
        float lo = INFINITY, hi = -INFINITY;
        for (std::size_t k = static_cast<std::size_t>(c); k < xyz.size(); k += 3) lo = std::fmin(lo, xyz[k]), hi = std::fmax(hi, xyz[k]);
        EXPECT_EQ(position.minValues[c], lo);
        EXPECT_EQ(position.maxValues[c], hi);
      }
      for (std::uint32_t i : indices(model, primitive.indices)) EXPECT_LT(i, position.count);
      for (const auto& [name, accessor] : primitive.attributes) EXPECT_EQ(model.accessors.at(static_cast<std::size_t>(accessor)).count, position.count) << name;
    }
}

// Blender's room, textured and two-sided, solved and exported: the floor keeps its checker as a
// texture over UVs, the file validates, and lambert reads it back with the same area and camera.
TEST(GltfExportTest, TexturedTwoSidedSceneRoundTrips) {
  Result<Scene> scene = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/tests/data/blender_room.glb");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  RadiosityOptions options;
  options.uniform.targetPatches = 1500;
  options.formFactors.showProgress = false;
  auto engine = Radiosity::create(*scene, options);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  (*engine)->setLights(scene->lights);
  ASSERT_TRUE((*engine)->solve().ok());
  const SolutionView& solution = (*engine)->solution();
  const std::filesystem::path dir = testing::scratchDirectory("gltf-export", "textured");
  const std::string path = (dir / "room.glb").string();
  ASSERT_TRUE(writeGlb(path, solution).ok());
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warn, path)) << error;
  expectValidBuffers(model);

  int textured = 0;
  for (const tinygltf::Primitive& primitive : model.meshes[0].primitives) {
    const tinygltf::Material& material = model.materials.at(static_cast<std::size_t>(primitive.material));
    if (material.pbrMetallicRoughness.baseColorTexture.index < 0) {
      EXPECT_FALSE(primitive.attributes.count("TEXCOORD_0"));
      continue;
    }
    ++textured;
    EXPECT_EQ(material.name, "floor");
    ASSERT_TRUE(primitive.attributes.count("TEXCOORD_0"));
    const tinygltf::Image& image = model.images.at(static_cast<std::size_t>(
        model.textures.at(static_cast<std::size_t>(material.pbrMetallicRoughness.baseColorTexture.index)).source));
    // The checker comes back texel for texel: 0.8 and 0.2 sRGB, 204 and 51.
    ASSERT_EQ(image.width, 64);
    ASSERT_EQ(image.component, 4);
    for (std::size_t t = 0; t < image.image.size(); t += 4) EXPECT_TRUE(image.image[t] == 204 || image.image[t] == 51) << t;
  }
  EXPECT_EQ(textured, 1);

  // Read back by lambert: the exported sides are one-sided triangles, as many square metres.
  Result<Scene> back = loadScene(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  double area = 0, backArea = 0;
  for (const Surface& s : scene->surfaces) area += surfaceArea(s);
  for (const Surface& s : back->surfaces) backArea += surfaceArea(s);
  EXPECT_NEAR(backArea, area, 1e-4 * area);
  EXPECT_NEAR(length(back->camera.eye - scene->camera.eye), 0, 1e-5);
  const Vec3 forward = normalize(scene->camera.target - scene->camera.eye);
  EXPECT_NEAR(dot(normalize(back->camera.target - back->camera.eye), forward), 1, 1e-6);
  EXPECT_NEAR(back->camera.verticalFovDegrees, scene->camera.verticalFovDegrees, 1e-5);
}

// An emission texture black over half a material: the patches that emit nothing are exported as
// reflecting surfaces under the base colour texture, the rest as emitters (radiance over white).
TEST(GltfExportTest, PatchesAnEmissionTextureLeavesDarkKeepTheirBaseColourTexture) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf-export", "emission-texture");
  testing::writeHalfWhitePng(dir / "emit.png");
  const std::string path = (dir / "strip.json").string();
  std::ofstream(path) << R"({"materials": [{"name": "lamp", "albedo": [0.5, 0.5, 0.5], "texture": "emit.png",
      "emittedRadiance": [1, 1, 1], "emissionTexture": "emit.png"}], "surfaces": [
      {"material": "lamp", "vertices": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]], "uvs": [[0,1], [0.5,1], [0.5,0], [0,0]]},
      {"material": "lamp", "vertices": [[1,0,0], [2,0,0], [2,1,0], [1,1,0]], "uvs": [[0.5,1], [1,1], [1,0], [0.5,0]]}]})";
  Result<Scene> scene = loadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  RadiosityOptions options;
  options.uniform.targetPatches = 256;
  options.formFactors.showProgress = false;
  auto engine = Radiosity::create(*scene, options);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  ASSERT_TRUE((*engine)->solve().ok());
  const tinygltf::Model model = exportAndRead((*engine)->solution(), {}, "emission-texture");
  ASSERT_EQ(model.meshes.size(), 1u);
  double emittingArea = 0, texturedArea = 0;
  for (const tinygltf::Primitive& primitive : model.meshes[0].primitives) {
    const std::vector<float> xyz = floats(model, primitive.attributes.at("POSITION"));
    double area = 0;
    const std::vector<std::uint32_t> triangles = indices(model, primitive.indices);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
      auto at = [&](std::uint32_t v) { return Vec3{xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]}; };
      area += 0.5 * length(cross(at(triangles[t + 1]) - at(triangles[t]), at(triangles[t + 2]) - at(triangles[t])));
    }
    const tinygltf::Material& material = model.materials.at(static_cast<std::size_t>(primitive.material));
    if (material.name == "lamp (emitting)") {
      EXPECT_LT(material.pbrMetallicRoughness.baseColorTexture.index, 0);
      emittingArea += area;
    } else {
      EXPECT_EQ(material.name, "lamp");
      EXPECT_GE(material.pbrMetallicRoughness.baseColorTexture.index, 0);
      texturedArea += area;
    }
  }
  // The white half emits; patches touching the black half's edge (a column ~0.1 m wide) blend.
  EXPECT_NEAR(emittingArea + texturedArea, 2, 1e-5);
  EXPECT_GE(emittingArea, 1 - 1e-5);
  EXPECT_LT(emittingArea, 1.2);
}

}  // namespace
}  // namespace lambert
