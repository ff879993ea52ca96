// End-to-end: `lambert solve --probes` writes the volume its --json reports, and
// examples/read_probes (the format alone, no library) reads it back as the library does.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "lambert/bake/probes.h"
#include "lambert/core/rgb.h"
#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

// The RGB the example prints ("irradiance R G B W/m^2 …").
Rgb printedIrradiance(const std::string& output) {
  Rgb e{NAN, NAN, NAN};
  const std::size_t at = output.find("irradiance ");
  if (at != std::string::npos) std::sscanf(output.c_str() + at, "irradiance %lf %lf %lf", &e.r, &e.g, &e.b);
  return e;
}

TEST(ProbesCliTest, SolveWritesTheVolumeAndTheExampleReadsIt) {
  const fs::path dir = testing::scratchDirectory("cli", "probes");
  const std::string path = (dir / "cornell.probes").string();
  testing::CommandResult result = testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --no-cache "
                                                 "--probes " + path + " --probe-spacing 80 --json");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const nlohmann::json stats = nlohmann::json::parse(result.output.substr(result.output.find('{')));
  // 556 × 549 × 560 mm at 80 mm: 7 × 7 × 7 cells.
  EXPECT_EQ(stats["probes"].get<int>(), 343);
  EXPECT_EQ(stats["probes_file"], path);
  Result<ProbeVolume> volume = readProbes(path);
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(stats["probes_valid"].get<std::size_t>(), volume->numValid);
  EXPECT_EQ(stats["probes_invalid"].get<std::size_t>(), volume->numProbes() - volume->numValid);
  EXPECT_GT(volume->numValid, 300u);  // the blocks hold a few
  EXPECT_LT(volume->numValid, 343u);

  // At a valid probe the example gives that probe's E(n); halfway to a valid neighbour along x,
  // the mean of the two.
  std::size_t probe = 0;
  while (probe + 1 < volume->numProbes() && !(volume->valid[probe] && volume->valid[probe + 1] && (probe + 1) % 7 != 0)) ++probe;
  ASSERT_LT(probe + 1, volume->numProbes());
  const Vec3 n{0, 1, 0};
  auto exampleAt = [&](const Vec3& p) {
    char arguments[256];
    std::snprintf(arguments, sizeof arguments, " %s %.17g %.17g %.17g 0 1 0", path.c_str(), p.x, p.y, p.z);
    testing::CommandResult r = testing::shell(std::string(LAMBERT_READ_PROBES_PATH) + arguments);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return printedIrradiance(r.output);
  };
  const Rgb atProbe = exampleAt(volume->position(probe));
  const Rgb halfway = exampleAt((volume->position(probe) + volume->position(probe + 1)) * 0.5);
  const Rgb a = volume->irradiance(probe, n), b = volume->irradiance(probe + 1, n);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(atProbe[c], a[c], 1e-4 * std::fabs(a[c]) + 1e-9);
    EXPECT_NEAR(halfway[c], 0.5 * (a[c] + b[c]), 1e-4 * std::fabs(a[c] + b[c]) + 1e-9);
  }
  EXPECT_GT(a.g, 0);
}

// The values against a closed form: in a closed cube, faces toward the inside, whose every face
// emits L_e and reflects ρ (the furnace), the radiance is L_e / (1 − ρ) everywhere and in every
// direction, so every probe's irradiance is E(n) = π L_e / (1 − ρ) for every normal, which the L2
// SH holds exactly (a constant is its first band alone). The default solve's probes, and the
// example reading them, within 1% (measured 0.02%): a factor π, a bounce lost (ρ of the light) or
// a probe read at the wrong place is far outside.
TEST(ProbesCliTest, ProbesInAFurnaceGiveItsIrradiance) {
  const fs::path dir = testing::scratchDirectory("cli", "probes_furnace");
  const double albedo = 0.5, emitted = 1, irradiance = kPi * emitted / (1 - albedo);
  std::ofstream(dir / "furnace.json") << R"({"materials": [{"name": "glow", "albedo": [0.5, 0.5, 0.5], "emittedRadiance": [1, 1, 1]}],
    "surfaces": [{"material": "glow", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]},
                 {"material": "glow", "vertices": [[0, 0, 1], [0, 1, 1], [1, 1, 1], [1, 0, 1]]},
                 {"material": "glow", "vertices": [[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0]]},
                 {"material": "glow", "vertices": [[0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]]},
                 {"material": "glow", "vertices": [[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]]},
                 {"material": "glow", "vertices": [[1, 0, 0], [1, 0, 1], [1, 1, 1], [1, 1, 0]]}]})";
  const std::string path = (dir / "furnace.probes").string();
  testing::CommandResult result = testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene " + (dir / "furnace.json").string() +
                                                 " --no-cache -q --probes " + path + " --probe-spacing 0.25");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  Result<ProbeVolume> volume = readProbes(path);
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->numValid, volume->numProbes()) << "every probe is inside the cube";
  const Vec3 normals[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0.6, 0.8, 0}};
  for (std::size_t probe = 0; probe < volume->numProbes(); ++probe)
    for (const Vec3& n : normals) {
      const Rgb e = volume->irradiance(probe, n);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(e[c], irradiance, 0.01 * irradiance) << "probe " << probe << " normal " << n.x << "," << n.y << "," << n.z;
    }
  const Rgb printed = printedIrradiance(
      testing::shell(std::string(LAMBERT_READ_PROBES_PATH) + " " + path + " 0.4 0.55 0.3 0 0 1").output);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(printed[c], irradiance, 0.01 * irradiance) << "the example, channel " << c;
}

TEST(ProbesCliTest, SpacingWithoutProbesAndTooFineASpacingAreRefused) {
  testing::CommandResult result =
      testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --no-cache --probe-spacing 10");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_NE(result.output.find("--probe-spacing has no effect"), std::string::npos) << result.output;
  const fs::path dir = testing::scratchDirectory("cli", "probes_refused");
  const std::string path = (dir / "fine.probes").string();
  result = testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --no-cache --probes " + path +
                          " --probe-spacing 0.5");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_NE(result.output.find("spacing of at least"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace lambert
