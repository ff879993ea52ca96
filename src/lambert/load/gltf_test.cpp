// The glTF loader against a file Blender's own exporter wrote (tests/data/blender_room.glb, from
// shared/samples; its README lists what was set in Blender), and against broken files.
#include "lambert/load/gltf.h"

#include "lambert/light/emission.h"
#include "lambert/mesh/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

#include "lambert/core/warning.h"
#include "lambert/load/scene_file.h"
#include "tests/support/emissive_strip.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

const std::string kBlenderRoom = std::string(LAMBERT_SOURCE_DIR) + "/tests/data/blender_room.glb";

const Light& lightNamed(const Scene& scene, const std::string& name) {
  for (const Light& light : scene.lights)
    if (light.name == name) return light;
  ADD_FAILURE() << "no light " << name;
  return scene.lights.front();
}

double areaOfMaterial(const Scene& scene, const std::string& material) {
  double area = 0;
  for (const Surface& s : scene.surfaces)
    if (scene.materials[s.material].name == material) area += surfaceArea(s);
  return area;
}

void expectNear(const Rgb& value, const Rgb& expected, double tolerance) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], expected[c], tolerance) << "channel " << c;
}

TEST(GltfTest, BlenderExportLoadsWithItsLightsMaterialsAndCamera) {
  WarningCapture warnings;
  Result<Scene> scene = loadScene(kBlenderRoom);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->name, "blender_room");
  EXPECT_EQ(scene->metresPerUnit, 1);  // glTF is in metres

  // Photometric to radiometric at 683 lm/W: Blender's 100 W point light is 100 / 4π W/sr.
  ASSERT_EQ(scene->lights.size(), 3u);
  const Light& point = lightNamed(*scene, "point");
  EXPECT_EQ(point.kind, LightKind::Point);
  expectNear(point.intensity, Rgb{1, 0.95, 0.9} * (100 / (4 * kPi)), 1e-4);
  EXPECT_NEAR(length(point.position - Vec3{-1.2, 2, 0.5}), 0, 1e-6);
  const Light& spot = lightNamed(*scene, "spot");
  EXPECT_EQ(spot.kind, LightKind::Spot);
  expectNear(spot.intensity, Rgb{0.8, 0.9, 1} * (200 / (4 * kPi)), 1e-4);
  EXPECT_NEAR(spot.coneAngleDegrees, 22.5, 1e-5);  // Blender's 45° spot size is the full angle
  EXPECT_NEAR(spot.falloffDegrees, 4.5, 1e-5);     // blend 0.2: inner cone 18°
  EXPECT_LT(spot.direction.y, -0.5);               // pointing down into the room
  const Light& sun = lightNamed(*scene, "sun");
  EXPECT_EQ(sun.kind, LightKind::Directional);
  expectNear(sun.irradiance, Rgb{1, 1, 0.95} * 3.0, 1e-6);  // 2049 lx / 683
  EXPECT_NEAR(length(sun.direction), 1, 1e-12);
  EXPECT_LT(sun.direction.y, 0);

  // Materials: factors, the checker's mean (its texels are 0.8 and 0.2 sRGB-encoded, 204 and 51,
  // in equal numbers: decoded, 0.6038 and 0.0331), emission × strength.
  auto decode = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
  const double checkerMean = (decode(204 / 255.0) + decode(51 / 255.0)) / 2;
  double panelPower = 0;
  for (std::size_t i = 0; i < scene->surfaces.size(); ++i) {
    const Surface& s = scene->surfaces[i];
    // Blender marks every material double-sided: each surface has its twin, back to back.
    ASSERT_GE(s.twin, 0);
    EXPECT_EQ(scene->surfaces[static_cast<std::size_t>(s.twin)].twin, static_cast<int>(i));
    const Surface& twin = scene->surfaces[static_cast<std::size_t>(s.twin)];
    EXPECT_NEAR(dot(polygonNormal(facePositions(s, s.faces[0])), polygonNormal(facePositions(twin, twin.faces[0]))), -1, 1e-9);
    if (static_cast<std::size_t>(s.twin) < i) continue;  // the back copies: counted once below
    const Material& m = scene->materials[s.material];
    EXPECT_TRUE(m.twoSided);
    if (m.name == "wall") expectNear(m.albedo, Rgb::gray(0.7), 1e-6);
    if (m.name == "red") expectNear(m.albedo, Rgb{0.6, 0.08, 0.06}, 1e-6);
    if (m.name == "floor") {
      expectNear(m.albedo, Rgb::gray(1), 1e-3);  // the texture carries the colour
      ASSERT_TRUE(m.texture);
      EXPECT_EQ(m.texture->width, 64);
      EXPECT_EQ(s.faceUvs.size(), s.faces.size());
    }
    if (m.name == "panel") {
      expectNear(s.emittedRadiance, Rgb{5, 4.5, 4}, 1e-5);
      panelPower += surfaceArea(s) * kPi * s.emittedRadiance.r;
      EXPECT_LT(surfaceNormal(s).y, -0.999);  // the panel faces down
    } else {
      EXPECT_EQ(s.emittedRadiance, Rgb{});
    }
  }
  // Geometry through the node transforms: a 4 × 3 m floor, a 0.6 × 0.4 m panel.
  EXPECT_NEAR(areaOfMaterial(*scene, "floor"), 2 * 12, 1e-5);  // front and back
  EXPECT_NEAR(panelPower, 0.24 * kPi * 5, 1e-5);
  // The sphere's split vertices are welded: 24 × 12 faces 15° apart are smooth regions.
  int sphereRegions = 0;
  std::size_t sphereFaces = 0;
  for (const Surface& s : scene->surfaces)
    if (s.name.rfind("sphere", 0) == 0) {
      ++sphereRegions;
      sphereFaces += s.faces.size();
    }
  EXPECT_GE(sphereFaces, 24u * 10u);
  EXPECT_LE(sphereRegions, 3);

  EXPECT_NEAR(length(scene->camera.eye - Vec3{0, 1.6, 5.5}), 0, 1e-6);
  EXPECT_NEAR(scene->camera.verticalFovDegrees, 0.6939551846210171 * 180 / kPi, 1e-9);
  EXPECT_LT(scene->camera.target.z, scene->camera.eye.z);  // looking into the room (−z)

  EXPECT_EQ(warnings.messages(), std::vector<std::string>{});

  // The checker reaches the patches through the UVs: 8 × 8 squares of 0.5 × 0.375 m, so patches of
  // at most 0.1 m take one texel colour or a blend at a square's edge, and their area-weighted
  // mean is the texture's mean.
  const Mesh mesh = subdivideScene(*scene, 0.1);
  const std::vector<Rgb> albedo = patchAlbedo(*scene, mesh);
  double lowest = 1, highest = 0, weighted = 0, area = 0;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    const Surface& s = scene->surfaces[mesh.patches[i].surface];
    if (scene->materials[s.material].name != "floor" || s.name.find("(back)") != std::string::npos) continue;
    lowest = std::min(lowest, albedo[i].r);
    highest = std::max(highest, albedo[i].r);
    weighted += albedo[i].r * mesh.patches[i].area;
    area += mesh.patches[i].area;
  }
  EXPECT_NEAR(lowest, decode(51 / 255.0), 2e-3);
  EXPECT_NEAR(highest, decode(204 / 255.0), 2e-3);
  EXPECT_NEAR(area, 12, 1e-6);
  EXPECT_NEAR(weighted / area, checkerMean, 0.01);
}

// The strip of tests/support/emissive_strip.h as glTF: emissiveFactor × emissive strength ×
// emissiveTexture (the half-white PNG beside it, unless withImage is false); `material` is the
// material's JSON.
std::string writeEmissiveStrip(const std::filesystem::path& dir, const std::string& material, bool withImage = true) {
  if (withImage) testing::writeHalfWhitePng(dir / "emit.png");
  std::vector<char> bin;
  auto put = [&](const void* data, std::size_t size) { bin.insert(bin.end(), static_cast<const char*>(data), static_cast<const char*>(data) + size); };
  for (const Vec3& p : testing::kStripPositions)
    for (float x : {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}) put(&x, 4);
  for (const Vec3& p : testing::kStripPositions)
    for (float x : {static_cast<float>(testing::stripU(p)), static_cast<float>(1 - p.y)}) put(&x, 4);
  put(testing::kStripTriangles, sizeof testing::kStripTriangles);
  testing::writeBytes(dir / "strip.bin", bin);
  const std::string path = (dir / "strip.gltf").string();
  std::ofstream(path) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"name": "strip", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "buffers": [{"uri": "strip.bin", "byteLength": 144}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72}, {"buffer": 0, "byteOffset": 72, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 120, "byteLength": 24}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [2, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 6, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"}],
    "textures": [{"source": 0}], "images": [{"uri": "emit.png"}],
    "materials": [)" << material << "]}";
  return path;
}

// Blender, three.js and the glTF spec: emitted radiance = emissiveFactor × strength × the
// sRGB-decoded emissiveTexture. Helmet-like: the texture is black over half the strip.
TEST(GltfTest, EmissiveTextureScalesTheEmissionPerPatch) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf", "emissive-texture");
  const std::string path = writeEmissiveStrip(dir, R"({"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}, "emissiveFactor": [1, 0.5, 0.25], "emissiveTexture": {"index": 0},
      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}})");
  WarningCapture warnings;
  Result<Scene> scene = loadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(warnings.messages().empty()) << warnings.messages().front();
  ASSERT_EQ(scene->surfaces.size(), 1u);
  const Rgb radiance{4, 2, 1};
  EXPECT_EQ(scene->surfaces[0].emittedRadiance, radiance);
  // What `lambert info` and the path tracer take: the mean over the strip, half of the factor.
  const Rgb mean = meanEmittedRadiance(*scene, scene->surfaces[0]);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], radiance[c] / 2, 0.005 * radiance[c]);
  testing::expectEmissionFollowsHalfWhiteTexture(*scene, radiance);

  // A missing image is refused, naming it, as a missing base colour texture is.
  std::filesystem::remove(dir / "emit.png");
  const std::string lamp = R"({"name": "lamp", "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0}})";
  Result<Scene> missing = readGltf(writeEmissiveStrip(dir, lamp, false));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, path + ": emit.png: the image could not be loaded (a missing or unreadable file?)");
  // Under a black factor (glTF's default) the texture changes nothing, and is not read.
  Result<Scene> dark = readGltf(writeEmissiveStrip(dir, R"({"name": "dark", "emissiveTexture": {"index": 0}})", false));
  ASSERT_TRUE(dark.ok()) << dark.error().message;
  EXPECT_EQ(dark->surfaces[0].emittedRadiance.maxComponent(), 0);
  EXPECT_EQ(dark->materials[0].emissionTexture, nullptr);
}

// Found by fuzz/gltf_fuzz.cpp (a mutated Blender glb whose node named a mesh past the end):
// tinygltf leaves a node's indices unchecked and std::vector::at threw out of the reader. The
// minimal reproducer is in the corpus; the camera and POSITION accessor indices had the same flaw.
TEST(GltfTest, FuzzedIndicesPastTheEndAreErrorsNotExceptions) {
  const std::string reproducer = std::string(LAMBERT_SOURCE_DIR) + "/tests/corpus/gltf/regression-node-mesh-out-of-range.gltf";
  Result<Scene> mesh = readGltf(reproducer);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().message, reproducer + ": node 'box' refers to mesh 7, which does not exist");

  const std::filesystem::path dir = testing::scratchDirectory("gltf", "fuzzed-indices");
  std::ofstream(dir / "camera.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"name": "eye", "camera": 3}]})";
  Result<Scene> camera = readGltf((dir / "camera.gltf").string());
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.error().message, (dir / "camera.gltf").string() + ": node 'eye' refers to camera 3, which does not exist");

  // Round 4: indices stored as floats (−1185.98) were cast to an unsigned index, which is
  // undefined behaviour; the spec allows unsigned integer indices only.
  const std::string floats = std::string(LAMBERT_SOURCE_DIR) + "/tests/corpus/gltf/regression-float-indices.gltf";
  Result<Scene> floatIndices = readGltf(floats);
  ASSERT_FALSE(floatIndices.ok());
  EXPECT_EQ(floatIndices.error().message,
            floats + ": mesh 'tri': indices (accessor 1) must be unsigned integers (componentType 5121, 5123 or 5125), not componentType 5126");

  std::ofstream(dir / "position.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"name": "m", "primitives": [{"attributes": {"POSITION": 9}}]}]})";
  Result<Scene> position = readGltf((dir / "position.gltf").string());
  ASSERT_FALSE(position.ok());
  EXPECT_EQ(position.error().message, (dir / "position.gltf").string() + ": mesh 'm': POSITION accessor 9 does not exist");
}

TEST(GltfTest, BrokenFilesAreErrorsNamingTheFile) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf", "bad");
  Result<Scene> missing = readGltf((dir / "nowhere.glb").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, (dir / "nowhere.glb").string() + ": no such glTF file");

  // A truncated .glb: the first 1,000 bytes of Blender's file.
  std::ifstream in(kBlenderRoom, std::ios::binary);
  std::vector<char> bytes(1000);
  in.read(bytes.data(), 1000);
  testing::writeBytes(dir / "truncated.glb", bytes);
  Result<Scene> truncated = readGltf((dir / "truncated.glb").string());
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.error().message, (dir / "truncated.glb").string() +
                                          ": the header says the file has 50344 bytes, but it has 1000 (truncated): export it again");

  // Bytes after the header's length are not glTF: ignored, with a warning; the file still loads.
  {
    std::ifstream whole(kBlenderRoom, std::ios::binary);
    std::vector<char> padded{std::istreambuf_iterator<char>(whole), std::istreambuf_iterator<char>()};
    padded.insert(padded.end(), 5, '\0');
    testing::writeBytes(dir / "padded.glb", padded);
    WarningCapture warnings;
    Result<Scene> scene = readGltf((dir / "padded.glb").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    EXPECT_EQ(warnings.count((dir / "padded.glb").string() + ": 5 bytes after the length the header gives (50344) are ignored"), 1);
  }

  // An accessor that claims more vertices than its buffer holds.
  std::ofstream(dir / "overrun.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1000, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}]})";
  Result<Scene> overrun = readGltf((dir / "overrun.gltf").string());
  ASSERT_FALSE(overrun.ok());
  EXPECT_TRUE(testing::contains(overrun.error().message, "overrun.gltf: ")) << overrun.error().message;

  // The same file with the right count: one triangle, a default grey material, a default camera.
  std::ofstream(dir / "triangle.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "scale": [-1, 1, 1]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}]})";
  Result<Scene> triangle = readGltf((dir / "triangle.gltf").string());
  ASSERT_TRUE(triangle.ok()) << triangle.error().message;
  ASSERT_EQ(triangle->surfaces.size(), 1u);
  EXPECT_NEAR(surfaceArea(triangle->surfaces[0]), 0.5, 1e-12);
  // Mirrored by the node's scale, the winding is flipped back: the front still faces +z.
  EXPECT_GT(surfaceNormal(triangle->surfaces[0]).z, 0.999);
  EXPECT_EQ(triangle->materials[triangle->surfaces[0].material].name, "default");
}

// tinygltf skips a property of the wrong type silently; lambert names its JSON path.
TEST(GltfTest, WrongTypesAreErrorsNamingTheJsonPath) {
  const std::filesystem::path dir = testing::scratchDirectory("gltf", "types");
  const std::string head = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], )";
  const std::string rest = R"(, "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}]})";
  struct Case {
    std::string json;     // between head and rest
    std::string message;  // after "<file>: "; empty: it loads
  };
  const Case cases[] = {
      {R"("nodes": [{"mesh": "quad"}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}])",
       R"(/nodes/0/mesh: an index (a whole number, 0 or more, without a decimal point) is expected here, not "quad")"},
      {R"("nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": -1}}]}])",
       "/meshes/0/primitives/0/attributes/POSITION: an index (a whole number, 0 or more, without a decimal point) is expected here, not -1"},
      {R"("nodes": [{"mesh": 0, "translation": [1, 2]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}])",
       "/nodes/0/translation: an array of 3 numbers is expected here, not [1,2]"},
      {R"("nodes": {"mesh": 0}, "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}])",
       R"(/nodes: an array is expected here, not {"mesh":0})"},
      {R"("nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
          "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, "opaque"]}}])",
       "/materials/0/pbrMetallicRoughness/baseColorFactor: an array of 4 numbers is expected here, not [0.5,0.5,0.5,\"opaque\"]"},
      // tinygltf would skip an index written with a decimal point too.
      {R"("nodes": [{"mesh": 0.0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}])",
       "/nodes/0/mesh: an index (a whole number, 0 or more, without a decimal point) is expected here, not 0.0"},
      {R"("nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}])", ""},
  };
  for (const Case& c : cases) {
    const std::string file = (dir / "case.gltf").string();
    std::ofstream(file) << head << c.json << rest;
    Result<Scene> scene = readGltf(file);
    if (c.message.empty()) {
      EXPECT_TRUE(scene.ok()) << c.json << "\n" << scene.error().message;
    } else {
      ASSERT_FALSE(scene.ok()) << c.json;
      EXPECT_EQ(scene.error().message, file + ": " + c.message);
    }
  }
}

}  // namespace
}  // namespace lambert
