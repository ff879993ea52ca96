// The .glb export, read back with tinygltf: geometry in metres, unlit materials, and COLOR_0 such
// that base colour × COLOR_0 is the solved radiance (× exposure) at every vertex.
#include "lambert/io/gltf_export.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>

#include "lambert/engine/radiosity.h"
#include "lambert/scene/builtin.h"
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
          // base × COLOR_0 = L × 2^exposure, to float precision.
          const double expected = radiance[3 * v + c] * std::exp2(exposure);
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

}  // namespace
}  // namespace lambert
