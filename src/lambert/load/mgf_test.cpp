#include "lambert/load/mgf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>

#include "lambert/core/warning.h"
#include "lambert/light/lights.h"
#include "lambert/light/photometry.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}


// MGF is z-up, lambert y-up: (x, y, z) → (x, z, −y).
Vec3 fromMgf(const Vec3& p) { return {p.x, p.z, -p.y}; }

Result<Scene> readText(const std::string& test, const std::string& text, const MgfOptions& options = {}) {
  const fs::path dir = testing::scratchDirectory("mgf", test);
  write(dir / "t.mgf", text);
  return readMgf((dir / "t.mgf").string(), options);
}

bool hasVertex(const Scene& scene, const Vec3& p, double tolerance = 1e-9) {
  for (const Surface& s : scene.surfaces)
    for (const Vec3& v : s.vertices)
      if (length(v - p) < tolerance) return true;
  return false;
}

double totalArea(const Scene& scene) {
  double area = 0;
  for (const Surface& s : scene.surfaces) area += surfaceArea(s);
  return area;
}

// Calls check(centroid, area vector) for every face of the scene.
void forEachFace(const Scene& scene, const std::function<void(const Vec3&, const Vec3&)>& check) {
  for (const Surface& s : scene.surfaces)
    for (const auto& face : surfaceFaces(s)) {
      const std::vector<Vec3> corners = facePositions(s, face);
      Vec3 centroid;
      for (const Vec3& c : corners) centroid += c;
      check(centroid / static_cast<double>(corners.size()), polygonAreaVector(corners));
    }
}

const Surface& surfaceNamed(const Scene& scene, const std::string& name) {
  for (const Surface& s : scene.surfaces)
    if (s.name == name) return s;
  ADD_FAILURE() << "no surface " << name;
  return scene.surfaces.at(0);
}

void expectRgbNear(const Rgb& actual, const Rgb& expected, double tolerance) {
  EXPECT_NEAR(actual.r, expected.r, tolerance);
  EXPECT_NEAR(actual.g, expected.g, tolerance);
  EXPECT_NEAR(actual.b, expected.b, tolerance);
}

// Photometric emittance (lm/m²) → lambert's L_e (W/(m²·sr)) for a white emitter: ÷ π ÷ 683 lm/W.
constexpr double kLeOfOneLux = 1 / (kPi * 683);

TEST(MgfTest, FacesMaterialsSidesUnitsAndAxes) {
  WarningCapture captured;
  Result<Scene> scene = readText("faces", R"(# a floor and a lamp, z up
m floor =
	c
		cxy .3333333333 .3333333333
	rd .5
	sides 1
v a =
	p 0 0 0
v b =
	p 2 0 0
v c = a
	p 2 2 0
v d =
	p 0 2 \
	  0
o room
	f a b c d
	o lamp
		m lamp =
			ed 1000
			rd .2
		v l1 =
			p .5 .5 2
		v l2 =
			p .5 1.5 2
		v l3 =
			p 1.5 1.5 2
		v l4 =
			p 1.5 .5 2
		f l1 l2 l3 l4
	o
o
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->name, "t");
  EXPECT_EQ(scene->metresPerUnit, 1);  // MGF is in metres
  ASSERT_EQ(scene->surfaces.size(), 2u);
  const Surface& floor = surfaceNamed(*scene, "room");
  EXPECT_NEAR(surfaceArea(floor), 4, 1e-12);
  EXPECT_GT(surfaceNormal(floor).y, 0.999);  // MGF's +z (counter-clockwise from above) is lambert's +y
  EXPECT_TRUE(hasVertex(*scene, fromMgf({2, 2, 0})));
  EXPECT_TRUE(hasVertex(*scene, {2, 0, -2}));
  const Material& floorMaterial = scene->materials[floor.material];
  EXPECT_EQ(floorMaterial.name, "floor");
  expectRgbNear(floorMaterial.albedo, Rgb::gray(0.5), 1e-9);
  EXPECT_FALSE(floorMaterial.twoSided);  // sides 1
  EXPECT_EQ(floor.emittedRadiance, Rgb{});

  const Surface& lamp = surfaceNamed(*scene, "room/lamp");
  EXPECT_LT(surfaceNormal(lamp).y, -0.999);  // clockwise from above: facing down
  const Material& lampMaterial = scene->materials[lamp.material];
  EXPECT_TRUE(lampMaterial.twoSided);  // MGF's default is 2 sides
  expectRgbNear(lampMaterial.albedo, Rgb::gray(0.2), 1e-9);
  expectRgbNear(lamp.emittedRadiance, Rgb::gray(1000 * kLeOfOneLux), 1e-9);
  EXPECT_NEAR(lamp.emittedRadiance.r, 0.466047, 1e-6);  // 1000 / (π · 683)
  EXPECT_EQ(captured.messages(), std::vector<std::string>{});
}

TEST(MgfTest, DefaultMaterialIsBlackAndTwoSidedAndBareMResetsIt) {
  Result<Scene> scene = readText("default-material", R"(v a =
	p 0 0 0
v b =
	p 1 0 0
v c =
	p 0 1 0
f a b c
m
	rd .3
	sides 1
xf -t 5 0 0
f a b c
xf
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->surfaces.size(), 2u);
  const Material& first = scene->materials[scene->surfaces[0].material];
  const Material& second = scene->materials[scene->surfaces[1].material];
  EXPECT_EQ(first.albedo, Rgb{});  // MGF's default rd is 0
  EXPECT_TRUE(first.twoSided);
  expectRgbNear(second.albedo, Rgb::gray(0.3), 1e-9);
  EXPECT_FALSE(second.twoSided);
}

const char* kTriangle = R"(v a =
	p 0 0 0
v b =
	p 1 0 0
v c =
	p 0 1 0
)";

TEST(MgfTest, TransformsActInOrderAndNestInnerFirst) {
  Result<Scene> scene = readText("xf", std::string(kTriangle) + R"(xf -t 10 0 0
	xf -s 2
		f a b c
	xf
xf
xf -rz 90 -t 0 0 3
	f a b c
xf
xf -t 0 0 7 -mz
	f a b c
xf
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  // Inner -s 2 first, then the outer -t 10: (1, 0, 0) → (12, 0, 0).
  EXPECT_TRUE(hasVertex(*scene, fromMgf({12, 0, 0})));
  EXPECT_TRUE(hasVertex(*scene, fromMgf({10, 2, 0})));
  // -rz 90 (counter-clockwise looking down z) then the translation: (1, 0, 0) → (0, 1, 3).
  EXPECT_TRUE(hasVertex(*scene, fromMgf({0, 1, 3}), 1e-12));
  EXPECT_TRUE(hasVertex(*scene, fromMgf({-1, 0, 3}), 1e-12));
  // -t then -mz: z = −7, and the mirror turns the face over (its normal now −z: lambert −y).
  EXPECT_TRUE(hasVertex(*scene, fromMgf({1, 0, -7})));
  ASSERT_EQ(scene->surfaces.size(), 3u);
  EXPECT_GT(surfaceNormal(scene->surfaces[0]).y, 0.999);
  EXPECT_LT(surfaceNormal(scene->surfaces[2]).y, -0.999);
}

TEST(MgfTest, ArraysRepeatTheEnclosedEntitiesCumulatively) {
  Result<Scene> scene = readText("array", std::string(kTriangle) + R"(xf -t 1 0 0 -a 3 -t 0 2 0 -a 2 -t 0 0 5
	f a b c
xf
xf -i 3 -t 1 0 0
	f a b c
xf
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->surfaces.size(), 7u);  // 3 × 2 instances, and one more
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j) {
      EXPECT_TRUE(hasVertex(*scene, fromMgf({1, 2.0 * i, 5.0 * j}))) << i << " " << j;
      EXPECT_TRUE(hasVertex(*scene, fromMgf({2, 2.0 * i, 5.0 * j}))) << i << " " << j;
    }
  EXPECT_FALSE(hasVertex(*scene, fromMgf({1, 6, 0})));  // no fourth instance
  EXPECT_TRUE(hasVertex(*scene, fromMgf({3, 0, 0})));   // -i 3: three steps at once
  EXPECT_NEAR(totalArea(*scene), 7 * 0.5, 1e-12);
}

TEST(MgfTest, IncludesAreRelativeToTheIncludingFileAndTakeATransform) {
  const fs::path dir = testing::scratchDirectory("mgf", "include");
  write(dir / "top.mgf", "i parts/room.mgf -t 5 0 0\ni parts/room.mgf -a 2 -t 0 10 0\n");
  write(dir / "parts" / "room.mgf", "m white =\n\trd .5\ni tile.mgf\n");
  write(dir / "parts" / "tile.mgf", std::string(kTriangle) + "f a b c\n");
  Result<Scene> scene = readMgf((dir / "top.mgf").string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->surfaces.size(), 3u);
  EXPECT_TRUE(hasVertex(*scene, fromMgf({6, 0, 0})));
  EXPECT_TRUE(hasVertex(*scene, fromMgf({1, 0, 0})));
  EXPECT_TRUE(hasVertex(*scene, fromMgf({1, 10, 0})));
  EXPECT_TRUE(hasVertex(*scene, fromMgf({0, 11, 0})));
  EXPECT_EQ(scene->materials[scene->surfaces[0].material].name, "white");
}

// Every face's normal points away from (outward) or toward (inward) the primitive's inside,
// given by the point of its core nearest the face's centroid.
int countFacing(const Scene& scene, const std::function<Vec3(const Vec3&)>& corePoint, bool outward) {
  int wrong = 0;
  forEachFace(scene, [&](const Vec3& centroid, const Vec3& area) {
    const double d = dot(area, centroid - corePoint(centroid));
    wrong += outward ? d <= 0 : d >= 0;
  });
  return wrong;
}

struct Primitive {
  std::string name, text;
  double exactArea;
  std::function<Vec3(const Vec3&)> core;  // in lambert coordinates
};

TEST(MgfTest, CurvedPrimitivesAreaAndOrientation) {
  const MgfOptions options{.divisions = 64, .regions = {}, .includeRoot = {}};
  const std::string vertices = R"(v o =
	p 0 0 0
	n 0 0 1
v top =
	p 0 0 2
v p0 =
	p 0 0 0
v p1 =
	p 0 1 0
v p2 =
	p 1 1 0
v p3 =
	p 1 0 0
)";
  // The z axis of MGF is lambert's y axis: the core of an axial primitive is its nearest point
  // on that axis, of the torus the nearest point on its core circle (radius 1.5 in y = 0).
  auto axis = [](const Vec3& p) { return Vec3{0, p.y, 0}; };
  auto torusCore = [](const Vec3& p) { return 1.5 * normalize(Vec3{p.x, 0, p.z}); };
  const std::vector<Primitive> primitives = {
      {"sphere", "sph o 1.5", 4 * kPi * 1.5 * 1.5, [](const Vec3&) { return Vec3{}; }},
      {"cylinder", "cyl o 0.5 top", 2 * kPi * 0.5 * 2, axis},
      {"cone", "cone o 1 top 0.5", kPi * (1 + 0.5) * std::sqrt(0.25 + 4), axis},
      {"apex", "cone o 1 top 0", kPi * 1 * std::sqrt(1 + 4), axis},
      {"torus", "torus o 1 2", 4 * kPi * kPi * 1.5 * 0.5, torusCore},
      {"prism", "prism p0 p1 p2 p3 1", 6, [](const Vec3&) { return fromMgf({0.5, 0.5, 0.5}); }},
  };
  for (const Primitive& p : primitives) {
    SCOPED_TRACE(p.name);
    Result<Scene> out = readText(p.name, vertices + p.text + "\n", options);
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_NEAR(totalArea(*out), p.exactArea, 0.01 * p.exactArea);  // inscribed: within 1% at 64
    EXPECT_LT(totalArea(*out), p.exactArea + 1e-9);
    EXPECT_EQ(countFacing(*out, p.core, true), 0);
    // A negative radius (a negative prism length) turns every face inward.
    std::string inward = p.text;
    if (p.name == "sphere") inward = "sph o -1.5";
    if (p.name == "cylinder") inward = "cyl o -0.5 top";
    if (p.name == "cone") inward = "cone o -1 top -0.5";
    if (p.name == "apex") inward = "cone o -1 top 0";
    if (p.name == "torus") inward = "torus o -1 -2";
    if (p.name == "prism") {  // extruded toward the face's front (−z), so its inside moves there
      Result<Scene> in = readText(p.name + "-in", vertices + "prism p0 p1 p2 p3 -1\n", options);
      ASSERT_TRUE(in.ok()) << in.error().message;
      EXPECT_EQ(countFacing(*in, [](const Vec3&) { return fromMgf({0.5, 0.5, -0.5}); }, false), 0);
      continue;
    }
    Result<Scene> in = readText(p.name + "-in", vertices + inward + "\n", options);
    ASSERT_TRUE(in.ok()) << in.error().message;
    EXPECT_NEAR(totalArea(*in), p.exactArea, 0.01 * p.exactArea);
    EXPECT_EQ(countFacing(*in, p.core, false), 0);
  }
}

TEST(MgfTest, RingFacesAlongItsVertexNormal) {
  const MgfOptions options{.divisions = 64, .regions = {}, .includeRoot = {}};
  Result<Scene> scene = readText("ring", R"(v up =
	p 0 0 0
	n 0 0 1
v down =
	p 0 0 1
	n 0 0 -1
o annulus
	ring up 1 2
o
o disc
	ring down 0 1
o
)", options);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Surface& annulus = surfaceNamed(*scene, "annulus");
  const Surface& disc = surfaceNamed(*scene, "disc");
  EXPECT_NEAR(surfaceArea(annulus), kPi * (4 - 1), 0.01 * kPi * 3);
  EXPECT_NEAR(surfaceArea(disc), kPi, 0.01 * kPi);
  EXPECT_GT(surfaceNormal(annulus).y, 0.999);
  EXPECT_LT(surfaceNormal(disc).y, -0.999);
}

// The albedo of a one-triangle scene with the given colour lines and rd.
Rgb albedoOf(const std::string& test, const std::string& colour, double rd) {
  Result<Scene> scene = readText(test, std::string(kTriangle) + "m x =\n" + colour + "\n\trd " + std::to_string(rd) + "\nf a b c\n");
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  if (!scene.ok()) return {};
  return scene->materials[scene->surfaces.at(0).material].albedo;
}

TEST(MgfTest, CxyToRgb) {
  // MGF's white is equal-energy, (1/3, 1/3): it is RGB (1, 1, 1), and rd its grey.
  expectRgbNear(albedoOf("white", "\tc\n\t\tcxy 0.333333333333 0.333333333333", 0.8), Rgb::gray(0.8), 1e-9);
  expectRgbNear(albedoOf("default-colour", "", 0.8), Rgb::gray(0.8), 1e-12);
  // Rec. 709's red primary: only the red channel, its luminance 0.2126·R equal to rd.
  expectRgbNear(albedoOf("red", "\tc\n\t\tcxy 0.64 0.33", 0.2), {0.2 / 0.2126, 0, 0}, 2e-3);
  // Rec. 709's green primary, by hand: luminance 0.7152·G = rd.
  expectRgbNear(albedoOf("green", "\tc\n\t\tcxy 0.30 0.60", 0.5), {0, 0.5 / 0.7152, 0}, 3e-3);
}

TEST(MgfTest, SpectraBlackBodiesAndMixtures) {
  // A flat spectrum over the visible range is (nearly) equal-energy white.
  const Rgb flat = albedoOf("flat", "\tc\n\t\tcspec 380 780 1 1 1 1 1", 0.5);
  expectRgbNear(flat, Rgb::gray(0.5), 0.01);
  // A black body is the chromaticity of the Planckian locus at its temperature: against the
  // cubic-spline fit of Kim et al. (2002), independent of the spectral integration; within the
  // colour matching functions' fit error.
  expectRgbNear(albedoOf("cct6504", "\tc\n\t\tcct 6504", 0.5), albedoOf("xy6504", "\tc\n\t\tcxy 0.31343 0.32360", 0.5), 0.006);
  expectRgbNear(albedoOf("cct3000", "\tc\n\t\tcct 3000", 0.2), albedoOf("xy3000", "\tc\n\t\tcxy 0.43658 0.40417", 0.2), 0.004);
  // 6504 K is near D65 (x, y) = (0.3127, 0.3290), which in lambert's E-white RGB is 1/(E's
  // Rec. 709 RGB) per channel: E = XYZ (1, 1, 1) → (1.20478, 0.94830, 0.90884); at luminance rd.
  const Rgb d65{1 / 1.2047843, 1 / 0.9483008, 1 / 0.9088427};
  const Rgb cct = albedoOf("cct", "\tc\n\t\tcct 6504", 0.5);
  expectRgbNear(cct, 0.5 * d65 / d65.luminance(), 0.03);
  EXPECT_GT(cct.b, cct.r);  // bluer than MGF's white
  // 5455 K is the black body nearest equal-energy white (a little greener).
  expectRgbNear(albedoOf("cct5455", "\tc\n\t\tcct 5455", 0.5), Rgb::gray(0.5), 0.04);
  // cmix weights are luminances: equal parts of (0.64, 0.33) and (0.15, 0.06) are the colour of
  // the XYZ sum at unit luminance each: X = 0.64/0.33 + 0.15/0.06, Y = 2, Z = 0.03/0.33 + 0.79/0.06.
  const double X = 0.64 / 0.33 + 0.15 / 0.06, Y = 2, Z = 0.03 / 0.33 + 0.79 / 0.06;
  const std::string mixed = "\tc\n\t\tcxy " + std::to_string(X / (X + Y + Z)) + " " + std::to_string(Y / (X + Y + Z));
  const Rgb byHand = albedoOf("mix-by-hand", mixed, 0.05);
  const Rgb mix = albedoOf("mix", "c r =\n\tcxy 0.64 0.33\nc b =\n\tcxy 0.15 0.06\nc\n\tcmix 1 r 1 b", 0.05);
  expectRgbNear(mix, byHand, 1e-5);
}

TEST(MgfTest, EmissionIsLumensPerSquareMetreOverPiAnd683) {
  Result<Scene> scene = readText("ed", std::string(kTriangle) + R"(m warm =
	c
		cct 3000
	ed 87712
f a b c
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Rgb le = scene->surfaces.at(0).emittedRadiance;
  EXPECT_NEAR(le.luminance(), 87712 * kLeOfOneLux, 1e-9 * 87712);  // the colour keeps its luminance
  EXPECT_GT(le.r, le.g);
  EXPECT_GT(le.g, le.b);  // 3000 K is orange
}

TEST(MgfTest, IgnoredAndUnknownEntitiesWarnOncePerKind) {
  WarningCapture captured;
  Result<Scene> scene = readText("ignored", std::string(kTriangle) + R"(m glass =
	rs .1 .02
	rs .2 .02
	td .3
	ir 1.5 0
	ts .8 0
foo 1 2
foo 3
fh a b c
f a b c
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(captured.count("rs (specular reflectance) is ignored"), 1);
  EXPECT_EQ(captured.count("t.mgf:8: rs"), 1);  // names the first one's file and line
  EXPECT_EQ(captured.count("td (diffuse transmittance)"), 1);
  EXPECT_EQ(captured.count("ir (index of refraction)"), 1);
  EXPECT_EQ(captured.count("ts (specular transmittance)"), 1);
  EXPECT_EQ(captured.count("t.mgf:13: unknown entity 'foo'"), 1);
  EXPECT_EQ(captured.count("unknown entity"), 1);
  EXPECT_EQ(captured.count("t.mgf:15: fh (face with holes) is not supported"), 1);
  EXPECT_EQ(captured.messages().size(), 6u);
}

struct BadInput {
  std::string name, text, message;
};

TEST(MgfTest, BadInputIsAnErrorWithFileAndLine) {
  const std::vector<BadInput> cases = {
      {"unknown-vertex", "v a =\n\tp 0 0 0\nf a b c\n", "t.mgf:3: f: undefined vertex 'b'"},
      {"argument-count", "v a =\n\tp 0 0 0\nsph a\n", "t.mgf:3: sph takes 2 arguments, not 1"},
      {"argument-type", "m x =\n\trd half\n", "t.mgf:2: rd: expected a number, got 'half'"},
      {"non-finite", "v a =\n\tp 1e999 0 0\n", "t.mgf:2: p: '1e999' is not a finite number"},
      {"nan", "v a =\n\tp nan 0 0\n", "t.mgf:2: p: 'nan' is not a finite number"},
      {"negative-rd", "m x =\n\trd -0.1\n", "t.mgf:2: rd -0.1: a reflectance must not be negative; give one between 0 and 1"},
      {"negative-ed", "m x =\n\ted -5\n", "t.mgf:2: ed -5: an emittance must not be negative; give it in lm/m²"},
      {"cold-cct", "c\n\tcct 50\n", "t.mgf:2: cct 50: a black body below 100 K gives no visible light; give the colour temperature"},
      {"ring-negative", "v c =\n\tp 0 0 0\n\tn 0 0 1\nring c -1 1\n", "t.mgf:4: ring: the radii must not be negative"},
      {"undefined-material", "m nope\n", "t.mgf:1: m: undefined material 'nope'"},
      {"undefined-colour", "c\n\tcmix 1 nope\n", "t.mgf:2: cmix: undefined colour 'nope'"},
      {"sides", "m x =\n\tsides 3\n", "t.mgf:2: sides 3: must be 1 (one-sided) or 2 (two-sided)"},
      {"bad-xf-flag", "xf -q 1\nxf\n", "t.mgf:1: xf: unknown transformation argument '-q'"},
      {"missing-include", "\n\ni nothere.mgf\n", "t.mgf:3: cannot open include 'nothere.mgf' (looked for "},
      {"cycle", "i t.mgf\n", "t.mgf:1: include cycle: 't.mgf' is already being read"},
      {"ring-without-normal", "v c =\n\tp 0 0 0\nring c 0 1\n", "t.mgf:3: ring: the centre vertex 'c' has no normal"},
      {"cone-signs", "v a =\n\tp 0 0 0\nv b =\n\tp 0 0 1\ncone a 1 b -1\n", "t.mgf:5: cone: the radii must not have different signs"},
      {"no-faces", "v a =\n\tp 0 0 0\n", "t.mgf: no faces"},
  };
  for (const BadInput& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path dir = testing::scratchDirectory("mgf-bad", c.name);
    write(dir / "top" / "t.mgf", c.text);
    write(dir / "outside.mgf", std::string(kTriangle) + "f a b c\n");
    Result<Scene> scene = readMgf((dir / "top" / "t.mgf").string());
    ASSERT_FALSE(scene.ok());
    EXPECT_TRUE(testing::contains(scene.error().message, c.message)) << scene.error().message;
  }
}

TEST(MgfTest, IncludeCyclesAndDepthAreErrorsInTheIncludedFile) {
  const fs::path dir = testing::scratchDirectory("mgf", "cycle");
  write(dir / "a.mgf", "i sub/b.mgf\n");
  write(dir / "sub" / "b.mgf", "# b\ni ../a.mgf\n");
  Result<Scene> cycle = readMgf((dir / "a.mgf").string());
  ASSERT_FALSE(cycle.ok());
  EXPECT_TRUE(testing::contains(cycle.error().message, "b.mgf:2: include cycle: '../a.mgf'")) << cycle.error().message;

  // 40 files, each including the next: deeper than 32.
  auto deepName = [](int i) {
    std::string name = "d";
    name += std::to_string(i);
    name += ".mgf";
    return name;
  };
  for (int i = 0; i < 40; ++i) write(dir / deepName(i), std::string("i ") + deepName(i + 1) + "\n");
  write(dir / "d40.mgf", std::string(kTriangle) + "f a b c\n");
  Result<Scene> deep = readMgf((dir / "d0.mgf").string());
  ASSERT_FALSE(deep.ok());
  EXPECT_TRUE(testing::contains(deep.error().message, "d32.mgf:1: includes nested deeper than 32 levels")) << deep.error().message;
}

TEST(MgfTest, ShippedFloorScene) {
  WarningCapture captured;
  Result<Scene> scene = readMgf(std::string(LAMBERT_SOURCE_DIR) + "/scenes/floor/floor.mgf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(captured.messages(), std::vector<std::string>{});
  std::size_t faces = 0, emitters = 0;
  for (const Surface& s : scene->surfaces) {
    faces += surfaceFaces(s).size();
    emitters += s.emittedRadiance.maxComponent() > 0;
  }
  EXPECT_GT(faces, 100u);
  EXPECT_LT(faces, 2000u);
  EXPECT_GE(emitters, 4u);
  const Bounds bounds = sceneBounds(*scene);
  EXPECT_GT(bounds.hi.y - bounds.lo.y, 5.0);  // two storeys, y up
}

// RenderPark's hospital: hospital/hosp.mgf → parts of it → ../Materials/, a folder beside the
// top file's. Includes are relative to the including file wherever they lead; includeRoot
// confines them, links resolved.
TEST(MgfTest, IncludesGoUpFoldersUnlessConfinedToARoot) {
  const fs::path dir = testing::scratchDirectory("mgf", "include-up");
  write(dir / "hospital" / "hosp.mgf", "i parts/structure.mgf\n");
  write(dir / "hospital" / "parts" / "structure.mgf", "i ./../../Materials/lib.mgf\nm tile\n" + std::string(kTriangle) + "f a b c\n");
  write(dir / "Materials" / "lib.mgf", "m tile =\n\trd .25\n");
  const std::string top = (dir / "hospital" / "hosp.mgf").string();

  WarningCapture captured;
  Result<Scene> scene = readMgf(top);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(captured.messages(), std::vector<std::string>{});
  const Material& tile = scene->materials[scene->surfaces.at(0).material];
  EXPECT_EQ(tile.name, "tile");
  expectRgbNear(tile.albedo, Rgb::gray(0.25), 1e-12);  // the included file's material

  MgfOptions confined;
  confined.includeRoot = (dir / "hospital").string();
  Result<Scene> refused = readMgf(top, confined);
  ASSERT_FALSE(refused.ok());
  const std::string& message = refused.error().message;
  EXPECT_TRUE(testing::contains(message, "structure.mgf:1: include './../../Materials/lib.mgf' is ")) << message;
  EXPECT_TRUE(testing::contains(message, "lib.mgf, outside the folder includes are confined to (" + confined.includeRoot + ")")) << message;
  EXPECT_TRUE(testing::contains(message, "give a root that holds it")) << message;

  confined.includeRoot = dir.string();  // a root holding both folders
  EXPECT_TRUE(readMgf(top, confined).ok());

  // A symbolic link inside the root that leads out of it is outside.
  write(dir / "hospital" / "linked.mgf", "i parts/via-link.mgf\n");
  std::error_code ec;
  fs::create_symlink(dir / "Materials" / "lib.mgf", dir / "hospital" / "parts" / "via-link.mgf", ec);
  if (!ec) {
    confined.includeRoot = (dir / "hospital").string();
    Result<Scene> linked = readMgf((dir / "hospital" / "linked.mgf").string(), confined);
    ASSERT_FALSE(linked.ok());
    EXPECT_TRUE(testing::contains(linked.error().message, "linked.mgf:1: include 'parts/via-link.mgf' is ")) << linked.error().message;
  }
}

// CIE 1931 2° colour matching functions x̄, ȳ, z̄ at 380, 390, ..., 780 nm (the CIE's table),
// independent of the reader's analytic fit.
constexpr double kCie1931[41][3] = {
    {0.001368, 0.000039, 0.006450}, {0.004243, 0.000120, 0.020050}, {0.014310, 0.000396, 0.067850}, {0.043510, 0.001210, 0.207400},
    {0.134380, 0.004000, 0.645600}, {0.283900, 0.011600, 1.385600}, {0.348280, 0.023000, 1.747060}, {0.336200, 0.038000, 1.772110},
    {0.290800, 0.060000, 1.669200}, {0.195360, 0.090980, 1.287640}, {0.095640, 0.139020, 0.812950}, {0.032010, 0.208020, 0.465180},
    {0.004900, 0.323000, 0.272000}, {0.009300, 0.503000, 0.158200}, {0.063270, 0.710000, 0.078250}, {0.165500, 0.862000, 0.042160},
    {0.290400, 0.954000, 0.020300}, {0.433450, 0.994950, 0.008750}, {0.594500, 0.995000, 0.003900}, {0.762100, 0.952000, 0.002100},
    {0.916300, 0.870000, 0.001650}, {1.026300, 0.757000, 0.001100}, {1.062200, 0.631000, 0.000800}, {1.002600, 0.503000, 0.000340},
    {0.854450, 0.381000, 0.000190}, {0.642400, 0.265000, 0.000050}, {0.447900, 0.175000, 0.000020}, {0.283500, 0.107000, 0},
    {0.164900, 0.061000, 0},        {0.087400, 0.032000, 0},        {0.046770, 0.017000, 0},        {0.022700, 0.008210, 0},
    {0.011359, 0.004102, 0},        {0.005790, 0.002091, 0},        {0.002899, 0.001047, 0},        {0.001440, 0.000520, 0},
    {0.000690, 0.000249, 0},        {0.000332, 0.000120, 0},        {0.000166, 0.000060, 0},        {0.000083, 0.000030, 0},
    {0.000042, 0.000015, 0}};

// (x, y) of a spectrum sampled at 380, 390, ..., 780 nm, by the table.
std::pair<double, double> chromaticityByTable(const std::vector<double>& samples) {
  double xyz[3] = {0, 0, 0};
  for (std::size_t i = 0; i < 41; ++i)
    for (int k = 0; k < 3; ++k) xyz[k] += samples[i] * kCie1931[i][k];
  const double sum = xyz[0] + xyz[1] + xyz[2];
  return {xyz[0] / sum, xyz[1] / sum};
}

std::string cxyText(const std::pair<double, double>& xy) {
  return "\tc\n\t\tcxy " + std::to_string(xy.first) + " " + std::to_string(xy.second);
}

TEST(MgfTest, NegativeSpectralSamplesCountAsTheyIntegrate) {
  // Flat, but -0.2 at 440–460 nm, where z̄ peaks: a real (yellowish) colour whose integral
  // depends on the negative samples' sign.
  std::vector<double> samples(41, 1.0);
  for (int i = 6; i <= 8; ++i) samples[i] = -0.2;
  std::string cspec = "\tc\n\t\tcspec 380 780";
  for (double v : samples) cspec.append(" ").append(std::to_string(v));
  WarningCapture captured;
  const Rgb read = albedoOf("cspec-negative", cspec, 0.5);
  EXPECT_EQ(captured.messages(), std::vector<std::string>{});  // a real colour: nothing to repair
  const Rgb expected = albedoOf("cspec-negative-by-table", cxyText(chromaticityByTable(samples)), 0.5);
  expectRgbNear(read, expected, 0.01);
  // Clipping the negative samples to 0 would give a colour the tolerance tells apart.
  std::vector<double> clipped = samples;
  for (double& v : clipped) v = std::fmax(v, 0.0);
  const Rgb wrong = albedoOf("cspec-clipped-by-table", cxyText(chromaticityByTable(clipped)), 0.5);
  EXPECT_GT(std::fabs(wrong.b - expected.b), 0.05);

  // MGF's standard illuminant library's daylight basis functions are spectra of this kind: one
  // that integrates to no real colour loads, and is repaired only where a material uses it.
  std::string basis = "c day2 =\n\tcspec 380 780";
  for (int i = 0; i < 41; ++i) basis += i < 20 ? " -1" : " 0.01";
  Result<Scene> unused = readText("basis-unused", basis + "\nc\n" + std::string(kTriangle) + "m x =\n\trd .5\nf a b c\n");
  ASSERT_TRUE(unused.ok()) << unused.error().message;
  EXPECT_EQ(captured.messages(), std::vector<std::string>{});
}

// The corner of the CIE chromaticity diagram's purple line nearest (x, y) along the line from
// white (1/3, 1/3), for (x, y) below it; the line's ends are the spectral locus at 380 nm
// (0.1741, 0.0050) and 780 nm (0.7347, 0.2653).
std::pair<double, double> ontoPurpleLine(double x, double y) {
  const double ax = 0.1741, ay = 0.0050, bx = 0.7347, by = 0.2653, ex = 1.0 / 3, ey = 1.0 / 3;
  // e + t (p − e) = a + s (b − a)
  const double dx = x - ex, dy = y - ey, mx = bx - ax, my = by - ay;
  const double t = ((ax - ex) * my - (ay - ey) * mx) / (dx * my - dy * mx);
  return {ex + t * dx, ey + t * dy};
}

TEST(MgfTest, ColoursThatAreNotRealAreRepairedWhereUsed) {
  // cxy 0.4 0 (an RGB-to-xy conversion's purple: no luminance) → the most saturated real
  // colour of its hue, on the purple line.
  WarningCapture captured;
  Result<Scene> scene = readText("cxy-y0", "c purple =\n\tcxy 0.400000 0.000000\n" + std::string(kTriangle) + "m x =\n\tc purple\n\trd .1\nf a b c\n");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(captured.messages().size(), 1u);
  EXPECT_EQ(captured.count("t.mgf:2: cxy 0.400000 0.000000: no real colour (CIE XYZ ∝ (0.6667, 0, 1), no luminance): read as chromaticity ("), 1)
      << captured.messages()[0];
  EXPECT_EQ(captured.count("the most saturated real colour of its hue"), 1);
  EXPECT_EQ(captured.count("(first used by rd of material 'x' at "), 1) << captured.messages()[0];
  EXPECT_EQ(captured.count("t.mgf:12)"), 1) << captured.messages()[0];  // the face that uses it
  const Rgb repaired = scene->materials[scene->surfaces.at(0).material].albedo;
  const auto purple = ontoPurpleLine(0.4, 0);
  expectRgbNear(repaired, albedoOf("purple-by-hand", cxyText(purple), 0.1), 0.01);
  EXPECT_NEAR(repaired.luminance(), 0.1, 1e-9);  // rd is kept
  EXPECT_GT(repaired.r, repaired.g);
  EXPECT_GT(repaired.b, repaired.g);

  // cxy 0 0 (pure blue, by the same converters): where x = y meets the spectral locus, between
  // its 470 nm (0.1241, 0.0578) and 480 nm (0.0913, 0.1327) points.
  const double t = (0.1241 - 0.0578) / ((0.1327 - 0.0578) + (0.1241 - 0.0913)), onLocus = 0.1241 - t * (0.1241 - 0.0913);
  WarningCapture blue;
  expectRgbNear(albedoOf("cxy-00", "\tc\n\t\tcxy 0 0", 0.05), albedoOf("cxy-00-by-hand", cxyText({onLocus, onLocus}), 0.05), 0.01);
  EXPECT_EQ(blue.count("read as chromaticity (0.1039, 0.1039)"), 1) << (blue.messages().empty() ? "" : blue.messages()[0]);

  // Not used with a nonzero rd or ed: nothing to say.
  WarningCapture quiet;
  Result<Scene> unused = readText("cxy-y0-unused", "c blue =\n\tcxy 0 0\n" + std::string(kTriangle) + "m x =\n\tc blue\n\trd 0\nf a b c\n");
  ASSERT_TRUE(unused.ok()) << unused.error().message;
  EXPECT_EQ(quiet.messages(), std::vector<std::string>{});

  // x + y > 1: Z < 0 clipped; a mixture with a negative weight whose sum has no colour: white.
  WarningCapture clipped;
  EXPECT_GT(albedoOf("cxy-sum", "\tc\n\t\tcxy 0.7 0.4", 0.2).r, 0);
  EXPECT_EQ(clipped.count("t.mgf:"), 1);
  EXPECT_EQ(clipped.count("negative components clipped to 0"), 1);
  WarningCapture mixed;
  expectRgbNear(albedoOf("cmix-negative", "c r =\n\tcxy 0.64 0.33\nc\n\tcmix 1 r -1 r", 0.3), Rgb::gray(0.3), 1e-12);
  EXPECT_EQ(mixed.count("t.mgf:11: cmix 1 r -1 r: no real colour (CIE XYZ ∝ (0, 0, 0), nothing positive): read as white"), 1)
      << (mixed.messages().empty() ? "" : mixed.messages()[0]);
}

TEST(MgfTest, WhatCanBeUnderstoodIsRepairedWithAWarning) {
  WarningCapture captured;
  Result<Scene> scene = readText("repairs", std::string(kTriangle) + R"(v o =
	p 0 0 0
	n 0 0 1
m bright =
	rd 1.5
o
xf
sph o 0
prism a b c 0
ring o 2 1
xf -t 0 0 5
f a b c
o two words
o
)");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(captured.count("t.mgf:12: o: an end with no object to end; ignored"), 1);
  EXPECT_EQ(captured.count("t.mgf:13: xf: an end with no transformation to end; ignored"), 1);
  EXPECT_EQ(captured.count("t.mgf:14: sph: a sphere of radius 0, no area; skipped"), 1);
  EXPECT_EQ(captured.count("t.mgf:15: prism: length 0, no area; skipped"), 1);
  EXPECT_EQ(captured.count("t.mgf:16: ring: the radii are in the wrong order (rmin 2 > rmax 1); swapped"), 1);
  EXPECT_EQ(captured.count("t.mgf:19: o takes one name, not 2 words; read as 'two words'"), 1);
  EXPECT_EQ(captured.count("t.mgf:20: unbalanced xf: 1 transformation is not ended; ended at the end of the file"), 1);
  EXPECT_EQ(captured.count("material 'bright': rd: albedo of 1 or more lowered to 0.999"), 1);
  // The ring 1 ≤ r ≤ 2 and the face, lifted by the unended xf.
  EXPECT_NEAR(totalArea(*scene), 0.5 + kPi * (4 - 1) * std::sin(2 * kPi / 16) * 16 / (2 * kPi), 1e-9);
  EXPECT_TRUE(hasVertex(*scene, fromMgf({1, 0, 5})));

  // An array left open repeats what follows it to the end of its file.
  WarningCapture array;
  Result<Scene> repeated = readText("open-array", std::string(kTriangle) + "xf -a 3 -t 0 0 2\nf a b c\n");
  ASSERT_TRUE(repeated.ok()) << repeated.error().message;
  EXPECT_EQ(array.count("t.mgf:7: unbalanced xf: no xf ends this array (-a) in its file; it ends at the end of the file"), 1);
  EXPECT_NEAR(totalArea(*repeated), 3 * 0.5, 1e-12);
  EXPECT_TRUE(hasVertex(*repeated, fromMgf({1, 0, 4})));
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

// MGF's ies entity: the luminaire at its frame's origin, aimed down its −z, C = 0 along its x;
// -m multiplies the candela; a transform (an array here) places copies. MGF is z-up: a −z aim is
// lambert's −y, and −rz 90 turns C = 0 from +x to MGF's −y, lambert's +z.
TEST(MgfTest, IesEntityPlacesLuminairesByItsTransform) {
  const fs::path dir = testing::scratchDirectory("mgf", "ies");
  write(dir / "lamps" / "down.ies",
        "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0.2 0.2 0\n1 1 10\n0 45 90\n0\n100 80 0\n");
  write(dir / "t.mgf", std::string(R"(v a =
	p 0 0 0
v b =
	p 1 0 0
v c =
	p 0 1 0
f a b c
ies lamps/down.ies -m 2 -t 1 2 3 -a 2 -t 0 5 0
ies lamps/down.ies -rz -90 -t 0 0 4
)"));
  WarningCapture warnings;
  Result<Scene> scene = readMgf((dir / "t.mgf").string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(warnings.messages().size(), 0u);
  ASSERT_EQ(scene->lights.size(), 3u);
  for (const Light& l : scene->lights) {
    EXPECT_EQ(l.kind, LightKind::Luminaire);
    ASSERT_TRUE(l.photometry);
    EXPECT_LT(length(l.direction - Vec3{0, -1, 0}), 1e-12);
  }
  EXPECT_EQ(scene->lights[0].photometry, scene->lights[2].photometry);  // read once
  EXPECT_LT(length(scene->lights[0].position - fromMgf({1, 2, 3})), 1e-12);
  EXPECT_LT(length(scene->lights[1].position - fromMgf({1, 7, 3})), 1e-12);
  EXPECT_LT(length(scene->lights[2].position - fromMgf({0, 0, 4})), 1e-12);
  EXPECT_EQ(scene->lights[0].intensity.g, 2);
  EXPECT_EQ(scene->lights[2].intensity.g, 1);
  EXPECT_NEAR(scene->lights[0].rotationDegrees, 0, 1e-9);
  EXPECT_LT(length(luminaireFrame(scene->lights[2]).c0 - fromMgf({0, -1, 0})), 1e-12);
  // 45° from the nadir straight below the first: I = 2 × 80 cd at 45°, E = I cos³45° / h².
  const Rgb e = unshadowedIrradiance(scene->lights[0], fromMgf({1, 2 + 3, 0}), {0, 1, 0}, 1);
  EXPECT_NEAR(e.g * 683, 160 * std::pow(std::cos(kPi / 4), 3) / 9, 1e-9);
  // A missing file is an error naming the MGF line.
  write(dir / "bad.mgf", "ies nowhere.ies\n");
  Result<Scene> bad = readMgf((dir / "bad.mgf").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("bad.mgf:1: ies 'nowhere.ies'"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace lambert
