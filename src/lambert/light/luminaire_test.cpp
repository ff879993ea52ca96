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
  // Aimed sideways along +x (LM-72: orient 0, tilt 90), its nadir is +x and C = 0 has risen with
  // the tilt from east to straight up; C = 90 stays north (−z). (Before the LM-72 frame, C = 0
  // fell back on −z here and flipped from up to down as an aim crossed the horizontal.)
  l.rotationDegrees = 0;
  l.direction = {1, 0, 0};
  f = luminaireFrame(l);
  EXPECT_LT(length(f.c0 - Vec3{0, 1, 0}), 1e-12);
  EXPECT_LT(length(f.c90 - Vec3{0, 0, -1}), 1e-12);
  double c = 0, g = 0;
  photometricAngles(f, normalize(Vec3{1, 1, 0}), c, g);
  EXPECT_NEAR(g, 45, 1e-9);
  EXPECT_NEAR(c, 0, 1e-9);
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
// writer's text reads back to the same light (its frame to rounding), and what is wrong is an error naming its field.
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
    // The aim is written as the LM-72 angles (orient, tilt, roll, spin), which give the frame back
    // to rounding, not bit for bit; all else reads back exactly.
    const LuminaireFrame fx = luminaireFrame(x), fy = luminaireFrame(y);
    EXPECT_LT(length(fx.nadir - fy.nadir) + length(fx.c0 - fy.c0) + length(fx.c90 - fy.c90), 1e-12) << i;
    y.direction = x.direction;
    y.rotationDegrees = x.rotationDegrees;
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

// --- Aiming (IES LM-72, "counter-clockwise from east"; docs/photometry.md "Aiming") ---

// An asymmetric floodlight: a cosine beam leaning toward C = 0 (I(C = 0) / I(C = 180) = 1.6 / 0.4
// at γ = 90° − ε), nothing above γ = 90°.
double flood(double c, double g) {
  return g > 90 ? 0 : 1000 * std::cos(g * kDeg) * (1 + 0.6 * std::sin(g * kDeg) * std::cos(c * kDeg));
}

// Lux on a façade 15 m east of a floodlight whose aim sweeps through the horizontal: Orient 0,
// Tilt 80° → 100° in 0.05° steps (from 10° below to 10° above the horizon). The C0 half plane
// turns smoothly with the tilt (it points up at the horizon), so the lux changes smoothly: every
// step within 0.1 % (the issue's "aiming continuous to 0.1 % through ±10° of the horizontal").
// The frame lambert used before (C0 = +x made perpendicular to the aim) flips C0 from up to down
// as the aim crosses the horizontal: rebuilt here from its definition, it jumps by far more.
TEST(LuminaireAimingTest, TiltThroughTheHorizontalIsContinuous) {
  Light l = luminaire(photometryOf(flood, 5), {0, 0, 0});
  const Vec3 point{15, 3, 1}, normal{-1, 0, 0};  // 15 m east, 3 m above the luminaire, 1 m south
  // The lux the old frame gave: the nadir as now, C0 = +x projected off it (−z projected off it
  // where that is under 1e-6 long), C90 = C0 × nadir.
  const auto oldLux = [&](const Vec3& nadir) {
    Vec3 c0 = Vec3{1, 0, 0} - nadir * nadir.x;
    if (length(c0) < 1e-6) c0 = Vec3{0, 0, -1} + nadir * nadir.z;
    c0 = normalize(c0);
    const Vec3 c90 = cross(c0, nadir);
    const Vec3 w = normalize(point);
    double c = std::atan2(dot(w, c90), dot(w, c0)) / kDeg;
    if (c < 0) c += 360;
    const double g = std::acos(dot(w, nadir)) / kDeg;
    return l.photometry->candela(c, g) * dot(-w, normal) / lengthSquared(point);
  };
  double worstNew = 0, worstOld = 0, previousNew = 0, previousOld = 0, atHorizon = 0;
  for (int k = 0; k <= 400; ++k) {
    const double tilt = 80 + 0.05 * k;
    aimLuminaire(l, LuminaireAiming{0, tilt, 0, 0});
    const double now = lux(unshadowedIrradiance(l, point, normal, 1)), old = oldLux(l.direction);
    ASSERT_GT(now, 0);
    if (k == 200) atHorizon = now;
    if (k == 140 || k == 200 || k == 260)
      std::printf("  aim %+.0f deg elevation: %.2f lx (the old frame: %.2f lx)\n", tilt - 90, now, old);
    if (k > 0) {
      worstNew = std::fmax(worstNew, std::fabs(now / previousNew - 1));
      worstOld = std::fmax(worstOld, std::fabs(old / previousOld - 1));
    }
    previousNew = now;
    previousOld = old;
  }
  std::printf("  tilt 80..100 deg in 0.05 deg steps: largest step %.4f %% (the old frame: %.1f %%); %.2f lx at the horizon\n",
              100 * worstNew, 100 * worstOld, atHorizon);
  EXPECT_LT(worstNew, 0.001);
  EXPECT_GT(worstOld, 0.1);  // the flip the test exists for
  // The same sweep as a moving light: an aim turned about the scene's z axis (the east–west
  // vertical plane) by lightAtTime has the frame the tilt gives, so a moving floodlight does not
  // flip either.
  Light moving = l;
  aimLuminaire(moving, LuminaireAiming{0, 80, 0, 0});
  moving.angularVelocity = {0, 0, 20 * kDeg};  // 20°/s about +z: +x toward +y, the aim rising
  for (double seconds : {0.25, 0.5, 0.75}) {
    const LuminaireFrame f = luminaireFrame(lightAtTime(moving, seconds)), g = luminaireFrame(LuminaireAiming{0, 80 + 20 * seconds, 0, 0});
    EXPECT_LT(length(f.nadir - g.nadir) + length(f.c0 - g.c0) + length(f.c90 - g.c90), 1e-12) << seconds;
  }
}

// An asymmetric table whose every grid value says where it is: I = 500 + 400 sin γ · (C mod 360)/360,
// so that a direction's (C, γ), when on the grid (γ a multiple of 5°, C of 30°), reads back from
// its intensity exactly (measured points are reproduced exactly).
double labelled(double c, double g) { return 500 + 400 * std::sin(g * kDeg) * (std::fmod(c, 360) / 360); }

// The candela a luminaire sends along a direction (white, multiplier 1: W/sr × 683).
double candelaToward(const Light& l, const Vec3& direction) { return 683 * luminaireIntensity(l, normalize(direction)).g; }

// Each angle alone, and one combination, against directions whose (C, γ) follow from the
// rotations described in words (scene axes: east +x, up +y, north −z), not from the frame code.
TEST(LuminaireAimingTest, EachAngleAgainstHandComputedDirections) {
  Light l = luminaire(photometryOf(labelled, 5), {0, 0, 0});
  const double s30 = 0.5, c30 = std::sqrt(3.0) / 2, s45 = std::sqrt(0.5);
  const Vec3 down{0, -1, 0};
  // All 0: nadir down, C0 east, C90 north. 30° from down toward north: C = 90, γ = 30.
  aimLuminaire(l, {0, 0, 0, 0});
  EXPECT_NEAR(candelaToward(l, {0, -c30, -s30}), labelled(90, 30), 1e-9);
  // Orient 90 alone: C0 turns from east to north, C90 from north to west. 30° from down toward
  // west is C = 90; toward south C = 180; toward east C = 270.
  aimLuminaire(l, {90, 0, 0, 0});
  EXPECT_NEAR(candelaToward(l, {-s30, -c30, 0}), labelled(90, 30), 1e-9);
  EXPECT_NEAR(candelaToward(l, {0, -c30, s30}), labelled(180, 30), 1e-9);
  EXPECT_NEAR(candelaToward(l, {s30, -c30, 0}), labelled(270, 30), 1e-9);
  // Tilt 30 alone: the nadir lifts 30° toward east (the C0 side), C0 rises to 30° above east,
  // C90 stays north. Straight down lies 30° from the nadir on the side away from C0: C = 180,
  // γ = 30. Due east at the horizon lies 60° from the nadir, in the C0 half plane: C = 0, γ = 60.
  aimLuminaire(l, {0, 30, 0, 0});
  EXPECT_NEAR(candelaToward(l, down), labelled(180, 30), 1e-9);
  EXPECT_NEAR(candelaToward(l, {1, 0, 0}), labelled(0, 60), 1e-9);
  // Due north at the horizon: 90° from the nadir (which has no north part), in the C90 plane.
  EXPECT_NEAR(candelaToward(l, {0, 0, -1}), labelled(90, 90), 1e-9);
  // Roll 30 alone: about C0 (east) the nadir leans 30° toward C90 (north); C90 rises to 30°
  // above north. Straight down lies 30° from the nadir away from C90: C = 270, γ = 30. Due
  // north at the horizon: 60° from the nadir, in the C90 half plane: C = 90, γ = 60.
  aimLuminaire(l, {0, 0, 30, 0});
  EXPECT_NEAR(candelaToward(l, down), labelled(270, 30), 1e-9);
  EXPECT_NEAR(candelaToward(l, {0, 0, -1}), labelled(90, 60), 1e-9);
  // Due east at the horizon stays on C0, 90° from the nadir.
  EXPECT_NEAR(candelaToward(l, {1, 0, 0}), labelled(0, 90), 1e-9);
  // Spin 60 alone: the nadir stays down, C0 turns 60° from east toward north. 45° from down
  // toward east: C = −60 = 300, γ = 45; toward north: C = 30.
  aimLuminaire(l, {0, 0, 0, 60});
  EXPECT_NEAR(candelaToward(l, {s45, -s45, 0}), labelled(300, 45), 1e-9);
  EXPECT_NEAR(candelaToward(l, {0, -s45, -s45}), labelled(30, 45), 1e-9);
  // Orient 90 + Tilt 30 + Spin 90: orient makes C0 north, C90 west; the tilt lifts the nadir 30°
  // toward north (C0 rises to 30° above north), so straight down is 30° from the nadir on the
  // C = 180 side; spinning the planes by +90° brings what was C = 180 to C = 90 (C0 → C90 →
  // C180: a direction at old C lies at C − 90). Due west at the horizon: 90° from the nadir, was
  // C = 90 (C90 west), now C = 0. Due south at the horizon: 120° from the nadir (sin 30° below
  // its plane), on the side away from C0: was C = 180, now C = 90.
  aimLuminaire(l, {90, 30, 0, 90});
  EXPECT_NEAR(candelaToward(l, down), labelled(90, 30), 1e-9);
  EXPECT_NEAR(candelaToward(l, {-1, 0, 0}), labelled(0, 90), 1e-9);
  EXPECT_NEAR(candelaToward(l, {0, 0, 1}), labelled(90, 120), 1e-9);
}

// The inverse a luminaire schedule prints: a light's aim-point angles (roll 0) give back its frame,
// including a negative tilt (an equivalent orient + 180°) and a roll (folded into orient, tilt,
// spin).
TEST(LuminaireAimingTest, ScheduleAnglesGiveTheFrameBack) {
  const LuminaireAiming cases[] = {{0, 0, 0, 0}, {90, 30, 0, 20}, {0, -30, 0, 0}, {45, 60, 25, -70}, {200, 170, 0, 10}, {10, 180, 0, 5}};
  for (const LuminaireAiming& a : cases) {
    Light l = luminaire(photometryOf(flood, 5), {1, 4, 2});
    aimLuminaire(l, a);
    const LuminaireAiming row = aimingOfDirection(l.direction, l.rotationDegrees);
    EXPECT_EQ(row.rollDegrees, 0);
    EXPECT_GE(row.orientDegrees, 0);
    EXPECT_LT(row.orientDegrees, 360);
    EXPECT_GE(row.tiltDegrees, 0);
    EXPECT_LE(row.tiltDegrees, 180);
    const LuminaireFrame f = luminaireFrame(a), g = luminaireFrame(row);
    EXPECT_LT(length(f.nadir - g.nadir) + length(f.c0 - g.c0) + length(f.c90 - g.c90), 1e-12)
        << a.orientDegrees << " " << a.tiltDegrees << " " << a.rollDegrees << " " << a.spinDegrees;
  }
  // Tilt −30 at orient 0 aims 30° from down toward west: orient 180, tilt 30.
  Light l = luminaire(photometryOf(flood, 5), {0, 0, 0});
  aimLuminaire(l, {0, -30, 0, 0});
  EXPECT_NEAR(aimingOfDirection(l.direction, l.rotationDegrees).orientDegrees, 180, 1e-12);
  EXPECT_NEAR(aimingOfDirection(l.direction, l.rotationDegrees).tiltDegrees, 30, 1e-12);
}

// The scene file: the four keys read, written and read back; "aim" + "rotationDegrees" give the
// frame the equivalent angles give; a downlight with a spin keeps the frame lambert always gave
// it (C0 = +x turned counter-clockwise seen from above, toward north −z); both forms at once are
// refused, naming the field.
TEST(LuminaireAimingTest, SceneFileAnglesAndAim) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "lambert_luminaire_aiming";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "flood.ies") << iesOf(flood, 5);
  const std::string head = R"({"materials": [{"name": "m", "albedo": [0.5, 0.5, 0.5]}],
    "surfaces": [{"name": "floor", "material": "m", "vertices": [[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]]}], "lights": [)";
  auto parse = [&](const std::string& lights) { return parseSceneFile(head + lights + "]}", (dir / "site.json").string()); };
  const double c30 = std::sqrt(3.0) / 2;
  Result<Scene> scene = parse(R"({"type": "ies", "file": "flood.ies", "position": [0, 8, 0], "orient": 90, "tilt": 30, "roll": 10, "spin": 20},
      {"type": "ies", "file": "flood.ies", "position": [0, 8, 0], "orient": 90, "tilt": 30, "spin": 20},
      {"type": "ies", "file": "flood.ies", "position": [0, 8, 0], "aim": [0, -0.8660254037844386, -0.5], "rotationDegrees": 20},
      {"type": "ies", "file": "flood.ies", "position": [0, 3, 0], "spin": 40},
      {"type": "ies", "file": "flood.ies", "position": [0, 3, 0], "aim": [0, -1, 0], "rotationDegrees": 40})");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->lights.size(), 5u);
  const auto near = [](const LuminaireFrame& f, const LuminaireFrame& g) {
    return length(f.nadir - g.nadir) + length(f.c0 - g.c0) + length(f.c90 - g.c90) < 1e-12;
  };
  EXPECT_TRUE(near(luminaireFrame(scene->lights[0]), luminaireFrame(LuminaireAiming{90, 30, 10, 20})));
  // Orient 90, tilt 30: the nadir 30° from down toward north, (0, −cos 30°, −sin 30°).
  EXPECT_LT(length(scene->lights[1].direction - Vec3{0, -c30, -0.5}), 1e-12);
  EXPECT_TRUE(near(luminaireFrame(scene->lights[1]), luminaireFrame(scene->lights[2])));
  EXPECT_EQ(scene->lights[2].rotationDegrees, 20);
  // The downlights: nadir −y, C0 = (cos 40°, 0, −sin 40°), C90 = C0 × nadir = (−sin 40°, 0, −cos 40°).
  const double s40 = std::sin(40 * kDeg), c40 = std::cos(40 * kDeg);
  for (std::size_t i : {3u, 4u}) {
    const LuminaireFrame f = luminaireFrame(scene->lights[i]);
    EXPECT_LT(length(f.nadir - Vec3{0, -1, 0}), 1e-15) << i;
    EXPECT_LT(length(f.c0 - Vec3{c40, 0, -s40}), 1e-15) << i;
    EXPECT_LT(length(f.c90 - Vec3{-s40, 0, -c40}), 1e-15) << i;
  }
  // Written as the four angles, and read back to the same frames.
  const std::string text = sceneFileText(*scene);
  EXPECT_NE(text.find("\"orient\""), std::string::npos);
  EXPECT_NE(text.find("\"roll\""), std::string::npos);
  EXPECT_EQ(text.find("\"aim\""), std::string::npos);
  Result<Scene> back = parseSceneFile(text, (dir / "again.json").string());
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_EQ(back->lights.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_TRUE(near(luminaireFrame(scene->lights[i]), luminaireFrame(back->lights[i]))) << i;
  // Both forms at once: refused, naming the first angle given.
  for (const char* both : {R"("aim": [1, 0, 0], "tilt": 90)", R"("rotationDegrees": 10, "spin": 10)"}) {
    Result<Scene> refused = parse(std::string(R"({"type": "ies", "file": "flood.ies", "position": [0, 3, 0], )") + both + "}");
    ASSERT_FALSE(refused.ok()) << both;
    EXPECT_NE(refused.error().message.find("either by \"aim\""), std::string::npos) << refused.error().message;
    EXPECT_NE(refused.error().message.find("/lights/0/"), std::string::npos) << refused.error().message;
  }
}

}  // namespace
}  // namespace lambert
