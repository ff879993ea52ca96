// End-to-end: `lambert solve --probes` writes the volume its --json reports, and
// examples/read_probes (the format alone, no library) reads it back as the library does.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "lambert/bake/probes.h"
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
  testing::CommandResult result = testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --patches 300 --no-cache "
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

TEST(ProbesCliTest, SpacingWithoutProbesAndTooFineASpacingAreRefused) {
  testing::CommandResult result =
      testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --patches 64 --no-cache --probe-spacing 10");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_NE(result.output.find("--probe-spacing has no effect"), std::string::npos) << result.output;
  const fs::path dir = testing::scratchDirectory("cli", "probes_refused");
  const std::string path = (dir / "fine.probes").string();
  result = testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --patches 64 --no-cache --probes " + path +
                          " --probe-spacing 0.5");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_NE(result.output.find("spacing of at least"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace lambert
