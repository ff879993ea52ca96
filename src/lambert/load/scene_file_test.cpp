#include "lambert/load/scene_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "lambert/core/warning.h"
#include "lambert/engine/radiosity.h"
#include "lambert/render/scene_camera.h"
#include "lambert/scene/builtin.h"
#include "tests/support/emissive_strip.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

void expectSameScene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.metresPerUnit, b.metresPerUnit);
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (std::size_t s = 0; s < a.surfaces.size(); ++s) {
    EXPECT_EQ(a.surfaces[s].name, b.surfaces[s].name);
    EXPECT_EQ(a.surfaces[s].vertices, b.surfaces[s].vertices) << a.surfaces[s].name;  // bit for bit
    EXPECT_EQ(a.surfaces[s].emittedRadiance, b.surfaces[s].emittedRadiance);
    EXPECT_EQ(a.materials[a.surfaces[s].material].albedo, b.materials[b.surfaces[s].material].albedo);
  }
  EXPECT_EQ(a.lights, b.lights);
  EXPECT_EQ(a.camera.eye, b.camera.eye);
  EXPECT_EQ(a.camera.target, b.camera.target);
  EXPECT_EQ(a.camera.up, b.camera.up);
  EXPECT_EQ(a.camera.verticalFovDegrees, b.camera.verticalFovDegrees);
  EXPECT_EQ(a.cameraGiven, b.cameraGiven);
  EXPECT_EQ(a.exposureStops, b.exposureStops);
}

TEST(SceneFileTest, BuiltInScenesRoundTripBitForBit) {
  for (const std::string& name : builtinSceneNames()) {
    Scene scene = *builtinScene(name);
    Result<Scene> read = parseSceneFile(sceneFileText(scene), name + ".json");
    ASSERT_TRUE(read.ok()) << read.error().message;
    expectSameScene(*read, scene);
  }
}

TEST(SceneFileTest, TheShippedCornellBoxIsTheBuiltInOne) {
  for (const std::string& name : {std::string("cornell"), std::string("cornell-spots")}) {
    const std::string path = std::string(LAMBERT_SOURCE_DIR) + "/scenes/cornell/" + name + ".json";
    Result<Scene> read = loadScene(path);
    ASSERT_TRUE(read.ok()) << read.error().message;
    expectSameScene(*read, *builtinScene(name));
  }
}

// The same box as OBJ + MTL, placed by a scene file that gives the unit and the camera: the same
// surfaces, and the same solution at every vertex.
TEST(SceneFileTest, TheShippedCornellObjIsTheBuiltInBox) {
  Result<Scene> fromObj = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/scenes/cornell/cornell-obj.json");
  ASSERT_TRUE(fromObj.ok()) << fromObj.error().message;
  const Scene builtin = cornellBox();
  ASSERT_EQ(fromObj->surfaces.size(), builtin.surfaces.size());
  for (std::size_t s = 0; s < builtin.surfaces.size(); ++s) {
    ASSERT_EQ(fromObj->surfaces[s].vertices.size(), builtin.surfaces[s].vertices.size()) << builtin.surfaces[s].name;
    for (std::size_t v = 0; v < builtin.surfaces[s].vertices.size(); ++v)
      EXPECT_LT(length(fromObj->surfaces[s].vertices[v] - builtin.surfaces[s].vertices[v]), 1e-9);
    EXPECT_EQ(fromObj->surfaces[s].emittedRadiance, builtin.surfaces[s].emittedRadiance);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(fromObj->materials[fromObj->surfaces[s].material].albedo[c], builtin.materials[builtin.surfaces[s].material].albedo[c], 1e-15);
  }
  EXPECT_EQ(fromObj->metresPerUnit, 0.001);
  EXPECT_EQ(fromObj->camera.eye, builtin.camera.eye);

  RadiosityOptions options;
  options.meshing = MeshStrategy::Uniform;
  options.uniform.targetPatches = 300;
  options.formFactors.showProgress = false;
  std::vector<Rgb> radiance[2];
  const Scene* scenes[2] = {&builtin, &*fromObj};
  for (int k = 0; k < 2; ++k) {
    auto engine = Radiosity::create(*scenes[k], options);
    ASSERT_TRUE(engine.ok());
    ASSERT_TRUE((*engine)->solve().ok());
    radiance[k] = (*engine)->solution().vertexRadiance();
  }
  ASSERT_EQ(radiance[0].size(), radiance[1].size());
  for (std::size_t v = 0; v < radiance[0].size(); ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance[1][v][c], radiance[0][v][c], 1e-3 * radiance[0][v][c] + 1e-12) << v;
}

TEST(SceneFileTest, MeshesArePlacedInTheScenesUnits) {
  const std::filesystem::path dir = testing::scratchDirectory("scene-file", "meshes");
  std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  auto read = [&](const std::string& meshes, const std::string& unit = "m") {
    std::ofstream(dir / "scene.json") << "{\"unit\": \"" + unit + "\", \"meshes\": [" + meshes + "]}";
    return loadScene((dir / "scene.json").string());
  };
  // Scaled by 2, turned 90° about y, moved: (1, 0, 0) → (2, 0, 0) → (0, 0, −2) → (10, 0, −2).
  Result<Scene> placed = read(R"({"path": "tri.obj", "transform": {"scale": 2, "rotateDegrees": [0, 90, 0], "translate": [10, 0, 0]}})");
  ASSERT_TRUE(placed.ok()) << placed.error().message;
  ASSERT_EQ(placed->surfaces.size(), 1u);
  EXPECT_LT(length(placed->surfaces[0].vertices[1] - Vec3{10, 0, -2}), 1e-12);
  EXPECT_NEAR(surfaceArea(placed->surfaces[0]), 2, 1e-12);
  // A mirroring scale keeps the front in front: mirrored across x the triangle still faces +z;
  // mirrored across its own plane its front is the mirror image of +z.
  Result<Scene> mirrored = read(R"({"path": "tri.obj", "transform": {"scale": [-1, 1, 1]}})");
  ASSERT_TRUE(mirrored.ok());
  EXPECT_GT(surfaceNormal(mirrored->surfaces[0]).z, 0.999);
  Result<Scene> flipped = read(R"({"path": "tri.obj", "transform": {"scale": [1, 1, -1]}})");
  ASSERT_TRUE(flipped.ok());
  EXPECT_LT(surfaceNormal(flipped->surfaces[0]).z, -0.999);
  Result<Scene> upright = read(R"({"path": "tri.obj"})");
  EXPECT_GT(surfaceNormal(upright->surfaces[0]).z, 0.999);
  // glTF is in metres: in a millimetre scene its floor is 4000 × 3000, its camera comes along.
  std::filesystem::copy_file(std::string(LAMBERT_SOURCE_DIR) + "/tests/data/blender_room.glb", dir / "room.glb");
  Result<Scene> room = read(R"({"path": "room.glb"})", "mm");
  ASSERT_TRUE(room.ok()) << room.error().message;
  double floorArea = 0;
  for (const Surface& s : room->surfaces)
    if (room->materials[s.material].name == "floor") floorArea += surfaceArea(s);
  EXPECT_NEAR(floorArea, 2 * 12e6, 1);  // two-sided: the floor and its twin
  EXPECT_NEAR(length(room->camera.eye - Vec3{0, 1600, 5500}), 0, 1e-3);
  EXPECT_EQ(room->lights.size(), 3u);
  EXPECT_NEAR(room->lights[0].position.y, 2000, 1e-3);

  for (const auto& [meshes, message] : std::vector<std::pair<std::string, std::string>>{
           {R"({"transform": {}})", "/meshes/0: missing required field \"path\""},
           {R"({"path": "scene.json"})", "/meshes/0/path: \"scene.json\" is not a mesh file"},
           {R"({"path": "gone.obj"})", "/meshes/0/path: " + (dir / "gone.obj").string() + ": no such OBJ file"},
           {R"({"path": "tri.obj", "transform": {"scale": 0}})", "/meshes/0/transform/scale: a scale of zero"},
           {R"({"path": "tri.obj", "offset": 1})", "/meshes/0/offset: unknown field"}}) {
    Result<Scene> bad = read(meshes);
    ASSERT_FALSE(bad.ok()) << meshes;
    EXPECT_TRUE(testing::contains(bad.error().message, message)) << bad.error().message;
  }
}

// Two OBJs that share one MTL, placed by one scene file: the MTL's problem is its own, named by
// its file and line, and reported once (it was once per OBJ, each naming the OBJ).
TEST(SceneFileTest, TwoMeshesSharingAMaterialLibraryReportItsProblemOnce) {
  const std::filesystem::path dir = testing::scratchDirectory("scene-file", "shared-mtl");
  std::ofstream(dir / "shared.mtl") << "# one library\nnewmtl white\nKd 1 1 1\n";
  for (const char* name : {"a.obj", "b.obj"}) std::ofstream(dir / name) << "mtllib shared.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl white\nf 1 2 3\n";
  std::ofstream(dir / "scene.json") << R"({"meshes": [{"path": "a.obj"}, {"path": "b.obj", "transform": {"translate": [2, 0, 0]}}]})";
  std::vector<std::string> reported;
  const WarningSink previous = setWarningSink([&](const std::string& m) { reported.push_back(m); });
  Result<Scene> scene = loadScene((dir / "scene.json").string());
  setWarningSink(previous);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->surfaces.size(), 2u);
  ASSERT_EQ(reported.size(), 1u) << (reported.empty() ? "" : reported.back());
  EXPECT_TRUE(testing::contains(reported[0], (dir / "shared.mtl").string() + ":3: material 'white': Kd: albedo of 1 or more lowered"))
      << reported[0];
}

// A glTF with no camera, placed by a scene file with none: the scene gives no camera, and is
// drawn from the view the bare file gets (inside the closed room), not from the loader's
// stand-in view from outside it (cameraViewingScene).
TEST(SceneFileTest, AGltfWithoutACameraPlacedByASceneFileGetsTheBareFilesView) {
  const std::filesystem::path dir = testing::scratchDirectory("scene-file", "gltf-no-camera");
  // A closed 4 × 3 × 5 m box, two-sided, as 12 triangles.
  const float corner[8][3] = {{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}, {0, 0, 5}, {4, 0, 5}, {4, 3, 5}, {0, 3, 5}};
  const std::uint16_t faces[6][4] = {{0, 1, 2, 3}, {5, 4, 7, 6}, {4, 0, 3, 7}, {1, 5, 6, 2}, {4, 5, 1, 0}, {3, 2, 6, 7}};
  std::vector<char> bin(reinterpret_cast<const char*>(corner), reinterpret_cast<const char*>(corner) + sizeof corner);
  for (const auto& f : faces)
    for (std::uint16_t i : {f[0], f[1], f[2], f[0], f[2], f[3]}) bin.insert(bin.end(), reinterpret_cast<const char*>(&i), reinterpret_cast<const char*>(&i) + 2);
  testing::writeBytes(dir / "box.bin", bin);
  std::ofstream(dir / "box.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"doubleSided": true}],
    "buffers": [{"byteLength": 168, "uri": "box.bin"}],
    "bufferViews": [{"buffer": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 72}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0,0,0], "max": [4,3,5]},
                  {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}]})";
  std::ofstream(dir / "scene.json") << R"({"meshes": [{"path": "box.gltf"}]})";
  Result<Scene> bare = loadScene((dir / "box.gltf").string()), placed = loadScene((dir / "scene.json").string());
  ASSERT_TRUE(bare.ok()) << bare.error().message;
  ASSERT_TRUE(placed.ok()) << placed.error().message;
  EXPECT_FALSE(placed->cameraGiven);
  const Result<ChosenCamera> bareView = sceneCamera(*bare, {}), placedView = sceneCamera(*placed, {});
  ASSERT_TRUE(bareView.ok() && placedView.ok());
  EXPECT_EQ(bareView->source, CameraSource::Inside);
  EXPECT_EQ(placedView->source, CameraSource::Inside);
  EXPECT_LT(length(placedView->camera.eye - bareView->camera.eye), 1e-9);
  EXPECT_LT(length(placedView->camera.target - bareView->camera.target), 1e-9);
}

TEST(SceneFileTest, UnitsDefaultsAndNames) {
  const std::string square = R"("materials": [{"name": "grey"}],
      "surfaces": [{"material": "grey", "vertices": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]]}])";
  Result<Scene> metres = parseSceneFile("{" + square + "}", "dir/room.json");
  ASSERT_TRUE(metres.ok()) << metres.error().message;
  EXPECT_EQ(metres->name, "room");                      // the file's stem
  EXPECT_EQ(metres->metresPerUnit, 1);                  // metres by default
  EXPECT_EQ(metres->materials[0].albedo, Rgb::gray(0.5));
  EXPECT_TRUE(metres->lights.empty());
  EXPECT_EQ(metres->camera.target, (Vec3{0.5, 0.5, 0}));  // looking at the bounding box's centre
  EXPECT_LT(metres->camera.eye.z, 0);
  for (auto [unit, factor] : {std::pair{"cm", 0.01}, std::pair{"mm", 0.001}, std::pair{"in", 0.0254}, std::pair{"ft", 0.3048}}) {
    Result<Scene> scaled = parseSceneFile(std::string("{\"unit\": \"") + unit + "\", " + square + "}", "x.json");
    ASSERT_TRUE(scaled.ok()) << scaled.error().message;
    EXPECT_EQ(scaled->metresPerUnit, factor) << unit;
  }
  Result<Scene> lit = parseSceneFile(R"({"materials": [{"name": "lamp", "albedo": [0.2, 0.3, 0.4], "emittedRadiance": [5, 6, 7]}],
      "surfaces": [{"name": "panel", "material": "lamp", "vertices": [[0,0,0], [1,0,0], [0,1,0]]}],
      "lights": [{"type": "directional", "direction": [0, -2, 0], "irradiance": [1, 1, 1]},
                 {"type": "point", "position": [0, 1, 0], "intensity": [2, 2, 2]}]})", "lit.json");
  ASSERT_TRUE(lit.ok()) << lit.error().message;
  EXPECT_EQ(lit->surfaces[0].emittedRadiance, (Rgb{5, 6, 7}));  // emission comes with the material
  EXPECT_EQ(lit->lights[0].kind, LightKind::Directional);
  EXPECT_EQ(lit->lights[0].direction, (Vec3{0, -1, 0}));       // normalised
  EXPECT_EQ(lit->lights[1].intensity, (Rgb{2, 2, 2}));
}

// Every error names the file and the JSON path (or line and column) and what is allowed.
// Two-sided materials get their twins when loaded, are written once, and read back the same;
// the defaults survive the round trip.
TEST(SceneFileTest, TwoSidedMaterialsAndDefaultsRoundTrip) {
  const std::filesystem::path dir = testing::scratchDirectory("scene-file", "two-sided");
  std::ofstream(dir / "panel.json") << R"({"version": 1,
    "materials": [{"name": "card", "albedo": [0.4, 0.5, 0.6], "twoSided": true}],
    "surfaces": [{"material": "card", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]}],
    "defaults": {"maxEdge": 0.25, "solver": "jacobi", "tolerance": 1e-5}})";
  Result<Scene> scene = loadScene((dir / "panel.json").string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->surfaces.size(), 2u);
  EXPECT_EQ(scene->surfaces[0].twin, 1);
  EXPECT_NEAR(surfaceNormal(scene->surfaces[1]).z, -1, 1e-12);
  EXPECT_EQ(scene->defaults.maxEdgeLength, 0.25);
  EXPECT_EQ(scene->defaults.solver, "jacobi");
  EXPECT_EQ(scene->defaults.tolerance, 1e-5);
  const std::string text = sceneFileText(*scene);
  ASSERT_TRUE(writeSceneFile((dir / "again.json").string(), *scene).ok());
  Result<Scene> again = loadScene((dir / "again.json").string());
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(sceneFileText(*again), text);
  EXPECT_EQ(again->surfaces.size(), 2u);  // the twin is made again, not written
  // A meshes entry can turn a file's sides either way.
  std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "sides.json") << R"({"meshes": [{"path": "tri.obj", "twoSided": true}]})";
  Result<Scene> sides = loadScene((dir / "sides.json").string());
  ASSERT_TRUE(sides.ok()) << sides.error().message;
  EXPECT_EQ(sides->surfaces.size(), 2u);
}

TEST(SceneFileTest, BadFilesAreRefusedNamingThePathAndTheRule) {
  const std::string material = R"("materials": [{"name": "m"}])";
  const std::string surface = R"("surfaces": [{"material": "m", "vertices": [[0,0,0], [1,0,0], [0,1,0]]}])";
  const std::string base = material + ", " + surface;
  const std::pair<std::string, std::string> cases[] = {
      {"{" + base + ", \"colour\": 1}", "bad.json: /colour: unknown field (allowed here: version, name, unit"},
      {"{" + base + R"(, "lights": [{"type": "point", "position": [0,1,0], "intensity": [1,1,1], "direction": [0,1,0]}]})",
       "bad.json: /lights/0/direction: unknown field (allowed here: name, type, position, intensity, maintenance)"},
      {"{" + base + R"(, "lights": [{"type": "spot", "position": [0,1,0], "direction": [0,-1,0], "intensity": [1,1,1], "coneAngleDegrees": 120}]})",
       "bad.json: /lights/0/coneAngleDegrees: 120 is out of range: allowed (0, 90]"},
      {"{" + base + R"(, "lights": [{"type": "spot", "position": [0,1,0], "direction": [0,-1,0], "intensity": [1,1,1], "coneAngleDegrees": 20, "falloffDegrees": 30}]})",
       "/lights/0/falloffDegrees: 30 is out of range: allowed [0, 20]"},
      {"{" + base + R"(, "lights": [{"type": "laser"}]})", "/lights/0/type: unknown light type \"laser\" (allowed: point, spot, directional, ies, sky, sun)"},
      {"{" + base + R"(, "lights": [{"type": "directional", "direction": [0,0,0], "irradiance": [1,1,1]}]})", "/lights/0/direction: the direction must not be zero"},
      {"{" + base + R"(, "lights": [{"type": "point", "position": "here", "intensity": [1,1,1]}]})", "/lights/0/position: expected an array of 3 numbers, found a string"},
      {R"({"materials": [{"name": "m", "albedo": [1, 0.5, 0.5]}], )" + surface + "}", "/materials/0/albedo/0: 1 is out of range: allowed [0, 1)"},
      {R"({"materials": [{"name": "m", "albedo": [0.5, -0.1, 0.5]}], )" + surface + "}", "/materials/0/albedo/1: -0.1 is out of range"},
      {R"({"materials": [{"name": "m", "emittedRadiance": [1, -2, 0]}], )" + surface + "}", "/materials/0/emittedRadiance/1: -2 is out of range"},
      {R"({"materials": [{"name": "m"}, {"name": "m"}], )" + surface + "}", "/materials/1/name: a second material named \"m\""},
      {"{" + material + R"(, "surfaces": [{"material": "stone", "vertices": [[0,0,0], [1,0,0], [0,1,0]]}]})", "/surfaces/0/material: no material named \"stone\""},
      {"{" + material + R"(, "surfaces": [{"material": "m", "vertices": [[0,0,0], [1,0,0], [2,0,0]]}]})", "/surfaces/0/vertices: the polygon has no area"},
      {"{" + material + R"(, "surfaces": [{"material": "m", "vertices": [[0,0,0], [2,0,0], [1,0.3,0], [1,2,0]]}]})", "/surfaces/0/vertices/2: the polygon is not convex at this vertex"},
      {"{" + material + R"(, "surfaces": [{"material": "m", "vertices": [[0,0,0], [1,0,0]]}]})", "a polygon needs at least 3 vertices, found 2"},
      {"{" + material + R"(, "surfaces": [{"material": "m", "vertices": [[0,0,0], [1,0,0], [0,1,1e400]]}]})", "not valid JSON"},
      {"{" + material + "}", "bad.json: /surfaces: the scene has no surfaces"},
      {"{\"unit\": \"furlong\", " + base + "}", "/unit: unknown unit \"furlong\" (allowed: m, cm, mm, in, ft)"},
      {"{\"unit\": \"m\", \"metresPerUnit\": 1, " + base + "}", "give either \"unit\" or \"metresPerUnit\", not both"},
      {"{\"version\": 2, " + base + "}", "/version: version 2 is not supported"},
      {"{" + base + R"(, "camera": {"eye": [0,0,0], "target": [0,0,0]}})", "/camera/target: the target must differ from the eye"},
      {"[1, 2]", "bad.json: /: expected an object, found an array"},
      {R"({"materials": [{"name": "m", "twoSided": 1}], )" + surface + "}", "/materials/0/twoSided: expected true or false, found a number"},
      {"{" + material + R"(, "surfaces": [{"material": "m", "vertices": [[0,0,0], [1,0,0], [0,1,0]], "uvs": [[0,0], [1,0]]}]})",
       "/surfaces/0/uvs: expected one [u, v] per vertex (3), found 2"},
      {"{" + base + R"(, "defaults": {"solver": "lu"}})", "/defaults/solver: \"lu\" is not a solver (allowed: direct, gs, jacobi, shoot)"},
      {"{" + base + R"(, "defaults": {"patches": 10.5}})", "/defaults/patches: expected a whole number of patches"},
      {"{" + base + R"(, "defaults": {"patches": 10, "maxEdge": 1}})", "/defaults/maxEdge: give either \"patches\" or \"maxEdge\", not both"},
      {"{" + base + R"(, "defaults": {"tolerance": 2}})", "/defaults/tolerance: 2 is out of range: allowed (0, 1)"},
      {"{" + base + R"(, "defaults": {"adaptive": true}})", "/defaults/adaptive: unknown field (allowed here: patches, maxEdge, solver, tolerance)"},
      {"{\n  \"name\": \"x\",\n  \"surfaces\": [,]\n}", "bad.json:3:16: not valid JSON"},
  };
  for (const auto& [text, message] : cases) {
    Result<Scene> read = parseSceneFile(text, "bad.json");
    ASSERT_FALSE(read.ok()) << text;
    EXPECT_NE(read.error().message.find(message), std::string::npos) << "got: " << read.error().message << "\nwanted: " << message;
  }
}

// "emissionTexture" multiplies "emittedRadiance" as glTF's emissiveTexture and MTL's map_Ke do:
// the strip of tests/support/emissive_strip.h as its two squares.
TEST(SceneFileTest, EmissionTextureScalesTheEmissionPerPatch) {
  const std::filesystem::path dir = testing::scratchDirectory("scene_file", "emission-texture");
  testing::writeHalfWhitePng(dir / "emit.png");
  const std::string surfaces = R"("surfaces": [
      {"name": "left", "material": "lamp", "vertices": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]], "uvs": [[0,1], [0.5,1], [0.5,0], [0,0]]},
      {"name": "right", "material": "lamp", "vertices": [[1,0,0], [2,0,0], [2,1,0], [1,1,0]], "uvs": [[0.5,1], [1,1], [1,0], [0.5,0]]}])";
  const std::string path = (dir / "strip.json").string();
  std::ofstream(path) << R"({"materials": [{"name": "lamp", "albedo": [0, 0, 0], "emittedRadiance": [2, 1, 0.5], "emissionTexture": "emit.png"}], )"
                      << surfaces << "}";
  Result<Scene> scene = loadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  testing::expectEmissionFollowsHalfWhiteTexture(*scene, {2, 1, 0.5}, {MeshStrategy::Uniform, MeshStrategy::Adaptive, MeshStrategy::Hierarchical});

  const std::pair<std::string, std::string> bad[] = {
      {R"({"materials": [{"name": "lamp", "emissionTexture": "emit.png"}], )", "/materials/0/emissionTexture: an emission texture multiplies \"emittedRadiance\": give it too"},
      {R"({"materials": [{"name": "lamp", "emittedRadiance": [1, 1, 1], "emissionTexture": "gone.png"}], )",
       "/materials/0/emissionTexture: " + (dir / "gone.png").string() + ": no such texture file"},
  };
  for (const auto& [head, message] : bad) {
    std::ofstream(path) << head << surfaces << "}";
    Result<Scene> read = loadScene(path);
    ASSERT_FALSE(read.ok()) << head;
    EXPECT_NE(read.error().message.find(message), std::string::npos) << read.error().message;
  }
}

TEST(SceneFileTest, LoadSceneChoosesByNameOrExtension) {
  EXPECT_TRUE(loadScene("cornell").ok());
  Result<Scene> unknown = loadScene("nowhere");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("unknown scene 'nowhere' (built-in scenes: cornell, cornell-spots"), std::string::npos);
  Result<Scene> missing = loadScene("/no/such/room.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "/no/such/room.json: no such scene file");
  Result<Scene> wrongKind = loadScene("room.obj");
  ASSERT_FALSE(wrongKind.ok());

  const std::filesystem::path dir = testing::scratchDirectory("scene-file", "write");
  const std::string path = (dir / "sub" / "box.json").string();
  ASSERT_TRUE(writeSceneFile(path, cornellBox()).ok());
  Result<Scene> back = loadScene(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  expectSameScene(*back, cornellBox());
  EXPECT_FALSE(testing::hasTemporaryFiles(dir / "sub"));
}

}  // namespace
}  // namespace lambert
