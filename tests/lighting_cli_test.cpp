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
#include "lambert/load/photometry_file.h"
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
                        Case{"report --scene cornell -o x.txt", "HTML page or a PDF"}}) {
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
  const testing::CommandResult screenshot = shell(chromium + "--window-size=1000,3000 --screenshot=" + shot + " file://" + page);
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

// A designer's report of an office (6 m × 4 m × 3 m, one panel near its north-west corner, maintenance
// factor 0.9 × 0.9), written as an HTML page and a PDF with the surface's CSV beside them:
//  - the figures come from the CSV's columns: Ē, E_min, E_max are the mean, least and greatest of E,
//    and E = E_direct + E_indirect in each row (no sky, no sun: their columns 0);
//  - the schedule's maintained flux is 0.81 × the flux the photometric file integrates to (read here);
//  - the PDF is a real one: poppler renders its sheets and finds the schedule, the figures and the
//    maintenance factors in its text, and the plan's brightest colours in its top-left quarter.
TEST(LightingCliTest, ReportIsAPageAndAPdfWhoseFiguresAreTheCsvsColumns) {
  if (std::system("command -v pdftoppm > /dev/null 2>&1 && command -v pdftotext > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "no pdftoppm/pdftotext here (Debian package poppler-utils; scripts/install-deps.sh installs it)";
  const fs::path dir = testing::scratchDirectory("lighting-cli", "report-pdf");
  const fs::path panel = fs::path(LAMBERT_SOURCE_DIR) / "tests" / "data" / "photometry" / "office-panel.ldt";
  std::ofstream(dir / "office.json") << R"({"name": "office", "maintenance": {"lampLumen": 0.9, "luminaire": 0.9},
    "materials": [{"name": "floor", "albedo": [0.2, 0.2, 0.2]}, {"name": "walls", "albedo": [0.5, 0.5, 0.5]}, {"name": "ceiling", "albedo": [0.7, 0.7, 0.7]}],
    "surfaces": [{"name": "floor", "material": "floor", "vertices": [[0,0,0],[0,0,4],[6,0,4],[6,0,0]]},
      {"name": "ceiling", "material": "ceiling", "vertices": [[0,3,0],[6,3,0],[6,3,4],[0,3,4]]},
      {"name": "north", "material": "walls", "vertices": [[0,0,0],[6,0,0],[6,3,0],[0,3,0]]},
      {"name": "south", "material": "walls", "vertices": [[0,0,4],[0,3,4],[6,3,4],[6,0,4]]},
      {"name": "west", "material": "walls", "vertices": [[0,0,0],[0,3,0],[0,3,4],[0,0,4]]},
      {"name": "east", "material": "walls", "vertices": [[6,0,0],[6,0,4],[6,3,4],[6,3,0]]}],
    "lights": [{"type": "ies", "file": ")" << panel.string() << R"(", "position": [1.5, 2.95, 1.0]}]})";
  const testing::CommandResult r = run("report --scene " + (dir / "office.json").string() + " --grid-spacing 0.25 -o " + (dir / "r.html").string() +
                                       " -o " + (dir / "r.pdf").string() + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  // The CSV's columns.
  const auto rows = csvRows(dir / "r-work-plane-0-80-m.csv");
  ASSERT_EQ(rows[0], (std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz", "E_direct", "E_sky", "E_sun", "E_indirect", "E"}));
  double sum = 0, lo = 1e300, hi = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double direct = std::stod(rows[i][6]), indirect = std::stod(rows[i][9]), e = std::stod(rows[i][10]);
    EXPECT_NEAR(direct + indirect, e, 1e-5 * e) << "row " << i;
    EXPECT_EQ(std::stod(rows[i][7]), 0);
    EXPECT_EQ(std::stod(rows[i][8]), 0);
    sum += e, lo = std::min(lo, e), hi = std::max(hi, e);
  }
  const double average = sum / static_cast<double>(rows.size() - 1);
  char text[64];
  const std::vector<char> bytes = testing::readBytes(dir / "r.html");
  const std::string html(bytes.begin(), bytes.end());
  for (double figure : {average, lo, hi}) {
    std::snprintf(text, sizeof text, "<td>%.1f</td>", figure);
    EXPECT_TRUE(contains(html, text)) << text;
  }
  EXPECT_NEAR(json["grid1_e_avg"].get<double>(), average, 1e-4 * average);
  // The schedule: 0.81 × the file's flux, maintained; the file's wattage.
  Result<Photometry> photometry = readPhotometry(panel.string());
  ASSERT_TRUE(photometry.ok());
  std::snprintf(text, sizeof text, "<td>%.1f</td><td>0.810</td><td>%.1f</td>", photometry->luminousFlux(), 0.81 * photometry->luminousFlux());
  EXPECT_TRUE(contains(html, text)) << text;
  EXPECT_TRUE(contains(html, "id=\"ugr\"")) << "UGR at the default observers";
  EXPECT_TRUE(contains(html, "id=\"mounting\""));
  // The PDF, rendered: its text and its sheets.
  const testing::CommandResult words = shell("pdftotext -layout " + (dir / "r.pdf").string() + " -");
  ASSERT_EQ(words.exitCode, 0) << words.output;
  std::snprintf(text, sizeof text, "%.1f", average);
  for (const std::string& expected : {std::string("Luminaire schedule"), std::string("Maintenance factors"), std::string(text), std::string("UGR")})
    EXPECT_TRUE(contains(words.output, expected)) << expected;
  const testing::CommandResult sheets = shell("pdftoppm -r 50 -png " + (dir / "r.pdf").string() + " " + (dir / "sheet").string());
  ASSERT_EQ(sheets.exitCode, 0) << sheets.output;
  // The sheet with the most of Turbo's saturated colours holds the plan; its reddest pixels (the
  // peak under the panel) lie in the top-left quarter of the coloured area.
  int planSheet = 0;
  std::size_t mostColoured = 0;
  PngImage plan;
  for (int k = 1; fs::exists(dir / ("sheet-" + std::to_string(k) + ".png")); ++k) {
    Result<PngImage> image = readPng((dir / ("sheet-" + std::to_string(k) + ".png")).string());
    ASSERT_TRUE(image.ok());
    std::size_t coloured = 0;
    for (std::size_t i = 0; i + 2 < image->rgb8.size(); i += 3)
      coloured += std::max({image->rgb8[i], image->rgb8[i + 1], image->rgb8[i + 2]}) - std::min({image->rgb8[i], image->rgb8[i + 1], image->rgb8[i + 2]}) > 100;
    if (coloured > mostColoured) mostColoured = coloured, planSheet = k, plan = *image;
  }
  ASSERT_GT(planSheet, 3) << "the surface's sheet follows the summary, the sources and glare";
  int x0 = plan.width, x1 = 0, y0 = plan.height, y1 = 0;
  double redX = 0, redY = 0, reds = 0;
  for (int y = 0; y < plan.height; ++y)
    for (int x = 0; x < plan.width; ++x) {
      const std::uint8_t* p = &plan.rgb8[(static_cast<std::size_t>(y) * plan.width + x) * 3];
      // Turbo's blues to reds; the legend's bar lies right of the plan, so only the plan's width counts.
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) <= 100) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  // The coloured box spans the plan and, at its right, the legend's bar (under a twentieth of the
  // box): the red of the bar's top is left out.
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x < x0 + 0.9 * (x1 - x0); ++x) {
      const std::uint8_t* p = &plan.rgb8[(static_cast<std::size_t>(y) * plan.width + x) * 3];
      if (p[0] > 180 && p[1] < 90 && p[2] < 60) redX += x, redY += y, reds += 1;
    }
  ASSERT_GT(reds, 0);
  const double across = (redX / reds - x0) / (x1 - x0), down = (redY / reds - y0) / (y1 - y0);
  std::printf("plan sheet %d: the reddest pixels %.2f across, %.2f down the coloured area\n", planSheet, across, down);
  EXPECT_LT(across, 0.4);
  EXPECT_LT(down, 0.5);
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

// `lambert daylight` as a user runs it on the test week: its sDA is the share of the CSV's sensors
// that pass, and each sensor's DA in the CSV is what the hourly CSV's columns give by LM-83's
// definition (occupied: hours ending 9 to 18; E ≥ 300 lx), recomputed here; the plans and the page are
// written; a missing weather file and an unknown metric are refused, naming them.
TEST(DaylightCliTest, MetricsAreTheHourlyColumnsAndBadInputIsRefused) {
  const fs::path dir = testing::scratchDirectory("daylight-cli", "office");
  const std::string scene = std::string(LAMBERT_SOURCE_DIR) + "/scenes/daylight/office-overcast.json";
  const std::string weather = std::string(LAMBERT_SOURCE_DIR) + "/tests/weather/boulder-week.epw";
  const testing::CommandResult r = run("daylight --scene " + scene + " --weather " + weather + " -o " + (dir / "office").string() +
                                       " --hourly " + (dir / "hourly.csv").string() + " --report " + (dir / "office.html").string() + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  const auto sensors = csvRows(dir / "office.csv");
  const auto hourly = csvRows(dir / "hourly.csv");
  ASSERT_EQ(hourly.size(), 169u);
  ASSERT_EQ(sensors.size(), 1u + json["sensors"].get<std::size_t>());
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(sensors[0].begin(), sensors[0].end(), name) - sensors[0].begin());
  };
  const std::size_t daColumn = column("DA_300lx_pct"), passColumn = column("sDA_300lx_50pct_pass");
  ASSERT_LT(passColumn, sensors[0].size());
  int passing = 0;
  for (std::size_t s = 1; s < sensors.size(); ++s) {
    int occupied = 0, above = 0;
    for (std::size_t h = 1; h < hourly.size(); ++h) {
      const int hour = std::stoi(hourly[h][2]);
      if (hour < 9 || hour > 18) continue;
      ++occupied;
      above += std::stod(hourly[h][2 + s]) >= 300;
    }
    EXPECT_NEAR(std::stod(sensors[s][daColumn]), 100.0 * above / occupied, 0.01) << "sensor " << s;
    passing += std::stoi(sensors[s][passColumn]);
  }
  EXPECT_NEAR(json["sda_percent"].get<double>(), 100.0 * passing / (sensors.size() - 1), 1e-6);
  for (const char* plan : {"office-da.png", "office-sunlit-hours.png", "office-udi-useful.png"}) EXPECT_TRUE(fs::exists(dir / plan)) << plan;
  const std::vector<char> page = testing::readBytes(dir / "office.html");
  EXPECT_TRUE(contains(std::string(page.begin(), page.end()), "sDA"));

  const testing::CommandResult missing = run("daylight --scene " + scene + " --weather " + (dir / "nowhere.epw").string());
  EXPECT_EQ(missing.exitCode, 2) << missing.output;
  EXPECT_TRUE(contains(missing.output, "nowhere.epw")) << missing.output;
  const testing::CommandResult metric = run("daylight --scene " + scene + " --weather " + weather + " --metrics sDA,GLARE");
  EXPECT_EQ(metric.exitCode, 2) << metric.output;
  EXPECT_TRUE(contains(metric.output, "GLARE")) << metric.output;
}

}  // namespace
}  // namespace lambert
