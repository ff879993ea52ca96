// Luminaires as lights (LightKind::Luminaire): the photometric frame, the far-field point source
// against CIE 171:2006 §5.2 through the solver, and where the far field breaks against a
// numerically integrated area source.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "lambert/core/photometric.h"
#include "lambert/engine/radiosity.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/load/photometry_file.h"
#include "lambert/mesh/mesh.h"
#include "lambert/light/lights.h"
#include "lambert/light/photometry.h"
#include "lambert/load/scene_file.h"

namespace lambert {
namespace {

constexpr double kDeg = kPi / 180;

// An LM-63-2002 file of I(C, γ) sampled every `step` degrees over the whole sphere (full C range).
std::string iesOf(double (*f)(double, double), double step, double openingMetres = 0, double cStep = 30) {
  std::ostringstream o;
  o.precision(17);
  const int nV = static_cast<int>(std::lround(180 / step)) + 1, nH = static_cast<int>(std::lround(360 / cStep)) + 1;
  o << "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 " << nV << " " << nH << " 1 2 " << openingMetres << " " << openingMetres << " 0\n1 1 10\n";
  for (int v = 0; v < nV; ++v) o << v * step << " ";
  o << "\n";
  for (int h = 0; h < nH; ++h) o << h * cStep << " ";
  o << "\n";
  for (int h = 0; h < nH; ++h) {
    for (int v = 0; v < nV; ++v) o << f(h * cStep, v * step) << " ";
    o << "\n";
  }
  return o.str();
}

std::shared_ptr<const Photometry> photometryOf(double (*f)(double, double), double step, double openingMetres = 0) {
  Result<Photometry> p = parseIes(iesOf(f, step, openingMetres), "test.ies");
  EXPECT_TRUE(p.ok()) << p.error().message;
  return std::make_shared<const Photometry>(std::move(*p));
}

double isotropic(double, double) { return 1000; }
// Non-isotropic and not rotationally symmetric: a batwing-like lobe toward C = 0.
double lobed(double c, double g) {
  return g > 90 ? 0 : 800 * std::cos(g * kDeg) * (1 + 0.5 * std::sin(g * kDeg) * std::cos(c * kDeg));
}
double lambertianDown(double, double g) { return g > 90 ? 0 : 1000 * std::cos(g * kDeg); }

Light luminaire(std::shared_ptr<const Photometry> p, Vec3 position) {
  Light l;
  l.kind = LightKind::Luminaire;
  l.position = position;
  l.photometry = std::move(p);
  l.intensity = Rgb::gray(1);
  return l;
}

double lux(const Rgb& e) { return 683 * (0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b); }

TEST(LuminaireTest, FrameAimsNadirAndTurnsC0AboutIt) {
  Light l = luminaire(photometryOf(lobed, 5), {0, 3, 0});
  LuminaireFrame f = luminaireFrame(l);
  EXPECT_LT(length(f.nadir - Vec3{0, -1, 0}), 1e-12);
  EXPECT_LT(length(f.c0 - Vec3{1, 0, 0}), 1e-12);
  EXPECT_LT(length(f.c90 - Vec3{0, 0, -1}), 1e-12);
  // The lobe leans toward C = 0: more light at +x than at −x, and after a 90° turn at −z.
  const Vec3 n{0, 1, 0};
  const double east = lux(unshadowedIrradiance(l, {1, 0, 0}, n, 1)), west = lux(unshadowedIrradiance(l, {-1, 0, 0}, n, 1));
  EXPECT_GT(east, 1.1 * west);
  l.rotationDegrees = 90;
  EXPECT_NEAR(lux(unshadowedIrradiance(l, {0, 0, -1}, n, 1)), east, 1e-9 * east);
  // Aimed sideways along +x, its nadir is +x and C = 0 falls back on −z.
  l.rotationDegrees = 0;
  l.direction = {1, 0, 0};
  f = luminaireFrame(l);
  EXPECT_LT(length(f.c0 - Vec3{0, 0, -1}), 1e-12);
  double c = 0, g = 0;
  photometricAngles(f, normalize(Vec3{1, 1, 0}), c, g);
  EXPECT_NEAR(g, 45, 1e-9);
}

// CIE 171:2006 §5.2: a point source at height h over a horizontal plane gives
// E = I(γ) cos³γ / h² at the point seen at γ from the nadir. Checked through the scene loader
// ("type": "ies") and the hierarchical solver's point irradiance, for an isotropic and a
// non-isotropic distribution, within 1 %.
TEST(LuminaireTest, Cie171PointSourceOverAPlane) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "lambert_luminaire_test";
  std::filesystem::create_directories(dir);
  const double h = 2.5;
  for (auto f : {isotropic, lobed}) {
    std::ofstream(dir / "lamp.ies") << iesOf(f, 5);
    std::ofstream(dir / "room.json") << R"({"materials": [{"name": "black", "albedo": [0, 0, 0]}],
      "surfaces": [{"name": "floor", "material": "black", "vertices": [[-6, 0, 6], [6, 0, 6], [6, 0, -6], [-6, 0, -6]]}],
      "lights": [{"type": "ies", "file": "lamp.ies", "position": [0, )" << h << R"(, 0], "aim": [0, -1, 0]}]})";
    Result<Scene> scene = readSceneFile((dir / "room.json").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ(scene->lights.size(), 1u);
    RadiosityOptions options;
    options.meshing = MeshStrategy::Hierarchical;
    options.formFactors.showProgress = false;
    auto engine = Radiosity::create(*scene, options);
    ASSERT_TRUE(engine.ok()) << engine.error().message;
    ASSERT_TRUE((*engine)->solve().ok());
    std::vector<SurfacePoint> points;
    std::vector<double> expected;
    for (double x : {0.0, 0.7, 1.9, 3.3, -2.4})
      for (double z : {0.0, -1.2, 2.8}) {
        points.push_back({{x, 0, z}, {0, 1, 0}, 0, 0});
        const double d = std::hypot(x, z), gamma = std::atan2(d, h);
        // C of the point: from +x toward −z (C = 90°), as luminaireFrame lays the planes out.
        double c = std::atan2(-z, x) / kDeg;
        if (c < 0) c += 360;
        expected.push_back(f(c, gamma / kDeg) * std::pow(std::cos(gamma), 3) / (h * h));
      }
    Result<std::vector<Rgb>> e = (*engine)->solution().pointIrradiance(points);
    ASSERT_TRUE(e.ok()) << e.error().message;
    double worst = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_NEAR(lux((*e)[i]), expected[i], 0.01 * expected[i]) << i << " at " << points[i].point.x << ", " << points[i].point.z;
      worst = std::fmax(worst, std::fabs(lux((*e)[i]) / expected[i] - 1));
    }
    std::printf("  CIE 171 5.2, %s: largest deviation from I cos^3(gamma) / h^2: %.4f %%\n", f == isotropic ? "isotropic" : "lobed",
                100 * worst);
  }
}

// Where the far field breaks. A square opening of side s emitting uniformly and diffusely
// (luminance L, I(γ) = L s² cos γ: what the file lambertianDown describes) over a receiver facing
// it on its axis at distance d: the exact E is the opening's integral ∫ L cosθ cosθ' / r² dA
// (midpoint rule, 400² cells); the far-field point source gives I₀/d². Their ratio is the
// far-field error; the Opening model (a 4 × 4 grid of points) is checked too. The luminaire's size
// is the opening's largest dimension, its diagonal s√2.
TEST(LuminaireTest, FarFieldBreaksWithinAboutFiveLuminaireSizes) {
  const double s = 0.6;  // metres
  auto photometry = photometryOf(lambertianDown, 2.5, s);
  const double luminance = 1000 / (s * s);
  std::printf("  d/s    d/diagonal  far-field error  opening (4x4) error  off-axis far-field error\n");
  for (double ratio : {0.5, 1.0, 2.0, 3.0, 5.0, 5 * std::sqrt(2.0), 10.0}) {
    const double d = ratio * s;
    auto exact = [&](const Vec3& x, const Vec3& n) {
      const int cells = 400;
      double e = 0;
      for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j) {
          const Vec3 y{(i + 0.5) / cells * s - s / 2, d, (j + 0.5) / cells * s - s / 2};
          const Vec3 toY = y - x;
          const double r2 = lengthSquared(toY), r = std::sqrt(r2);
          const double cosReceiver = dot(n, toY) / r, cosEmitter = toY.y / r;  // the opening faces −y
          if (cosReceiver > 0) e += luminance * cosReceiver * cosEmitter / r2 * (s * s / (cells * cells));
        }
      return e;
    };
    Light far = luminaire(photometry, {0, d, 0});
    Light area = far;
    area.luminaireModel = LuminaireModel::Opening;
    const Vec3 n{0, 1, 0};
    const double onAxis = exact({0, 0, 0}, n);
    const double farError = lux(unshadowedIrradiance(far, {0, 0, 0}, n, 1)) / onAxis - 1;
    const double areaError = lux(unshadowedIrradiance(area, {0, 0, 0}, n, 1)) / onAxis - 1;
    const Vec3 aside{d, 0, 0.3 * d};
    const double offAxis = exact(aside, n);
    const double farOffError = lux(unshadowedIrradiance(far, aside, n, 1)) / offAxis - 1;
    std::printf("  %5.2f  %5.2f      %+8.3f %%       %+8.3f %%           %+8.3f %%\n", ratio, ratio / std::sqrt(2.0), 100 * farError,
                100 * areaError, 100 * farOffError);
    if (ratio >= 5 * std::sqrt(2.0) - 1e-9) {  // from 5 luminaire sizes on: within 1 %
      EXPECT_LT(std::fabs(farError), 0.01) << ratio;
      EXPECT_LT(std::fabs(farOffError), 0.01) << ratio;
    }
    if (ratio < 2.5) {
      EXPECT_GT(std::fabs(farError), 0.05) << ratio;  // the far field fails up close
    }
    if (ratio >= 1) {
      EXPECT_LT(std::fabs(areaError), std::fabs(farError) / 4) << ratio;  // the opening model holds
    }
  }
}

// Shadow rays go from each of the opening's sources: half an opening hidden behind a wall edge
// lets about half its light through.
TEST(LuminaireTest, OpeningModelCastsAPenumbra) {
  Scene scene;
  scene.materials.push_back({"grey", Rgb::gray(0.5)});
  Surface blocker;
  blocker.name = "blocker";
  // A horizontal plate just under the luminaire covering x < 0, facing up.
  blocker.vertices = {{-5, 1.9, 5}, {0, 1.9, 5}, {0, 1.9, -5}, {-5, 1.9, -5}};
  scene.surfaces.push_back(blocker);
  Mesh mesh = subdivideScene(scene, 1.0);
  auto caster = makeEmbreeRayCaster(mesh);
  Light far = luminaire(photometryOf(lambertianDown, 5, 0.6), {0, 2, 0});
  Light area = far;
  area.luminaireModel = LuminaireModel::Opening;
  const Vec3 x{0, 0, 0}, n{0, 1, 0};
  const double open = lux(unshadowedIrradiance(area, x, n, 1));
  const double seen = lux(irradiance(area, x, n, *caster, 1e-6, 1));
  EXPECT_NEAR(seen / open, 0.5, 0.1);
  EXPECT_EQ(luminaireSources(area, 1).size(), 16u);
}

// The scene file's "ies" light: every field read, two lights of one file share its reading, the
// writer's text reads back to the same light, and what is wrong is an error naming its field.
TEST(LuminaireTest, SceneFileIesLightsReadWriteAndRefuse) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "lambert_luminaire_scene";
  std::filesystem::create_directories(dir / "lamps");
  std::ofstream(dir / "lamps" / "lamp.ies") << iesOf(lobed, 5, 0.3);
  const std::string head = R"({"materials": [{"name": "m", "albedo": [0.5, 0.5, 0.5]}],
    "surfaces": [{"name": "floor", "material": "m", "vertices": [[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]]}], "lights": [)";
  auto parse = [&](const std::string& lights) { return parseSceneFile(head + lights + "]}", (dir / "room.json").string()); };
  Result<Scene> scene = parse(R"({"type": "ies", "file": "lamps/lamp.ies", "position": [0, 3, 0], "aim": [0, -2, 0.5],
      "rotationDegrees": 30, "multiplier": 0.5, "color": [1, 0.5, 0.25], "model": "area", "openingSamples": 3},
      {"type": "ies", "file": "lamps/lamp.ies", "position": [1, 3, 0]})");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->lights.size(), 2u);
  const Light& a = scene->lights[0];
  EXPECT_EQ(a.kind, LightKind::Luminaire);
  EXPECT_EQ(a.photometry, scene->lights[1].photometry);
  EXPECT_LT(length(a.direction - normalize(Vec3{0, -2, 0.5})), 1e-12);
  EXPECT_EQ(a.rotationDegrees, 30);
  EXPECT_EQ(a.intensity.g, 0.25);
  EXPECT_EQ(a.intensity.b, 0.125);
  EXPECT_EQ(a.luminaireModel, LuminaireModel::Opening);
  EXPECT_EQ(a.openingSamplesPerSide, 3);
  const Light& b = scene->lights[1];
  EXPECT_LT(length(b.direction - Vec3{0, -1, 0}), 1e-12);
  EXPECT_EQ(b.intensity.r, 1);
  EXPECT_EQ(b.luminaireModel, LuminaireModel::FarField);
  // Written and read back (from another folder: the file is named by its absolute path).
  const std::string text = sceneFileText(*scene);
  Result<Scene> back = parseSceneFile(text, (std::filesystem::temp_directory_path() / "elsewhere.json").string());
  ASSERT_TRUE(back.ok()) << back.error().message;
  for (std::size_t i = 0; i < 2; ++i) {
    Light x = scene->lights[i], y = back->lights[i];
    ASSERT_TRUE(y.photometry);
    EXPECT_EQ(y.photometry->candelaGrid, x.photometry->candelaGrid);
    y.photometry = x.photometry;
    EXPECT_TRUE(x == y) << i;
  }
  struct Bad {
    std::string light, message;
  } bad[] = {{R"({"type": "ies", "file": "lamps/none.ies", "position": [0, 3, 0]})", "/lights/0/file: "},
             {R"({"type": "ies", "file": "lamps/lamp.ies", "position": [0, 3, 0], "model": "disc"})", "/lights/0/model: unknown luminaire model"},
             {R"({"type": "ies", "file": "lamps/lamp.ies", "position": [0, 3, 0], "openingSamples": 2})", "/lights/0/openingSamples: applies to"},
             {R"({"type": "ies", "file": "lamps/lamp.ies", "position": [0, 3, 0], "aim": [0, 0, 0]})", "/lights/0/aim: the aim must not be zero"},
             {R"({"type": "ies", "file": "lamps/lamp.ies"})", "missing required field \"position\""},
             {R"({"type": "ies", "file": "lamps/lamp.ies", "position": [0, 3, 0], "intensity": [1, 1, 1]})", "/lights/0/intensity: unknown field"}};
  for (const Bad& k : bad) {
    Result<Scene> refused = parse(k.light);
    ASSERT_FALSE(refused.ok()) << k.light;
    EXPECT_NE(refused.error().message.find(k.message), std::string::npos) << refused.error().message;
  }
}

// Maintenance factors (CIE 97): the scene's for every electric light without its own, a light's
// own as one number, {"factor"} or the four parts; each scales the light's output, so its
// illuminance and flux are the maintained ones; the light is written as new with its factor and
// reads back the same; what is out of (0, 1] or on a sun is refused, naming the field.
TEST(LuminaireTest, MaintenanceFactorsScaleTheLightsAndRoundTrip) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "lambert_luminaire_maintenance";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "lamp.ies") << iesOf(lobed, 5, 0.3);
  const std::string head = R"({"materials": [{"name": "m", "albedo": [0.5, 0.5, 0.5]}],
    "surfaces": [{"name": "floor", "material": "m", "vertices": [[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]]}])";
  const std::string lights = R"(, "lights": [{"type": "ies", "file": "lamp.ies", "position": [0, 3, 0]},
      {"type": "ies", "file": "lamp.ies", "position": [0, 3, 0], "maintenance": 0.8},
      {"type": "point", "position": [0, 3, 0], "intensity": [2, 2, 2], "maintenance": {"factor": 0.5}},
      {"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0], "intensity": [2, 2, 2]}]})";
  Result<Scene> fresh = parseSceneFile(head + lights, (dir / "a.json").string());
  Result<Scene> kept = parseSceneFile(head + R"(, "maintenance": {"lampLumen": 0.9, "lampSurvival": 1, "luminaire": 0.9, "roomSurface": 0.95})" + lights,
                                      (dir / "b.json").string());
  ASSERT_TRUE(fresh.ok()) << fresh.error().message;
  ASSERT_TRUE(kept.ok()) << kept.error().message;
  const double sceneFactor = 0.9 * 0.9 * 0.95;
  const double factors[] = {sceneFactor, 0.8, 0.5, sceneFactor};  // with the scene's factor
  const double own[] = {1, 0.8, 0.5, 1};                             // without it
  const Vec3 x{0.4, 0, 0.3}, up{0, 1, 0};
  for (std::size_t i = 0; i < 4; ++i) {
    const Light& a = fresh->lights[i];
    const Light& b = kept->lights[i];
    EXPECT_NEAR(a.maintenance.factor(), own[i], 1e-15) << i;
    EXPECT_NEAR(b.maintenance.factor(), factors[i], 1e-15) << i;
    EXPECT_NEAR(illuminanceLux(unshadowedIrradiance(b, x, up, 1)) / illuminanceLux(unshadowedIrradiance(a, x, up, 1)), factors[i] / own[i], 1e-12) << i;
    EXPECT_NEAR(lightLumens(b) / lightLumens(a), factors[i] / own[i], 1e-12) << i;
  }
  // The second luminaire, 0.8 of the first: its flux too.
  EXPECT_NEAR(lightLumens(fresh->lights[1]) / lightLumens(fresh->lights[0]), 0.8, 1e-12);
  // A point light's flux is 4π·I·683 lm; the maintained one that times MF.
  EXPECT_NEAR(lightLumens(kept->lights[2]), 0.5 * 4 * kPi * 2 * 683, 1e-9);
  // Written as new, read back maintained: the same lights.
  Result<Scene> back = parseSceneFile(sceneFileText(*kept), (dir / "c.json").string());
  ASSERT_TRUE(back.ok()) << back.error().message;
  for (std::size_t i = 0; i < 4; ++i) {
    Light y = back->lights[i];
    y.photometry = kept->lights[i].photometry;
    EXPECT_EQ(y.maintenance, kept->lights[i].maintenance) << i;
    EXPECT_NEAR(y.intensity.g, kept->lights[i].intensity.g, 1e-15) << i;
  }
  struct Bad {
    std::string text, message;
  } bad[] = {{R"(, "maintenance": 0, "lights": [])", "/maintenance: a maintenance factor lies in (0, 1]"},
             {R"(, "maintenance": {"luminaire": 1.2}, "lights": [])", "/maintenance/luminaire"},
             {R"(, "maintenance": {"factor": 0.8, "luminaire": 0.9}, "lights": [])", "/maintenance/luminaire: unknown field"},
             {R"(, "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1], "maintenance": 0.8}])",
              "/lights/0/maintenance: unknown field"}};
  for (const Bad& k : bad) {
    Result<Scene> refused = parseSceneFile(head + k.text + "}", (dir / "d.json").string());
    ASSERT_FALSE(refused.ok()) << k.text;
    EXPECT_NE(refused.error().message.find(k.message), std::string::npos) << refused.error().message;
  }
}

}  // namespace
}  // namespace lambert
