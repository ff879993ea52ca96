// End-to-end: the lighting-design commands as a user runs them — `lambert solve --points
// --export-points`, `--work-plane`/`--grid` with `--export-grids`, and `lambert report`, whose page
// headless Chromium opens (docs/photometry.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lambert/core/photometric.h"
#include "lambert/io/png.h"
#include "lambert/scene/builtin.h"
#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::contains;
using testing::shell;

testing::CommandResult run(const std::string& arguments) { return shell(std::string(LAMBERT_CLI_PATH) + " " + arguments + " --no-cache"); }

std::vector<std::vector<std::string>> csvRows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string field; std::getline(s, field, ',');) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

// The point 300 mm above the Cornell floor's middle sees the lamp whole: its direct light is
// B_e × F, F the lamp's form factor to the point by quadrature here, in lux 683 × the luminance.
TEST(LightingCliTest, PointsGetTheirLuxAndKeepTheirColumns) {
  const fs::path dir = testing::scratchDirectory("lighting-cli", "points");
  std::ofstream(dir / "in.csv") << "x,y,z,nx,ny,nz,name\n278,300,280,0,1,0,air\n278,0.5,280,0,1,0,floor\n";
  const testing::CommandResult r = run("solve --scene cornell --points " + (dir / "in.csv").string() + " --export-points " +
                                       (dir / "out.csv").string() + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto rows = csvRows(dir / "out.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz", "name", "E_direct", "E_sky", "E_sun", "E_indirect", "E"}));
  EXPECT_EQ(rows[1][6], "air");
  const double direct = std::stod(rows[1][7]), indirect = std::stod(rows[1][10]), total = std::stod(rows[1][11]);
  EXPECT_EQ(std::stod(rows[1][8]), 0) << "no sky";
  EXPECT_EQ(std::stod(rows[1][9]), 0) << "no sun";
  EXPECT_NEAR(total, direct + indirect, 1e-4 * total);
  const Scene cornell = cornellBox();
  const Surface* lamp = nullptr;
  for (const Surface& s : cornell.surfaces)
    if (s.name == "light") lamp = &s;
  ASSERT_NE(lamp, nullptr);
  const Vec3 x{278, 300, 280}, corner = lamp->vertices[0], u = lamp->vertices[1] - corner, v = lamp->vertices[3] - corner;
  const int cells = 400;
  double factor = 0;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j) {
      const Vec3 d = corner + u * ((i + 0.5) / cells) + v * ((j + 0.5) / cells) - x;
      const double r2 = lengthSquared(d);
      factor += d.y * d.y / (kPi * r2 * r2) * length(cross(u, v)) / (double(cells) * cells);
    }
  const double expected = illuminanceLux(lamp->emittedRadiance * (kPi * factor));
  EXPECT_NEAR(direct, expected, 2e-3 * expected);
  EXPECT_GT(indirect, 0.03 * direct);  // the walls' light
  EXPECT_LT(indirect, 0.3 * direct);
}

TEST(LightingCliTest, GridsWriteTheirFiguresCsvAndPicture) {
  const fs::path dir = testing::scratchDirectory("lighting-cli", "grids");
  const testing::CommandResult r =
      run("solve --scene cornell --work-plane 0.2 --grid floor --grid-spacing 0.05 --export-grids " + (dir / "g-").string() + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(json["grid1_name"], "work plane 0.20 m");
  EXPECT_EQ(json["grid2_name"], "floor");
  // 0.556 m / 0.05 m: 11 cells a side.
  EXPECT_EQ(json["grid1_points"], 121);
  const auto rows = csvRows(dir / "g-floor.csv");
  ASSERT_EQ(rows.size(), 1u + json["grid2_points"].get<std::size_t>());
  double sum = 0, lo = 1e300, hi = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double e = std::stod(rows[i].back());
    sum += e, lo = std::min(lo, e), hi = std::max(hi, e);
  }
  const double average = sum / static_cast<double>(rows.size() - 1);
  EXPECT_NEAR(json["grid2_e_avg"].get<double>(), average, 1e-3 * average);
  EXPECT_NEAR(json["grid2_u0"].get<double>(), lo / average, 1e-3);
  EXPECT_NEAR(json["grid2_e_max"].get<double>(), hi, 1e-3 * hi);
  Result<PngImage> picture = readPng((dir / "g-work-plane-0-20-m.png").string());
  ASSERT_TRUE(picture.ok());
  EXPECT_GT(picture->width, 600);
}

TEST(LightingCliTest, RefusesOptionsThatWouldDoNothing) {
  struct Case {
    std::string arguments, expected;
  };
  for (const Case& c : {Case{"solve --scene cornell --points /dev/null", "--points needs --export-points"},
                        Case{"solve --scene cornell --export-points x.csv", "give --points"},
                        Case{"solve --scene cornell --export-grids x-", "none is asked for"},
                        Case{"solve --scene cornell --grid-spacing 0.5", "--grid-spacing has no effect"},
                        Case{"solve --scene cornell --grid ceiling-of-nothing", "no surface or material of that name"},
                        Case{"solve --scene cornell --work-plane 2", "outside the scene"},
                        Case{"report --scene cornell -o x.pdf", "HTML page"}}) {
    const testing::CommandResult r = run(c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.arguments << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.expected)) << c.arguments << "\n" << r.output;
  }
}

// The report as a reader sees it: Chromium loads the page, its DOM holds the grid's figures as
// `solve` printed them and the false-colour picture decoded; its screenshot shows that picture.
TEST(LightingCliTest, ReportOpensInChromium) {
  if (std::system("command -v chromium > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "no chromium here (Debian package chromium; scripts/install-deps.sh installs it)";
  const fs::path dir = testing::scratchDirectory("lighting-cli", "report");
  const std::string page = (dir / "report.html").string();
  const testing::CommandResult r = run("report --scene cornell --grid floor -o " + page + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  char average[32];
  std::snprintf(average, sizeof average, "%.1f", json["grid1_e_avg"].get<double>());
  const std::string chromium = "timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars ";
  // The DOM as Chromium parsed it: the figure in the table, the picture and the histogram.
  const testing::CommandResult dom = shell(chromium + "--dump-dom file://" + page);
  ASSERT_EQ(dom.exitCode, 0) << dom.output;
  EXPECT_TRUE(contains(dom.output, "<td>" + std::string(average) + "</td>")) << average;
  EXPECT_TRUE(contains(dom.output, "data:image/png;base64,"));
  EXPECT_TRUE(contains(dom.output, "<svg class=\"histogram\""));
  const std::string shot = (dir / "report.png").string();
  const testing::CommandResult screenshot = shell(chromium + "--window-size=1000,1200 --screenshot=" + shot + " file://" + page);
  ASSERT_EQ(screenshot.exitCode, 0) << screenshot.output;
  Result<PngImage> image = readPng(shot);
  ASSERT_TRUE(image.ok());
  // The false-colour picture: many saturated pixels (Turbo's colours), which text and tables lack.
  std::size_t coloured = 0;
  for (std::size_t i = 0; i + 2 < image->rgb8.size(); i += 3) {
    const int r8 = image->rgb8[i], g8 = image->rgb8[i + 1], b8 = image->rgb8[i + 2];
    coloured += std::max({r8, g8, b8}) - std::min({r8, g8, b8}) > 100;
  }
  EXPECT_GT(coloured, 100000u);
}

}  // namespace
}  // namespace lambert
