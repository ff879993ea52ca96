// The .glb export, read back with tinygltf: geometry in metres, unlit materials, and COLOR_0 such
// that base colour × COLOR_0 is the solved radiance (× exposure) at every vertex.
#include "lambert/io/gltf_export.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>

#include "lambert/engine/radiosity.h"
#include "lambert/io/png.h"
#include "lambert/scene/builtin.h"
#include "lambert/load/scene_file.h"
#include "tests/support/emissive_strip.h"
#include "tests/support/engines.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

std::vector<float> floats(const tinygltf::Model& model, int accessorIndex) {
  const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(accessorIndex));
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  EXPECT_EQ(view.byteOffset % 4, 0u);
  std::vector<float> values(a.count * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type))));
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
  auto engine = testing::solved(cornellBox(), testing::uniformOptions(300));
  ASSERT_TRUE(engine);
  const SolutionView& solution = engine->solution();
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
  auto engine = testing::solved(*scene, testing::uniformOptions(1500), scene->lights);
  ASSERT_TRUE(engine);
  const SolutionView& solution = engine->solution();
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

// --- Texture coordinates through meshing and export -------------------------------------------
// Every exported textured vertex is looked up in the input's own triangles (read from the input
// here, not through lambert's loaders), and the input's UVs are interpolated there by barycentric
// weights from sub-triangle areas: the exported UV must be that value.

// One input triangle in scene units with its corners' UVs.
struct UvTriangle {
  std::array<Vec3, 3> p;
  std::array<Uv, 3> uv;
};

// The input's UV at q on a triangle lying in q's plane (normal parallel to `normal`, either way:
// a two-sided face's back has the front's UVs) and holding q, or nothing.
std::optional<Uv> inputUvAt(const std::vector<UvTriangle>& input, const Vec3& q, const Vec3& normal) {
  for (const UvTriangle& t : input) {
    const Vec3 n = cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
    const double twiceArea = length(n);
    if (std::fabs(dot(n / twiceArea, normalize(normal))) < 0.999) continue;
    const double extent = std::fmax(length(t.p[1] - t.p[0]), length(t.p[2] - t.p[0]));
    if (std::fabs(dot(q - t.p[0], n / twiceArea)) > 1e-5 * extent) continue;
    // Signed areas of the sub-triangles opposite each corner, over the whole.
    std::array<double, 3> w;
    for (int k = 0; k < 3; ++k) w[k] = dot(cross(t.p[(k + 1) % 3] - q, t.p[(k + 2) % 3] - q), n) / (twiceArea * twiceArea);
    if (std::fmin(w[0], std::fmin(w[1], w[2])) < -1e-6) continue;
    return Uv{w[0] * t.uv[0].u + w[1] * t.uv[1].u + w[2] * t.uv[2].u, w[0] * t.uv[0].v + w[1] * t.uv[1].v + w[2] * t.uv[2].v};
  }
  return std::nullopt;
}

// The exported model's textured vertices carry the input's UVs at their points; returns how many.
std::size_t expectInputUvs(const tinygltf::Model& model, const std::vector<UvTriangle>& input, double metresPerUnit, const std::string& what) {
  std::size_t checked = 0, wrong = 0;
  for (const tinygltf::Primitive& primitive : model.meshes.at(0).primitives) {
    if (!primitive.attributes.count("TEXCOORD_0")) continue;
    const std::vector<float> position = floats(model, primitive.attributes.at("POSITION"));
    const std::vector<float> normal = floats(model, primitive.attributes.at("NORMAL"));
    const std::vector<float> uv = floats(model, primitive.attributes.at("TEXCOORD_0"));
    EXPECT_EQ(uv.size() / 2, position.size() / 3) << what;
    for (std::size_t v = 0; v < position.size() / 3 && v < uv.size() / 2; ++v) {
      const Vec3 q = Vec3{position[3 * v], position[3 * v + 1], position[3 * v + 2]} / metresPerUnit;
      const std::optional<Uv> expected = inputUvAt(input, q, {normal[3 * v], normal[3 * v + 1], normal[3 * v + 2]});
      ++checked;
      if (!expected) {
        ADD_FAILURE() << what << ": exported vertex (" << q.x << ", " << q.y << ", " << q.z << ") lies on no textured input triangle";
        continue;
      }
      const bool same = std::fabs(uv[2 * v] - expected->u) <= 1e-5 && std::fabs(uv[2 * v + 1] - expected->v) <= 1e-5;
      if (!same && ++wrong <= 5)
        ADD_FAILURE() << what << ": vertex (" << q.x << ", " << q.y << ", " << q.z << ") exported UV (" << uv[2 * v] << ", " << uv[2 * v + 1]
                      << "), the input's there (" << expected->u << ", " << expected->v << ")";
    }
  }
  EXPECT_EQ(wrong, 0u) << what << ": of " << checked;
  return checked;
}

std::unique_ptr<Radiosity> solvedWith(const Scene& scene, MeshStrategy strategy, std::size_t uniformPatches, double linkError) {
  RadiosityOptions options = testing::uniformOptions(uniformPatches);
  options.meshing = strategy;
  options.hierarchical.links.linkError = linkError;
  return testing::solved(scene, options);
}

const char* strategyName(MeshStrategy strategy) {
  return strategy == MeshStrategy::Hierarchical ? "hierarchical" : strategy == MeshStrategy::Uniform ? "uniform" : "adaptive";
}

// Blender's room (glTF): its floor is two triangles of one quad, and the export must give the
// whole floor the checker's UVs, the first triangle as much as the second.
TEST(GltfExportTest, ExportedUvsAreTheGltfInputsAtTheSamePoints) {
  const std::string path = std::string(LAMBERT_SOURCE_DIR) + "/tests/data/blender_room.glb";
  // The input's textured triangles, read with tinygltf and placed by their nodes (scale and
  // translation: the file's textured node has no rotation).
  tinygltf::TinyGLTF reader;
  tinygltf::Model input;
  std::string error, warn;
  ASSERT_TRUE(reader.LoadBinaryFromFile(&input, &error, &warn, path)) << error;
  std::vector<UvTriangle> triangles;
  for (const tinygltf::Node& node : input.nodes) {
    if (node.mesh < 0) continue;
    for (const tinygltf::Primitive& primitive : input.meshes.at(static_cast<std::size_t>(node.mesh)).primitives) {
      if (input.materials.at(static_cast<std::size_t>(primitive.material)).pbrMetallicRoughness.baseColorTexture.index < 0) continue;
      ASSERT_TRUE(node.rotation.empty()) << node.name;
      const Vec3 scale = node.scale.empty() ? Vec3{1, 1, 1} : Vec3{node.scale[0], node.scale[1], node.scale[2]};
      const Vec3 offset = node.translation.empty() ? Vec3{} : Vec3{node.translation[0], node.translation[1], node.translation[2]};
      const std::vector<float> xyz = floats(input, primitive.attributes.at("POSITION"));
      const std::vector<float> uv = floats(input, primitive.attributes.at("TEXCOORD_0"));
      const tinygltf::Accessor& a = input.accessors.at(static_cast<std::size_t>(primitive.indices));
      ASSERT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
      const tinygltf::BufferView& view = input.bufferViews.at(static_cast<std::size_t>(a.bufferView));
      std::vector<std::uint16_t> index(a.count);
      std::memcpy(index.data(), input.buffers[0].data.data() + view.byteOffset + a.byteOffset, index.size() * 2);
      for (std::size_t t = 0; t + 2 < index.size(); t += 3) {
        UvTriangle triangle;
        for (int k = 0; k < 3; ++k) {
          const std::size_t i = index[t + static_cast<std::size_t>(k)];
          triangle.p[static_cast<std::size_t>(k)] = Vec3{xyz[3 * i] * scale.x, xyz[3 * i + 1] * scale.y, xyz[3 * i + 2] * scale.z} + offset;
          triangle.uv[static_cast<std::size_t>(k)] = {uv[2 * i], uv[2 * i + 1]};
        }
        triangles.push_back(triangle);
      }
    }
  }
  ASSERT_EQ(triangles.size(), 2u);  // the floor

  Result<Scene> scene = loadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  // Only the floor (both sides) and the ceiling panel lighting it, for time: the walls, block and
  // sphere have no texture.
  {
    std::vector<Surface> kept;
    std::vector<int> newIndex(scene->surfaces.size(), -1);
    for (std::size_t i = 0; i < scene->surfaces.size(); ++i) {
      const Surface& surface = scene->surfaces[i];
      if (!scene->materials.at(static_cast<std::size_t>(surface.material)).texture && !(surface.emittedRadiance.maxComponent() > 0)) continue;
      newIndex[i] = static_cast<int>(kept.size());
      kept.push_back(surface);
    }
    for (Surface& surface : kept)
      if (surface.twin >= 0) surface.twin = newIndex[static_cast<std::size_t>(surface.twin)];
    scene->surfaces = std::move(kept);
  }
  // The adaptive quad-tree takes single quads only, and a glTF file holds triangles.
  for (MeshStrategy strategy : {MeshStrategy::Hierarchical, MeshStrategy::Uniform}) {
    std::unique_ptr<Radiosity> engine = solvedWith(*scene, strategy, 2000, 2e-5);  // leaves finer than the checker's squares
    ASSERT_TRUE(engine);
    const SolutionView& solution = engine->solution();
    const tinygltf::Model model = exportAndRead(solution, {}, std::string("room-uv-") + strategyName(strategy));
    EXPECT_GT(expectInputUvs(model, triangles, scene->metresPerUnit, strategyName(strategy)), 50u);

    // What lambert draws: a patch of the floor inside one checker square (its centroid's, by the
    // input's UVs), every corner more than half a texel from the square's edges, so that the
    // bilinear filter reads that square's texels only, has that square's albedo, on both
    // triangles. A patch whose UVs were lost reads one place of the texture all over the floor.
    // (The hierarchical leaves, the default mesh: the uniform one at any size this test can
    // afford has a corner of every patch on a square's edge. Both take albedos through the
    // corner UVs checked above.)
    if (strategy != MeshStrategy::Hierarchical) continue;
    const Material& floor = scene->materials.at(static_cast<std::size_t>(solution.scene().surfaces.at(0).material));
    ASSERT_TRUE(floor.texture) << "the first surface is the floor";
    const Mesh& mesh = solution.vertexMesh();
    const double squares = 8, halfTexel = 0.5 * squares / floor.texture->width;  // in squares
    std::array<std::array<int, 2>, 2> inSquare{};  // per input triangle: patches of dark, light squares
    for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
      const Surface& surface = solution.scene().surfaces[mesh.patches[p].surface];
      if (surface.material != solution.scene().surfaces[0].material) continue;
      const std::optional<Uv> centre = inputUvAt(triangles, mesh.patches[p].centroid, mesh.patches[p].normal);
      ASSERT_TRUE(centre);
      const double su = std::floor(centre->u * squares), sv = std::floor(centre->v * squares);
      bool deepInside = true;
      for (const Vec3& corner : mesh.corners(p)) {
        const std::optional<Uv> uv = inputUvAt(triangles, corner, mesh.patches[p].normal);
        ASSERT_TRUE(uv);
        const double du = uv->u * squares - su, dv = uv->v * squares - sv;  // within the square: (0, 1)
        deepInside = deepInside && std::fmin(std::fmin(du, 1 - du), std::fmin(dv, 1 - dv)) > halfTexel * 1.01;
      }
      if (!deepInside) continue;
      const Rgb texel = floor.texture->sample((su + 0.5) / squares, (sv + 0.5) / squares);
      const double expected = floor.albedo.g * texel.g;
      EXPECT_NEAR(solution.vertexMeshAlbedo()[p].g, expected, 1e-6 * expected) << strategyName(strategy) << " patch " << p;
      std::size_t triangle = 0;
      while (triangle < 2 && !inputUvAt({triangles[triangle]}, mesh.patches[p].centroid, mesh.patches[p].normal)) ++triangle;
      ASSERT_LT(triangle, 2u);
      ++inSquare[triangle][texel.g > floor.texture->mean.g];
    }
    for (std::size_t t = 0; t < 2; ++t)
      for (int light = 0; light < 2; ++light) EXPECT_GE(inSquare[t][light], 3) << strategyName(strategy) << " triangle " << t << (light ? " light" : " dark");
  }
}

// Writes a 4×4 texture whose texels all differ, so that a wrong UV reads a wrong albedo.
void writeTestTexture(const std::filesystem::path& path) {
  std::vector<std::uint8_t> rgb;
  for (int k = 0; k < 16; ++k)
    for (int c = 0; c < 3; ++c) rgb.push_back(static_cast<std::uint8_t>(20 + 12 * k + 3 * c));
  ASSERT_TRUE(writePng(path.string(), 4, 4, rgb).ok());
}

// Two textured quads that are not parallelograms, with UVs that are not affine over them (so a
// patch straddling a quad's fan diagonal needs each corner's own fan triangle), and a lamp.
struct QuadScene {
  std::array<std::array<Vec3, 4>, 2> quads = {{
      {{{0, 0, 0}, {0, 0, 1}, {1.2, 0, 1.1}, {1, 0, 0}}},             // floor, facing +y
      {{{-0.1, 0.1, 0}, {-0.1, 0.9, 0}, {-0.1, 1, 1}, {-0.1, 0.2, 1.2}}},  // wall, facing +x
  }};
  std::array<std::array<Uv, 4>, 2> uvs = {{
      {{{0, 0}, {0, 1}, {1, 1}, {1, 0}}},
      {{{0.1, 0.2}, {0.3, 0.9}, {1.4, 1.0}, {1.0, -0.2}}},
  }};
  std::array<Vec3, 4> lamp = {{{0, 1.2, 0}, {1, 1.2, 0}, {1, 1.2, 1}, {0, 1.2, 1}}};  // facing −y

  // Each quad as its fan's two triangles, UVs linear over each.
  std::vector<UvTriangle> triangles() const {
    std::vector<UvTriangle> out;
    for (std::size_t q = 0; q < quads.size(); ++q)
      for (std::size_t k : {1, 2}) out.push_back({{quads[q][0], quads[q][k], quads[q][k + 1]}, {uvs[q][0], uvs[q][k], uvs[q][k + 1]}});
    return out;
  }
};

void expectInputUvsForEveryStrategy(const std::string& path, const QuadScene& quads, const std::string& what) {
  Result<Scene> scene = loadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (MeshStrategy strategy : {MeshStrategy::Hierarchical, MeshStrategy::Uniform, MeshStrategy::Adaptive}) {
    std::unique_ptr<Radiosity> engine = solvedWith(*scene, strategy, 300, 2e-3);
    ASSERT_TRUE(engine);
    const tinygltf::Model model = exportAndRead(engine->solution(), {}, what + "-uv-" + strategyName(strategy));
    EXPECT_GT(expectInputUvs(model, quads.triangles(), scene->metresPerUnit, what + " " + strategyName(strategy)), 20u);
  }
}

// OBJ: `vt` per face corner (OBJ's v runs up the image, lambert's down it).
TEST(GltfExportTest, ExportedUvsAreTheObjInputsAtTheSamePoints) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf-export", "obj-uv-input");
  writeTestTexture(dir / "texels.png");
  std::ofstream(dir / "quads.mtl") << "newmtl textured\nKd 0.9 0.9 0.9\nmap_Kd texels.png\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n";
  const QuadScene quads;
  std::ofstream obj(dir / "quads.obj");
  obj << "mtllib quads.mtl\nusemtl textured\n";
  int vertex = 1;
  for (std::size_t q = 0; q < quads.quads.size(); ++q) {
    for (const Vec3& v : quads.quads[q]) obj << "v " << v.x << " " << v.y << " " << v.z << "\n";
    for (const Uv& uv : quads.uvs[q]) obj << "vt " << uv.u << " " << 1 - uv.v << "\n";
    obj << "f";
    for (int k = 0; k < 4; ++k, ++vertex) obj << " " << vertex << "/" << vertex;
    obj << "\n";
  }
  obj << "usemtl lamp\n";
  for (const Vec3& v : quads.lamp) obj << "v " << v.x << " " << v.y << " " << v.z << "\n";
  obj << "f " << vertex << " " << vertex + 1 << " " << vertex + 2 << " " << vertex + 3 << "\n";
  obj.close();
  expectInputUvsForEveryStrategy((dir / "quads.obj").string(), quads, "obj");
}

// A scene file's inline polygons with "uvs".
TEST(GltfExportTest, ExportedUvsAreTheSceneFilePolygonsAtTheSamePoints) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf-export", "json-uv-input");
  writeTestTexture(dir / "texels.png");
  const QuadScene quads;
  std::ofstream json(dir / "quads.json");
  json << R"({"materials": [{"name": "textured", "albedo": [0.9, 0.9, 0.9], "texture": "texels.png"},)"
       << R"( {"name": "lamp", "albedo": [0, 0, 0], "emittedRadiance": [5, 5, 5]}], "surfaces": [)";
  auto polygon = [&](const std::array<Vec3, 4>& vertices) {
    json << "[";
    for (std::size_t k = 0; k < 4; ++k) json << (k ? ", [" : "[") << vertices[k].x << ", " << vertices[k].y << ", " << vertices[k].z << "]";
    json << "]";
  };
  for (std::size_t q = 0; q < quads.quads.size(); ++q) {
    json << R"({"material": "textured", "vertices": )";
    polygon(quads.quads[q]);
    json << R"(, "uvs": [)";
    for (std::size_t k = 0; k < 4; ++k) json << (k ? ", [" : "[") << quads.uvs[q][k].u << ", " << quads.uvs[q][k].v << "]";
    json << "]}, ";
  }
  json << R"({"material": "lamp", "vertices": )";
  polygon(quads.lamp);
  json << "}]}";
  json.close();
  expectInputUvsForEveryStrategy((dir / "quads.json").string(), quads, "scene-file");
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
  auto engine = testing::solved(*scene, testing::uniformOptions(256));
  ASSERT_TRUE(engine);
  const tinygltf::Model model = exportAndRead(engine->solution(), {}, "emission-texture");
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
