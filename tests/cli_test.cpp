// End-to-end: the `lambert` binary as a user runs it.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "lambert/io/png.h"
#include "lambert/render/camera.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

CommandResult run(const std::string& arguments) {
  std::string command = std::string(LAMBERT_CLI_PATH) + " " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) result.output.append(buffer.data(), n);
  int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

fs::path outputDir(const std::string& name) {
  fs::path dir = fs::path(LAMBERT_TEST_OUTPUT_DIR) / "cli" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Rgb meanAround(const PngImage& image, double cx, double cy, int radius) {
  Rgb sum;
  int count = 0;
  for (int y = static_cast<int>(cy) - radius; y <= static_cast<int>(cy) + radius; ++y)
    for (int x = static_cast<int>(cx) - radius; x <= static_cast<int>(cx) + radius; ++x) {
      const std::uint8_t* p = &image.rgb8[3 * (static_cast<std::size_t>(y) * image.width + x)];
      sum += Rgb{double(p[0]), double(p[1]), double(p[2])};
      ++count;
    }
  return sum / count;
}

TEST(CliTest, RendersTheCornellBoxWithColourBleeding) {
  fs::path dir = outputDir("render");
  const std::string png = (dir / "cornell.png").string();
  CommandResult result = run("render --scene cornell --patches 304 --width 200 --height 150 -o " + png);
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.output.find("wrote " + png), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("visibility rays"), std::string::npos) << result.output;

  Result<PngImage> image = readPng(png);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, 200);
  EXPECT_EQ(image->height, 150);

  PinholeCamera camera(cornellBox().camera, 200, 150);
  auto red = camera.project({554, 274, 280});
  auto green = camera.project({0.5, 274, 280});
  ASSERT_TRUE(red && green);
  EXPECT_LT(red->x, 100);  // the red wall is on the left
  EXPECT_GT(green->x, 100);
  Rgb left = meanAround(*image, red->x, red->y, 3);
  Rgb right = meanAround(*image, green->x, green->y, 3);
  EXPECT_GT(left.r, left.g + 20) << left.r << " " << left.g;
  EXPECT_GT(right.g, right.r + 20) << right.g << " " << right.r;
  // Colour bleeding: the tall block's side facing the red wall picks up red.
  auto block = camera.project({460, 200, 360});
  ASSERT_TRUE(block.has_value());
  Rgb side = meanAround(*image, block->x, block->y, 2);
  EXPECT_GT(side.r, side.g) << "tall block side " << side.r << " " << side.g;
}

TEST(CliTest, JsonStatsAreMachineReadable) {
  fs::path dir = outputDir("json");
  const std::string png = (dir / "flat.png").string();
  CommandResult result = run("render --patches 192 --formfactor point --solver shoot --shading flat --width 64 "
                             "--height 64 --json -o " + png);
  ASSERT_EQ(result.exitCode, 0) << result.output;
  nlohmann::json stats = nlohmann::json::parse(result.output);
  EXPECT_GE(stats["patches"].get<int>(), 192);
  EXPECT_EQ(stats["formfactor_method"], "point");
  EXPECT_EQ(stats["solver"], "shoot");
  EXPECT_EQ(stats["converged"], "yes");
  EXPECT_LT(stats["residual"].get<double>(), 1e-5);
  EXPECT_GT(stats["visibility_rays"].get<long>(), 0);
  for (const char* key : {"mesh_seconds", "formfactor_seconds", "solve_seconds", "render_seconds", "total_seconds"})
    EXPECT_TRUE(stats.contains(key)) << key;
  EXPECT_TRUE(fs::exists(png));
}

TEST(CliTest, BadInputFailsClearlyAndWritesNothing) {
  fs::path dir = outputDir("bad");
  const std::string png = (dir / "never.png").string();

  CommandResult unknown = run("render --scene nowhere -o " + png);
  EXPECT_NE(unknown.exitCode, 0);
  EXPECT_NE(unknown.output.find("unknown scene 'nowhere'"), std::string::npos) << unknown.output;

  CommandResult zero = run("render --patches 0 -o " + png);
  EXPECT_NE(zero.exitCode, 0);
  EXPECT_NE(zero.output.find("--patches"), std::string::npos) << zero.output;

  CommandResult solver = run("render --solver magic -o " + png);
  EXPECT_NE(solver.exitCode, 0);
  EXPECT_NE(solver.output.find("magic"), std::string::npos) << solver.output;

  EXPECT_FALSE(fs::exists(png));

  fs::create_directories(dir / "taken.png");  // a directory where the image should go
  CommandResult blocked = run("render --patches 64 --width 32 --height 32 -o " + (dir / "taken.png").string());
  EXPECT_NE(blocked.exitCode, 0);
  EXPECT_NE(blocked.output.find((dir / "taken.png").string()), std::string::npos) << blocked.output;
}

TEST(CliTest, HelpListsTheOptions) {
  CommandResult help = run("render --help");
  EXPECT_EQ(help.exitCode, 0);
  for (const char* option : {"--patches", "--formfactor", "--solver", "--width", "--json", "--shading"})
    EXPECT_NE(help.output.find(option), std::string::npos) << option;
  CommandResult scenes = run("scenes");
  EXPECT_EQ(scenes.exitCode, 0);
  EXPECT_NE(scenes.output.find("cornell"), std::string::npos);
}

}  // namespace
}  // namespace lambert
