// The camera a picture is taken from (render/scene_camera.h): given in the file's own frame, or
// chosen inside a closed scene; back-face culling; automatic exposure (render/tonemap.h).
#include "lambert/render/scene_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lambert/engine/radiosity.h"
#include "lambert/mesh/mesh.h"
#include "lambert/reference/reference.h"
#include "lambert/render/camera.h"
#include "lambert/render/rasterizer.h"
#include "lambert/render/solution_image.h"
#include "lambert/render/tonemap.h"
#include "lambert/load/scene_file.h"
#include "tests/support/engines.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

// A quad oriented so its front faces `towards` (counter-clockwise seen from there).
std::array<Vec3, 4> facing(std::array<Vec3, 4> quad, const Vec3& towards) {
  const Vec3 normal = cross(quad[1] - quad[0], quad[2] - quad[0]);
  if (dot(normal, towards - quad[0]) < 0) std::reverse(quad.begin(), quad.end());
  return quad;
}

// The six walls of the box [lo, hi], facing in (or out), as quads.
std::vector<std::array<Vec3, 4>> boxWalls(const Vec3& lo, const Vec3& hi, bool inward) {
  const Vec3 c = (lo + hi) * 0.5;
  std::vector<std::array<Vec3, 4>> walls;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {0.0, 1.0}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      std::array<Vec3, 4> q;
      for (int k = 0; k < 4; ++k) {
        double p[3] = {c.x, c.y, c.z};
        const double los[3] = {lo.x, lo.y, lo.z}, his[3] = {hi.x, hi.y, hi.z};
        p[axis] = side > 0 ? his[axis] : los[axis];
        p[u] = (k == 1 || k == 2) ? his[u] : los[u];
        p[v] = (k >= 2) ? his[v] : los[v];
        q[k] = {p[0], p[1], p[2]};
      }
      const Vec3 outside = q[0] + (q[0] - c);
      walls.push_back(facing(q, inward ? c : outside));
    }
  return walls;
}

// A closed room, z up as MGF writes it: walls of albedo 0.5 facing in, and a lamp hanging under
// the ceiling, facing down.
std::string mgfRoom(const Vec3& size) {
  std::ostringstream mgf;
  mgf << "m wall =\n\tc\n\t\tcxy .3333333333 .3333333333\n\trd .5\n";
  int n = 0;
  auto face = [&](const std::array<Vec3, 4>& q) {
    for (const Vec3& p : q) mgf << "v v" << n++ << " =\n\tp " << p.x << " " << p.y << " " << p.z << "\n";
    mgf << "f v" << n - 4 << " v" << n - 3 << " v" << n - 2 << " v" << n - 1 << "\n";
  };
  for (const auto& wall : boxWalls({0, 0, 0}, size, true)) face(wall);
  mgf << "m lamp =\n\tc\n\t\tcxy .3333333333 .3333333333\n\ted 200\n\trd .2\n";
  const double h = size.z - 0.05, cx = size.x / 2, cy = size.y / 2;
  face(facing({Vec3{cx - 0.3, cy - 0.3, h}, Vec3{cx + 0.3, cy - 0.3, h}, Vec3{cx + 0.3, cy + 0.3, h}, Vec3{cx - 0.3, cy + 0.3, h}},
              {cx, cy, 0}));
  return mgf.str();
}

Scene loadMgfRoom(const std::string& test, const Vec3& size) {
  const fs::path dir = testing::scratchDirectory("scene_camera", test);
  std::ofstream(dir / "room.mgf") << mgfRoom(size);
  Result<Scene> scene = loadScene((dir / "room.mgf").string());
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  return scene.ok() ? *scene : Scene{};
}

// A scene of quads in one material, built in code (y up).
Scene quadScene(const std::vector<std::array<Vec3, 4>>& quads, Rgb albedo = Rgb::gray(0.5)) {
  Scene scene;
  scene.name = "quads";
  scene.materials = {{"grey", albedo}};
  for (const auto& q : quads) scene.surfaces.push_back({"quad", {q.begin(), q.end()}, 0, {}});
  scene.camera = cameraViewingScene(scene);
  return scene;
}

// A corridor 2 m wide, 3 m high and 20 m long, closed, walls facing in, with small ceiling lamps.
Scene corridor(double lampRadiance) {
  Scene scene = quadScene(boxWalls({0, 0, 0}, {2, 3, 20}, true), Rgb::gray(0.6));
  scene.materials.push_back({"lamp", Rgb::gray(0.2)});
  for (double z : {3.0, 8.0, 13.0, 18.0})
    scene.surfaces.push_back({"lamp", {{0.8, 2.95, z - 0.2}, {1.2, 2.95, z - 0.2}, {1.2, 2.95, z + 0.2}, {0.8, 2.95, z + 0.2}},
                              1, Rgb::gray(lampRadiance)});
  scene.camera = cameraViewingScene(scene);
  return scene;
}

// The flat method on about `patches` patches, solved by Gauss–Seidel to 1e-9.
std::unique_ptr<Radiosity> solved(const Scene& scene, std::size_t patches) {
  RadiosityOptions options = testing::uniformOptions(patches, SolverKind::GaussSeidel);
  options.tolerance = 1e-9;
  return testing::solved(scene, options);
}

double percentile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

// ---------------------------------------------------------------------------------------------
// The camera in the file's frame

TEST(SceneCameraTest, MgfFileFrameIsTheLoadersTransform) {
  const Scene scene = loadMgfRoom("frame", {10, 4, 3});
  ASSERT_FALSE(scene.surfaces.empty());
  EXPECT_FALSE(scene.cameraGiven);
  EXPECT_EQ(scene.fileFrame.up, (Vec3{0, 0, 1}));
  // The corner written as (10, 4, 3) is a vertex of the loaded scene at the frame's image of it.
  const Vec3 corner = scene.fileFrame.scenePoint({10, 4, 3});
  bool found = false;
  for (const Surface& s : scene.surfaces)
    for (const Vec3& v : s.vertices) found |= length(v - corner) < 1e-9;
  EXPECT_TRUE(found) << corner.x << " " << corner.y << " " << corner.z;
  // z up in the file is y up in the scene, and the inverse undoes it.
  EXPECT_NEAR(length(scene.fileFrame.sceneDirection({0, 0, 1}) - Vec3{0, 1, 0}), 0, 1e-12);
  const Vec3 p{1.5, -2.25, 7};
  EXPECT_NEAR(length(scene.fileFrame.filePoint(scene.fileFrame.scenePoint(p)) - p), 0, 1e-12);
}

TEST(SceneCameraTest, EyeAndTargetInAnMgfFilesZUpFrameLandWhereExpected) {
  const Scene scene = loadMgfRoom("eye", {10, 4, 3});
  ASSERT_FALSE(scene.surfaces.empty());
  CameraRequest request;
  request.eye = Vec3{1, 2, 1.5};
  request.target = Vec3{9, 2, 1.5};
  request.verticalFovDegrees = 50;
  Result<ChosenCamera> chosen = sceneCamera(scene, request);
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  EXPECT_EQ(chosen->source, CameraSource::Request);
  const PinholeCamera pinhole(chosen->camera, 200, 100);
  // The target at the centre; a point 0.8 m above it in the file (z) above the centre by
  // f·0.8/8 pixels, f = 50 / tan(25°); a point 1 m to the file's +y (the camera's left, looking
  // along +x with z up) left of the centre.
  const ScreenPoint target = *pinhole.project(scene.fileFrame.scenePoint({9, 2, 1.5}));
  EXPECT_NEAR(target.x, 100, 1e-9);
  EXPECT_NEAR(target.y, 50, 1e-9);
  const double focal = 50 / std::tan(25 * kPi / 180);
  const ScreenPoint above = *pinhole.project(scene.fileFrame.scenePoint({9, 2, 2.3}));
  EXPECT_NEAR(above.x, 100, 1e-9);
  EXPECT_NEAR(above.y, 50 - focal * 0.8 / 8, 1e-9);
  const ScreenPoint left = *pinhole.project(scene.fileFrame.scenePoint({9, 3, 1.5}));
  EXPECT_NEAR(left.x, 100 - focal * 1.0 / 8, 1e-9);
  EXPECT_NEAR(left.y, 50, 1e-9);
  // --up given in the file's frame: x up turns the picture a quarter.
  request.up = Vec3{0, 1, 0};
  Result<ChosenCamera> turned = sceneCamera(scene, request);
  ASSERT_TRUE(turned.ok());
  const ScreenPoint sideways = *PinholeCamera(turned->camera, 200, 100).project(scene.fileFrame.scenePoint({9, 3, 1.5}));
  EXPECT_NEAR(sideways.x, 100, 1e-9);
  EXPECT_NEAR(sideways.y, 50 - focal * 1.0 / 8, 1e-9);
}

TEST(SceneCameraTest, RequestsThatAreNoCameraAreRefused) {
  const Scene scene = quadScene(boxWalls({0, 0, 0}, {1, 1, 1}, true));
  auto refused = [&](CameraRequest r, const std::string& part) {
    Result<ChosenCamera> c = sceneCamera(scene, r);
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find(part), std::string::npos) << c.error().message;
  };
  refused({Vec3{0, 0, 0}, std::nullopt, std::nullopt, std::nullopt}, "--eye needs --target");
  refused({std::nullopt, Vec3{0, 0, 0}, std::nullopt, std::nullopt}, "--target needs --eye");
  refused({Vec3{1, 1, 1}, Vec3{1, 1, 1}, std::nullopt, std::nullopt}, "--target must differ from --eye");
  refused({Vec3{0, 0, 0}, Vec3{0, 2, 0}, std::nullopt, std::nullopt}, "--up must not be parallel");
  refused({Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 0}, std::nullopt}, "--up must not be zero");
  refused({Vec3{0, 0, 0}, Vec3{1, 0, 0}, std::nullopt, 180.0}, "--fov");
  refused({Vec3{NAN, 0, 0}, Vec3{1, 0, 0}, std::nullopt, std::nullopt}, "--eye must be three finite numbers");
  // Only a field of view: the scene's own camera, narrowed.
  Result<ChosenCamera> narrowed = sceneCamera(scene, {std::nullopt, std::nullopt, std::nullopt, 10.0});
  ASSERT_TRUE(narrowed.ok());
  EXPECT_EQ(narrowed->camera.verticalFovDegrees, 10);
  EXPECT_EQ(narrowed->source, CameraSource::Inside);  // the closed cube has no camera of its own
}

// ---------------------------------------------------------------------------------------------
// The default view

TEST(SceneCameraTest, DefaultViewStandsInsideAClosedRoomAndSeesItLit) {
  const Scene scene = loadMgfRoom("inside", {10, 4, 3});
  ASSERT_FALSE(scene.surfaces.empty());
  const ChosenCamera chosen = defaultCamera(scene);
  ASSERT_EQ(chosen.source, CameraSource::Inside);
  const Vec3 eye = scene.fileFrame.filePoint(chosen.camera.eye);
  EXPECT_TRUE(eye.x > 0 && eye.x < 10 && eye.y > 0 && eye.y < 4 && eye.z > 0 && eye.z < 3) << eye.x << " " << eye.y << " " << eye.z;
  // Level, down the room's length (file x): within 25° of it (its longest lines of sight run
  // corner to corner).
  const Vec3 look = normalize(scene.fileFrame.filePoint(chosen.camera.target) - eye);
  EXPECT_GT(std::fabs(look.x), std::cos(25 * kPi / 180));
  EXPECT_NEAR(look.z, 0, 1e-9);
  // What it sees: every pixel a lit front face (no back, no background).
  Scene seen = scene;
  seen.camera = chosen.camera;
  auto engine = solved(seen, 600);
  ASSERT_TRUE(engine);
  SolutionImageOptions options;
  options.width = 64;
  options.height = 48;
  const Image image = renderSolution(engine->solution(), options);
  int lit = 0;
  for (const Rgb& p : image.pixels) lit += p.luminance() > 0;
  EXPECT_EQ(lit, 64 * 48);
}

// A file written with another axis up (MGF files y-up): the ceiling light, facing down that axis,
// says which way is up for the default view.
TEST(SceneCameraTest, DefaultViewTakesUpFromTheCeilingLights) {
  Scene scene = quadScene(boxWalls({0, 0, 0}, {3, 4, 6}, true));
  scene.materials.push_back({"lamp", Rgb::gray(0.2)});
  scene.surfaces.push_back({"lamp", {{2.95, 1.5, 2.5}, {2.95, 2.5, 2.5}, {2.95, 2.5, 3.5}, {2.95, 1.5, 3.5}}, 1, Rgb::gray(10)});
  if (surfaceNormal(scene.surfaces.back()).x > 0) std::reverse(scene.surfaces.back().vertices.begin(), scene.surfaces.back().vertices.end());
  const ChosenCamera chosen = defaultCamera(scene);
  ASSERT_EQ(chosen.source, CameraSource::Inside);
  EXPECT_NEAR(length(chosen.camera.up - Vec3{1, 0, 0}), 0, 1e-12);
  // Level with respect to that up: the view runs across x.
  EXPECT_NEAR(chosen.camera.target.x - chosen.camera.eye.x, 0, 1e-9);
  // Without the light, the file's own up (y).
  scene.surfaces.pop_back();
  EXPECT_NEAR(length(defaultCamera(scene).camera.up - Vec3{0, 1, 0}), 0, 1e-12);
}

TEST(SceneCameraTest, OpenScenesAndObjectsKeepTheOutsideView) {
  // A stage: a box 5 wide and high, 1 deep, its front (z = 0) open: from anywhere inside, much
  // of every direction escapes.
  auto openBox = [](double depth) {
    std::vector<std::array<Vec3, 4>> walls = boxWalls({0, 0, 0}, {5, 5, depth}, true);
    walls.erase(std::remove_if(walls.begin(), walls.end(), [](const auto& q) { return q[0].z == 0 && q[2].z == 0; }), walls.end());
    EXPECT_EQ(walls.size(), 5u);
    return quadScene(walls);
  };
  const ChosenCamera stage = defaultCamera(openBox(1));
  EXPECT_EQ(stage.source, CameraSource::Outside);
  EXPECT_LT(stage.camera.eye.z, 0);
  // As deep as it is wide (the Cornell box's proportions): still open, seen from in front.
  const ChosenCamera box = defaultCamera(openBox(5));
  EXPECT_EQ(box.source, CameraSource::Outside);
  EXPECT_LT(box.camera.eye.z, 0);
  // A closed cube facing out (an object): every point inside sees backs.
  EXPECT_EQ(defaultCamera(quadScene(boxWalls({0, 0, 0}, {1, 1, 1}, false))).source, CameraSource::Outside);
  // The same cube facing in is a room.
  EXPECT_EQ(defaultCamera(quadScene(boxWalls({0, 0, 0}, {1, 1, 1}, true))).source, CameraSource::Inside);
  // A floor under the sky with a two-sided box standing on it: the box's inside is enclosed (its
  // twins face in), but the open space around it outweighs it.
  Scene floor = quadScene({facing({Vec3{-5, 0, -5}, Vec3{5, 0, -5}, Vec3{5, 0, 5}, Vec3{-5, 0, 5}}, {0, 1, 0})});
  floor.materials.push_back({"box", Rgb::gray(0.5), true});
  for (const auto& q : boxWalls({-1, 0.01, -1}, {1, 3, 1}, false)) floor.surfaces.push_back({"box", {q.begin(), q.end()}, 1, {}});
  addTwins(floor);
  const ChosenCamera outside = defaultCamera(floor);
  EXPECT_EQ(outside.source, CameraSource::Outside);
  // From in front and above (25°), not edge-on to the floor.
  const Vec3 view = normalize(outside.camera.target - outside.camera.eye);
  EXPECT_NEAR(view.y, -std::sin(25 * kPi / 180), 1e-9);
  EXPECT_GT(view.z, 0);
}

// ---------------------------------------------------------------------------------------------
// Back-face culling

TEST(SceneCameraTest, CullsTheBackOfAOneSidedFaceButDrawsATwoSidedTwin) {
  // A quad facing +z, seen from behind (the camera at z = −4), in front of a lit wall facing the
  // camera at z = 2.
  for (bool twoSided : {false, true}) {
    Scene scene;
    scene.name = "cull";
    scene.materials = {{"quad", Rgb::gray(0.5), twoSided}, {"wall", Rgb{}}};  // the wall reflects nothing: its radiance is its own
    scene.surfaces.push_back({"quad", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, 0, Rgb::gray(1)});
    scene.surfaces.push_back({"wall", {{-5, -5, 2}, {-5, 5, 2}, {5, 5, 2}, {5, -5, 2}}, 1, Rgb::gray(3)});
    addTwins(scene);
    const Mesh mesh = subdivideScene(scene, 10);
    std::vector<Rgb> radiosity;
    for (const Patch& p : mesh.patches) radiosity.push_back(scene.surfaces[p.surface].emittedRadiance * kPi);
    const Camera camera{{0, 0, -4}, {0, 0, 0}, {0, 1, 0}, 60};
    const Image image = renderRadiance(camera, mesh, radiosity, {32, 32, Shading::Flat, 1});
    // The centre sees the quad's back: culled, the wall behind shows (radiance 3); a two-sided
    // quad's twin faces the camera and shows its own emission (radiance 1, as its front's).
    EXPECT_NEAR(image.at(16, 16).r, twoSided ? 1.0 : 3.0, 1e-12) << (twoSided ? "two-sided" : "one-sided");
    EXPECT_NEAR(image.at(1, 16).r, 3.0, 1e-12);  // beside the quad: the wall
    // The reference's camera rays pass the same backs (its picture is compared with this one).
    // (Nothing lights the twin's side, so it reflects nothing.)
    scene.camera = camera;  // the tracer draws from the scene's camera
    const ReferenceRenderer reference(scene, mesh, ReferenceOptions{.samplesPerPixel = 4, .maxBounces = 1, .showProgress = false});
    const Image traced = reference.render(32, 32);
    EXPECT_NEAR(traced.at(16, 16).r, twoSided ? 1.0 : 3.0, 1e-9);
  }
}

// ---------------------------------------------------------------------------------------------
// Automatic exposure

TEST(SceneCameraTest, AutoExposureIsTheLogAverageKey) {
  // Half the pixels at luminance a, half at b, a quarter of the image black (left out):
  // L̄ = exp((log(δ+a) + log(δ+b)) / 2) with δ = 10⁻⁴ (a + b) / 2.
  Image image{4, 4, std::vector<Rgb>(16)};
  const double a = 0.02, b = 5;
  for (int i = 0; i < 12; ++i) image.pixels[static_cast<std::size_t>(i)] = Rgb::gray(i % 2 ? a : b);
  const double delta = 1e-4 * (a + b) / 2;
  EXPECT_NEAR(autoExposureStops(image), std::log2(0.18 / std::sqrt((delta + a) * (delta + b))), 1e-12);
  EXPECT_EQ(autoExposureStops(Image{2, 2, std::vector<Rgb>(4)}), 0);
  // A scene's own exposure wins.
  Scene calibrated;
  calibrated.exposureStops = -1.5;
  EXPECT_EQ(sceneExposureStops(calibrated, image), -1.5);
}

TEST(SceneCameraTest, AutoExposureGivesTheSamePictureWhateverTheEmissionScale) {
  Scene scene = corridor(300);
  const ChosenCamera chosen = defaultCamera(scene);
  ASSERT_EQ(chosen.source, CameraSource::Inside);
  scene.camera = chosen.camera;
  SolutionImageOptions options;
  options.width = 80;
  options.height = 60;
  auto engine = solved(scene, 300);
  ASSERT_TRUE(engine);
  const Image image = renderSolution(engine->solution(), options);
  const double stops = autoExposureStops(image);

  // Eight times the emission: three stops less, and the same 8-bit picture.
  Scene brighter = scene;
  for (Surface& s : brighter.surfaces) s.emittedRadiance = s.emittedRadiance * 8;
  auto brighterEngine = solved(brighter, 300);
  ASSERT_TRUE(brighterEngine);
  const Image brighterImage = renderSolution(brighterEngine->solution(), options);
  EXPECT_NEAR(autoExposureStops(brighterImage), stops - 3, 1e-6);
  const std::vector<std::uint8_t> srgb = toSrgb8(image, stops), brighterSrgb = toSrgb8(brighterImage, autoExposureStops(brighterImage));
  int maxDifference = 0;
  for (std::size_t i = 0; i < srgb.size(); ++i) maxDifference = std::max(maxDifference, std::abs(int(srgb[i]) - int(brighterSrgb[i])));
  EXPECT_LE(maxDifference, 1);

  // Neither black nor blown out: the 1st and 99th percentiles of the exposed luminance lie inside
  // what 8-bit sRGB shows (above its first step, below white).
  std::vector<double> luminance;
  for (const Rgb& p : image.pixels) luminance.push_back(p.luminance() * std::exp2(stops));
  const double p1 = percentile(luminance, 0.01), p99 = percentile(luminance, 0.99);
  std::printf("corridor: exposure %.2f stops, exposed luminance 1st %.4f, 99th %.4f\n", stops, p1, p99);
  EXPECT_GT(p1, 1.0 / 255);
  EXPECT_LT(p99, 1.0);
  // At exposure 0 the same corridor is blown out: what the automatic exposure is for.
  std::vector<double> raw;
  for (const Rgb& p : image.pixels) raw.push_back(p.luminance());
  EXPECT_GT(percentile(raw, 0.5), 1.0);
}

// The scene file's "exposure" is read and written back; a file without one is automatic.
TEST(SceneCameraTest, SceneFileExposureRoundTrips) {
  Scene scene = quadScene(boxWalls({0, 0, 0}, {1, 1, 1}, true));
  EXPECT_FALSE(parseSceneFile(sceneFileText(scene), "auto.json")->exposureStops.has_value());
  EXPECT_FALSE(parseSceneFile(sceneFileText(scene), "auto.json")->cameraGiven);
  scene.exposureStops = 2.5;
  scene.cameraGiven = true;
  Result<Scene> back = parseSceneFile(sceneFileText(scene), "set.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->exposureStops, 2.5);
  EXPECT_TRUE(back->cameraGiven);
}

}  // namespace
}  // namespace lambert
