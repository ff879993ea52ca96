#include "lambert/light/photometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "lambert/core/rgb.h"
#include "lambert/core/rng.h"
#include "lambert/core/vec3.h"
#include "lambert/core/warning.h"
#include "lambert/load/photometry_file.h"

namespace lambert {
namespace {

constexpr double kDeg = kPi / 180;

std::string tempDir() {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "lambert_photometry_test";
  std::filesystem::create_directories(dir);
  return dir.string();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

using Distribution = std::function<double(double c, double gamma)>;

struct IesSpec {
  std::string header = "IESNA:LM-63-2002";
  std::string tilt = "TILT=NONE";
  double lamps = 1, lumensPerLamp = 1000, multiplier = 1;
  int units = 2;
  double width = 0.3, length = 0.6, height = 0.05;
  double ballast = 1, futureUse = 1, watts = 40;
  int photometricType = 1;
  std::vector<double> vertical, horizontal;
  // One value per line unless split: a stress of LM-63's "values split over lines arbitrarily".
  int valuesPerLine = 7;
};

// An IES file of the distribution f sampled at the spec's angles (the candela values before the
// file's multipliers: f / (multiplier × ballast)).
std::string iesText(const IesSpec& s, const Distribution& f) {
  std::ostringstream o;
  o.precision(17);
  o << s.header << "\r\n[TEST] written by photometry_test\r\n[LUMINAIRE] test luminaire\r\n" << s.tilt << "\r\n";
  o << s.lamps << " " << s.lumensPerLamp << " " << s.multiplier << " " << s.vertical.size() << " " << s.horizontal.size() << " "
    << s.photometricType << " " << s.units << " " << s.width << " " << s.length << " " << s.height << "\r\n";
  o << s.ballast << " " << s.futureUse << " " << s.watts << "\r\n";
  int k = 0;
  auto put = [&](double v) { o << v << (++k % s.valuesPerLine == 0 ? "\r\n" : " "); };
  for (double v : s.vertical) put(v);
  for (double h : s.horizontal) put(h);
  for (double h : s.horizontal)
    for (double v : s.vertical) put(f(h, v) / (s.multiplier * s.ballast));
  o << "\r\n";
  return o.str();
}

std::vector<double> range(double from, double to, double step) {
  std::vector<double> out;
  for (double a = from; a <= to + 1e-9; a += step) out.push_back(a);
  return out;
}

// Checks every (C, γ) of a 15° lattice on the whole sphere against f where f is sampled (the
// measured γ at every C of the expanded planes): the symmetry expansion put the right column there.
void expectMatchesAtMeasuredAngles(const Photometry& p, const Distribution& f, double scale = 1) {
  for (double c : p.horizontalDegrees)
    for (double g : p.verticalDegrees) EXPECT_NEAR(p.candela(c, g), scale * f(c, g), 1e-9 * (1 + scale * f(c, g))) << c << " " << g;
}

// Distributions with exactly one symmetry each, positive everywhere, and smooth on the sphere (a
// harmonic cos mC or sin mC fades as sin^m γ toward the poles, where every C plane meets).
double sin2(double g) { return std::pow(std::sin(g * kDeg), 2); }
double rotational(double, double g) { return 500 * (1 + std::cos(g * kDeg)) + 20; }
double quadrant(double c, double g) { return 300 + 200 * std::cos(2 * c * kDeg) * sin2(g) + 100 * std::cos(g * kDeg); }
double bilateral(double c, double g) { return 300 + 150 * std::cos(c * kDeg) * std::sin(g * kDeg) + 50 * std::cos(2 * c * kDeg) * sin2(g); }
double bilateralC90(double c, double g) { return 300 + 150 * std::sin(c * kDeg) * std::sin(g * kDeg) + 50 * std::cos(2 * c * kDeg) * sin2(g); }
double asymmetric(double c, double g) {
  return 300 + 150 * std::cos(c * kDeg) * std::sin(g * kDeg) + 90 * std::sin(c * kDeg) * std::sin(g * kDeg) +
         40 * std::sin(3 * c * kDeg) * std::pow(std::sin(g * kDeg), 3);
}

TEST(PhotometryTest, IesSymmetriesExpandToTheWholeSphere) {
  const std::vector<double> vertical = range(0, 180, 10);
  struct Case {
    std::vector<double> horizontal;
    Distribution f;
    std::size_t planes;
  } cases[] = {{{0}, rotational, 1},
               {range(0, 90, 15), quadrant, 24},
               {range(0, 180, 15), bilateral, 24},
               {range(0, 360, 15), asymmetric, 24},
               {range(90, 270, 15), bilateralC90, 24}};
  for (const Case& k : cases) {
    IesSpec spec;
    spec.vertical = vertical;
    spec.horizontal = k.horizontal;
    const Distribution& f = k.f;
    Result<Photometry> p = parseIes(iesText(spec, f), "sym.ies");
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ(p->horizontalDegrees.size(), k.planes);
    EXPECT_EQ(p->verticalDegrees.size(), vertical.size());
    expectMatchesAtMeasuredAngles(*p, f);
    // Between the measured planes (15°) and angles (10°) too, within 0.5 % of the peak.
    for (double c = 7; c < 360; c += 31)
      for (double g = 3; g < 180; g += 17) EXPECT_NEAR(p->candela(c, g), f(c, g), 0.005 * p->maxCandela()) << c << " " << g;
  }
}

TEST(PhotometryTest, IesVersionsAndTheirMultipliers) {
  IesSpec spec;
  spec.vertical = range(0, 90, 5);
  spec.horizontal = {0};
  spec.multiplier = 2.5;
  spec.ballast = 0.9;
  const Distribution f = [](double, double g) { return 1000 * std::cos(g * kDeg) + 1; };
  for (const char* header : {"IESNA:LM-63-1995", "IESNA:LM-63-2002", "IES:LM-63-2019", "IESNA91", ""}) {
    IesSpec s = spec;
    s.header = header;
    // LM-63-1995 and before: the second value of line 11 is the ballast-lamp photometric factor,
    // a multiplier; 2002 reserves it, 2019 gives the file generation type: not multipliers.
    const bool lampFactor = std::string(header) == "IESNA:LM-63-1995" || std::string(header) == "IESNA91" || std::string(header).empty();
    s.futureUse = lampFactor ? 0.8 : 1.00001;
    std::string text = iesText(s, f);
    if (std::string(header).empty()) text = text.substr(text.find('\n') + 1);  // LM-63-1986 had no header line
    Result<Photometry> p = parseIes(text, "v.ies");
    ASSERT_TRUE(p.ok()) << header << ": " << p.error().message;
    expectMatchesAtMeasuredAngles(*p, f, lampFactor ? 0.8 : 1.0);
    EXPECT_EQ(p->name, "test luminaire");
    EXPECT_DOUBLE_EQ(p->lampLumens, 1000);
    EXPECT_DOUBLE_EQ(p->inputWatts, 40);
    EXPECT_NEAR(p->openingWidth, 0.3, 1e-12);
    EXPECT_NEAR(p->openingLength, 0.6, 1e-12);
  }
}

TEST(PhotometryTest, IesAbsolutePhotometryFeetAndRoundOpenings) {
  IesSpec s;
  s.lumensPerLamp = -1;
  s.units = 1;
  s.width = -0.5, s.length = -0.5, s.height = 0;
  s.vertical = range(0, 90, 30);
  s.horizontal = {0};
  Result<Photometry> p = parseIes(iesText(s, rotational), "abs.ies");
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->lampLumens, 0);
  EXPECT_TRUE(p->round);
  EXPECT_NEAR(p->openingLength, 0.5 * 0.3048, 1e-12);
  EXPECT_NEAR(p->openingWidth, 0.5 * 0.3048, 1e-12);
}

TEST(PhotometryTest, IesTiltIncludeAndTiltFile) {
  IesSpec s;
  s.vertical = range(0, 90, 45);
  s.horizontal = {0};
  s.tilt = "TILT=INCLUDE\r\n1\r\n3\r\n0 45 90\r\n1 0.8 0.5";
  Result<Photometry> p = parseIes(iesText(s, rotational), "tilt.ies");
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->tilt.lampGeometry, 1);
  ASSERT_EQ(p->tilt.degrees.size(), 3u);
  EXPECT_DOUBLE_EQ(p->tilt.factor(45), 0.8);
  EXPECT_DOUBLE_EQ(p->tilt.factor(67.5), 0.65);
  EXPECT_DOUBLE_EQ(p->tilt.factor(120), 0.5);
  expectMatchesAtMeasuredAngles(*p, rotational);

  const std::string dir = tempDir();
  writeText(dir + "/lamp.tlt", "2\n2\n0 90\n1 0.25\n");
  s.tilt = "TILT=lamp.tlt";
  writeText(dir + "/tilted.ies", iesText(s, rotational));
  Result<Photometry> fromFile = readIes(dir + "/tilted.ies");
  ASSERT_TRUE(fromFile.ok()) << fromFile.error().message;
  EXPECT_EQ(fromFile->tilt.lampGeometry, 2);
  EXPECT_DOUBLE_EQ(fromFile->tilt.factor(45), 0.625);
  s.tilt = "TILT=missing.tlt";
  Result<Photometry> missing = parseIes(iesText(s, rotational), dir + "/x.ies");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("x.ies:4: TILT=missing.tlt"), std::string::npos) << missing.error().message;
  EXPECT_NE(missing.error().message.find("TILT=INCLUDE"), std::string::npos);
}

TEST(PhotometryTest, IesRefusesTypesAAndBAndRepairsNegativeCandela) {
  IesSpec s;
  s.vertical = range(0, 90, 45);
  s.horizontal = {0};
  s.photometricType = 2;
  Result<Photometry> b = parseIes(iesText(s, rotational), "b.ies");
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("b.ies:5: photometric type B"), std::string::npos) << b.error().message;
  s.photometricType = 3;
  EXPECT_NE(parseIes(iesText(s, rotational), "a.ies").error().message.find("type A"), std::string::npos);
  s.photometricType = 1;
  WarningCapture warnings;
  Result<Photometry> negative = parseIes(iesText(s, [](double, double g) { return g == 45 ? -3.0 : 10.0; }), "n.ies");
  ASSERT_TRUE(negative.ok());
  EXPECT_EQ(negative->candela(0, 45), 0);
  EXPECT_EQ(warnings.count("n.ies:"), 1) << warnings.messages().size();
  EXPECT_EQ(warnings.count("negative candela"), 1);
}

// Interpolation: the measured values exactly, and a smooth distribution between them (cos γ every
// 5°, as a real downlight's file samples it, C every 22.5°) within 0.12 % of its peak.
TEST(PhotometryTest, InterpolationReproducesMeasuredPointsAndASmoothDistribution) {
  IesSpec s;
  s.vertical = range(0, 90, 5);
  s.horizontal = range(0, 360, 22.5);
  const Distribution f = [](double c, double g) { return 1000 * std::cos(g * kDeg) * (1 + 0.2 * std::cos(c * kDeg) * std::sin(g * kDeg)); };
  Result<Photometry> p = parseIes(iesText(s, f), "cos.ies");
  ASSERT_TRUE(p.ok()) << p.error().message;
  expectMatchesAtMeasuredAngles(*p, f);
  double worst = 0;
  for (double c = 0; c < 360; c += 1.7)
    for (double g = 0; g <= 90; g += 0.3) {
      const double value = p->candela(c, g);
      EXPECT_GE(value, 0);
      worst = std::fmax(worst, std::fabs(value - f(c, g)));
    }
  EXPECT_LT(worst, 0.0012 * 1000 * 1.2) << worst;
  // Above the last vertical angle the luminaire sends nothing.
  EXPECT_EQ(p->candela(10, 95), 0);
  // Never negative, even where data plunge to zero (a sharp beam edge): a monotone cubic does not
  // overshoot.
  s.horizontal = {0};
  Result<Photometry> beam = parseIes(iesText(s, [](double, double g) { return g < 30 ? 5000.0 : 0.0; }), "beam.ies");
  ASSERT_TRUE(beam.ok());
  for (double g = 0; g <= 90; g += 0.1) {
    EXPECT_GE(beam->candela(0, g), 0) << g;
    EXPECT_LE(beam->candela(0, g), 5000 * (1 + 1e-12)) << g;
  }
}

// Flux against closed forms: I₀ cos γ over the lower hemisphere gives π I₀ lm; an isotropic I₀
// over the sphere 4π I₀ lm.
TEST(PhotometryTest, FluxIntegralMatchesClosedForms) {
  IesSpec s;
  s.vertical = range(0, 90, 5);
  s.horizontal = range(0, 90, 30);
  Result<Photometry> cosine = parseIes(iesText(s, [](double, double g) { return 1000 * std::cos(g * kDeg); }), "c.ies");
  ASSERT_TRUE(cosine.ok());
  EXPECT_NEAR(cosine->luminousFlux(), kPi * 1000, 1e-4 * kPi * 1000);
  s.vertical = range(0, 180, 22.5);
  s.horizontal = {0};
  Result<Photometry> iso = parseIes(iesText(s, [](double, double) { return 250.0; }), "i.ies");
  ASSERT_TRUE(iso.ok());
  EXPECT_NEAR(iso->luminousFlux(), 4 * kPi * 250, 1e-4 * 4 * kPi * 250);
}

struct LdtSpec {
  int isym = 0;
  int mc = 24;
  std::vector<double> gammas = range(0, 180, 15);
  double flux = 2000, lor = 80, conversion = 1;
  double lengthMm = 600, widthMm = 300;
};

// A EULUMDAT file of f (in cd) at the planes Isym asks for, written as cd/klm.
std::string ldtText(const LdtSpec& s, const Distribution& f, double lorOverride = -1) {
  std::ostringstream o;
  o.precision(17);
  const double dc = 360.0 / s.mc;
  o << "lambert test\n1\n" << s.isym << "\n" << s.mc << "\n" << dc << "\n" << s.gammas.size() << "\n" << s.gammas[1] - s.gammas[0] << "\n";
  o << "report 1\nLDT test luminaire\nLT-1\ntest.ldt\n2026-12-04\n";
  o << 620 << "\n" << 320 << "\n" << 60 << "\n" << s.lengthMm << "\n" << s.widthMm << "\n20\n20\n20\n20\n";
  o << 100 << "\n" << (lorOverride >= 0 ? lorOverride : s.lor) << "\n" << s.conversion << "\n0\n1\n";
  o << "2\nT5 28W\n" << s.flux << "\n4000\n80\n" << 62 << "\n";
  for (int k = 0; k < 10; ++k) o << "0.5\n";
  for (int c = 0; c < s.mc; ++c) o << c * dc << "\n";
  for (double g : s.gammas) o << g << "\n";
  int first = 0, planes = s.mc;
  switch (s.isym) {
    case 1: planes = 1; break;
    case 2: planes = s.mc / 2 + 1; break;
    case 3: first = s.mc / 4, planes = s.mc / 2 + 1; break;
    case 4: planes = s.mc / 4 + 1; break;
  }
  for (int p = first; p < first + planes; ++p)
    for (double g : s.gammas) o << f(p * dc, g) * 1000 / s.flux / s.conversion << "\n";
  return o.str();
}

TEST(PhotometryTest, EulumdatSymmetriesUnitsAndDimensions) {
  const Distribution fs[] = {asymmetric, rotational, bilateral, bilateralC90, quadrant};
  WarningCapture warnings;  // these files' LOR is not their intensities' (checked below)
  for (int isym = 0; isym <= 4; ++isym) {
    LdtSpec s;
    s.isym = isym;
    s.conversion = 1.25;
    Result<Photometry> p = parseEulumdat(ldtText(s, fs[isym]), "s.ldt");
    ASSERT_TRUE(p.ok()) << isym << ": " << p.error().message;
    EXPECT_EQ(p->horizontalDegrees.size(), isym == 1 ? 1u : 24u) << isym;
    expectMatchesAtMeasuredAngles(*p, fs[isym]);
    for (double c = 5; c < 360; c += 37) EXPECT_NEAR(p->candela(c, 50), fs[isym](c, 50), 0.01 * fs[isym](c, 50)) << isym << " " << c;
    EXPECT_NEAR(p->openingLength, 0.6, 1e-12);
    EXPECT_NEAR(p->openingWidth, 0.3, 1e-12);
    EXPECT_NEAR(p->openingHeight, 0.02, 1e-12);
    EXPECT_EQ(p->lampLumens, 2000);
    EXPECT_EQ(p->inputWatts, 62);
    EXPECT_EQ(p->name, "LDT test luminaire");
  }
}

// The integral of the intensities is the luminaire's flux, lamp flux × LOR, when the file is
// consistent: I = k cos γ downward integrates to π k lm, so LOR = π k / lamp flux.
TEST(PhotometryTest, EulumdatFluxMatchesLampFluxTimesLor) {
  LdtSpec s;
  s.isym = 1;
  s.gammas = range(0, 180, 5);
  s.widthMm = 0;  // round
  const double k = 400;
  const Distribution f = [&](double, double g) { return g <= 90 ? k * std::cos(g * kDeg) : 0.0; };
  const double lor = kPi * k / s.flux * 100;
  WarningCapture warnings;
  Result<Photometry> p = parseEulumdat(ldtText(s, f, lor), "f.ldt");
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_TRUE(p->round);
  EXPECT_NEAR(p->statedLuminaireLumens, kPi * k, 1e-9);
  EXPECT_NEAR(p->luminousFlux(), p->statedLuminaireLumens, 2e-3 * p->statedLuminaireLumens);
  EXPECT_EQ(warnings.count("integrate"), 0);
  // A LOR that disagrees with the intensities is reported.
  Result<Photometry> off = parseEulumdat(ldtText(s, f, lor * 1.5), "off.ldt");
  ASSERT_TRUE(off.ok());
  EXPECT_EQ(warnings.count("off.ldt: the intensities integrate to"), 1);
}

TEST(PhotometryTest, SampleFilesInTheRepositoryRead) {
  const std::string dir = std::string(LAMBERT_SOURCE_DIR) + "/tests/data/photometry/";
  Result<Photometry> ies = readPhotometry(dir + "downlight.ies");
  ASSERT_TRUE(ies.ok()) << ies.error().message;
  EXPECT_EQ(ies->format, "IES LM-63-2002");
  EXPECT_EQ(ies->horizontalDegrees.size(), 1u);
  Result<Photometry> ldt = readPhotometry(dir + "office-panel.ldt");
  ASSERT_TRUE(ldt.ok()) << ldt.error().message;
  EXPECT_EQ(ldt->format, "EULUMDAT");
  EXPECT_GT(ldt->horizontalDegrees.size(), 4u);
  EXPECT_NEAR(ldt->luminousFlux(), ldt->statedLuminaireLumens, 0.05 * ldt->statedLuminaireLumens);
}

// Fuzz: truncated, garbled and shuffled files never crash or hang: each gives a Photometry whose
// values are finite and non-negative, or an error naming the file.
TEST(PhotometryTest, DamagedFilesAreRepairedOrRefusedNeverCrash) {
  IesSpec s;
  s.vertical = range(0, 90, 30);
  s.horizontal = range(0, 90, 45);
  s.tilt = "TILT=INCLUDE\n1\n2\n0 90\n1 0.5";
  LdtSpec l;
  l.mc = 4;
  l.gammas = range(0, 180, 45);
  l.isym = 2;
  const std::string sources[] = {iesText(s, quadrant), ldtText(l, bilateral)};
  const char garbage[] = {'x', '-', '9', '\0', '\n', ',', '.', 'e', ' ', '\xff', '[', '='};
  WarningCapture quiet;
  Pcg32 rng(2026, 25);
  int read = 0, refused = 0;
  for (int which = 0; which < 2; ++which) {
    const std::string& good = sources[which];
    const std::string name = which == 0 ? "fuzz.ies" : "fuzz.ldt";
    auto check = [&](const std::string& text) {
      Result<Photometry> p = which == 0 ? parseIes(text, name) : parseEulumdat(text, name);
      if (!p.ok()) {
        ++refused;
        EXPECT_EQ(p.error().message.rfind(name, 0), 0u) << p.error().message;
        return;
      }
      ++read;
      EXPECT_TRUE(std::isfinite(p->luminousFlux()));
      for (double c = 0; c < 360; c += 45)
        for (double g = 0; g <= 180; g += 30) {
          const double v = p->candela(c, g);
          EXPECT_TRUE(std::isfinite(v) && v >= 0) << v;
        }
    };
    for (std::size_t cut = 0; cut < good.size(); cut += 7) check(good.substr(0, cut));
    for (int trial = 0; trial < 150; ++trial) {
      std::string text = good;
      const int edits = 1 + static_cast<int>(rng.nextUint() % 4);
      for (int e = 0; e < edits; ++e) {
        const std::size_t at = rng.nextUint() % text.size();
        switch (rng.nextUint() % 3) {
          case 0: text[at] = garbage[rng.nextUint() % sizeof garbage]; break;
          case 1: text.erase(at, 1 + rng.nextUint() % 6); break;
          case 2: text = text.substr(0, at) + garbage[rng.nextUint() % sizeof garbage] + text.substr(at); break;
        }
        if (text.empty()) text.push_back('x');
      }
      check(text);
    }
  }
  EXPECT_GT(read, 10);
  EXPECT_GT(refused, 100);
}

}  // namespace
}  // namespace lambert
