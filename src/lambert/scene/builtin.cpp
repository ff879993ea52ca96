#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

// A block's four sides, each a quad from a top edge down to the floor, wound so the normal faces
// away from the block's vertical axis.
void addBlockSides(Scene& scene, const std::string& name, const std::vector<Vec3>& top, int material) {
  Vec3 centre;
  for (const Vec3& v : top) centre += v / static_cast<double>(top.size());
  for (std::size_t i = 0; i < top.size(); ++i) {
    Vec3 a = top[i], b = top[(i + 1) % top.size()];
    Surface side{name + " side " + std::to_string(i + 1), {a, {a.x, 0, a.z}, {b.x, 0, b.z}, b}, material, {}};
    Vec3 outward = (a + b) * 0.5 - centre;
    outward.y = 0;
    if (dot(surfaceNormal(side), outward) < 0) side.vertices = {b, {b.x, 0, b.z}, {a.x, 0, a.z}, a};
    scene.surfaces.push_back(std::move(side));
  }
}

}  // namespace

Scene cornellBox() {
  Scene scene;
  scene.name = "cornell";
  scene.metresPerUnit = 0.001;
  scene.materials = {{"white", {0.725, 0.71, 0.68}},
                     {"red", {0.63, 0.065, 0.05}},
                     {"green", {0.14, 0.45, 0.091}},
                     {"light", {0.78, 0.78, 0.78}}};
  constexpr int kWhite = 0, kRed = 1, kGreen = 2, kLight = 3;
  auto& s = scene.surfaces;
  s.push_back({"floor", {{552.8, 0, 0}, {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}}, kWhite, {}});
  s.push_back({"ceiling", {{556, 548.8, 0}, {556, 548.8, 559.2}, {0, 548.8, 559.2}, {0, 548.8, 0}}, kWhite, {}});
  s.push_back({"back wall", {{549.6, 0, 559.2}, {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}, kWhite, {}});
  s.push_back({"green wall", {{0, 0, 559.2}, {0, 0, 0}, {0, 548.8, 0}, {0, 548.8, 559.2}}, kGreen, {}});
  s.push_back({"red wall", {{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}, kRed, {}});
  s.push_back({"light", {{343, 548.7, 227}, {343, 548.7, 332}, {213, 548.7, 332}, {213, 548.7, 227}}, kLight, {17, 12, 4}});

  std::vector<Vec3> shortTop{{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}};
  s.push_back({"short block top", shortTop, kWhite, {}});
  addBlockSides(scene, "short block", shortTop, kWhite);
  std::vector<Vec3> tallTop{{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}};
  s.push_back({"tall block top", tallTop, kWhite, {}});
  addBlockSides(scene, "tall block", tallTop, kWhite);

  scene.camera = {{278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3};
  scene.cameraGiven = true;
  // Calibrated: the light's radiance is about white at 0 stops, as in the published images.
  scene.exposureStops = 0.0;
  return scene;
}

Scene cornellBoxWithSpots() {
  Scene scene = cornellBox();
  scene.name = "cornell-spots";
  for (Surface& s : scene.surfaces) s.emittedRadiance = {};
  // Two spots just under the ceiling at the front corners: a warm one on the floor between the
  // blocks, a cool one on the back wall. Each sweeps its footprint around a vertical axis (the
  // cool one also nods about x).
  Light warm;
  warm.name = "warm spot";
  warm.kind = LightKind::Spot;
  warm.position = {450, 530, 120};
  warm.direction = normalize(Vec3{-150, -530, 260});
  warm.intensity = Rgb{1.0, 0.62, 0.3} * 0.5;
  warm.coneAngleDegrees = 20;
  warm.falloffDegrees = 4;
  warm.angularVelocity = {0, 0.6, 0};
  Light cool = warm;
  cool.name = "cool spot";
  cool.position = {110, 530, 120};
  cool.direction = normalize(Vec3{90, -280, 439});
  cool.intensity = Rgb{0.3, 0.55, 1.0} * 0.5;
  cool.angularVelocity = {0.25, -0.8, 0};
  scene.lights = {warm, cool};
  return scene;
}

std::optional<Scene> builtinScene(const std::string& name) {
  if (name == "cornell") return cornellBox();
  if (name == "cornell-spots") return cornellBoxWithSpots();
  return std::nullopt;
}

std::vector<std::string> builtinSceneNames() { return {"cornell", "cornell-spots"}; }

}  // namespace lambert
