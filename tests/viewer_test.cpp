// `lambert view` in a real window: an X server without a screen (Xvfb) and Mesa's software
// OpenGL. The viewer plays a script and takes screenshots; the tests read them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "lambert/core/rgb.h"
#include "lambert/io/png.h"
#include "lambert/render/camera.h"
#include "lambert/scene/builtin.h"
#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::contains;
using testing::shell;

const std::string kCli = LAMBERT_CLI_PATH;
constexpr int kWidth = 640, kHeight = 360;

// Under AddressSanitizer (make sanitize): libGL unloads Mesa's driver at exit, before
// LeakSanitizer looks, so what the driver still held looks leaked, from an "<unknown module>"
// that no suppression can name. Preloading the driver keeps it mapped to the end, and leak
// checking stays on for the viewer's own code. The ASan runtime must come first in LD_PRELOAD;
// this test binary has it mapped, so its path is in /proc/self/maps.
std::string keepGlDriverLoaded() {
#if defined(__SANITIZE_ADDRESS__)
  std::string asanRuntime;
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line) && asanRuntime.empty();)
    if (std::size_t at = line.find('/'); at != std::string::npos && contains(line, "/libasan.so")) asanRuntime = line.substr(at);
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/usr/lib", ec)) {
    const fs::path driver = entry.path() / "dri" / "swrast_dri.so";
    if (!asanRuntime.empty() && fs::exists(driver, ec)) return "env LD_PRELOAD='" + asanRuntime + " " + driver.string() + "' ";
  }
#endif
  return "";
}

// Runs the viewer with a script under Xvfb. Skips (saying why) only where no X server can start.
CommandResult view(const fs::path& dir, const std::string& script, const std::string& arguments) {
  const fs::path scriptPath = dir / "script.txt";
  std::ofstream(scriptPath) << script;
  return shell("xvfb-run -a -s '-screen 0 1280x1024x24' " + keepGlDriverLoaded() + kCli + " view --no-cache --width " + std::to_string(kWidth) +
               " --height " + std::to_string(kHeight) + " --script " + scriptPath.string() + " " + arguments);
}

bool noXServer(const CommandResult& result) { return contains(result.output, "Xvfb failed to start"); }

struct Luminance {
  std::vector<double> pixels;  // Rec. 709 luminance of the sRGB-encoded values, 0–255
  double mean() const {
    double sum = 0;
    for (double v : pixels) sum += v;
    return pixels.empty() ? 0 : sum / static_cast<double>(pixels.size());
  }
};

Luminance luminance(const fs::path& path) {
  Result<PngImage> image = readPng(path.string());
  EXPECT_TRUE(image) << path << ": " << (image ? "" : image.error().message);
  Luminance l;
  if (!image) return l;
  EXPECT_EQ(image->width, kWidth);
  EXPECT_EQ(image->height, kHeight);
  for (std::size_t i = 0; i + 2 < image->rgb8.size(); i += 3)
    l.pixels.push_back(Rgb{double(image->rgb8[i]), double(image->rgb8[i + 1]), double(image->rgb8[i + 2])}.luminance());
  return l;
}

// Mean luminance in a square of the given half-width around a pixel.
double around(const Luminance& l, double x, double y, int radius) {
  double sum = 0;
  int n = 0;
  for (int j = static_cast<int>(y) - radius; j <= static_cast<int>(y) + radius; ++j)
    for (int i = static_cast<int>(x) - radius; i <= static_cast<int>(x) + radius; ++i)
      if (i >= 0 && j >= 0 && i < kWidth && j < kHeight) sum += l.pixels[static_cast<std::size_t>(j) * kWidth + i], ++n;
  return n ? sum / n : 0;
}

// The viewer's picture against lambert's software rasterizer's: mean luminance and mean absolute
// difference per pixel, each within 2% of the software image's mean luminance.
void expectSamePicture(const Luminance& viewer, const Luminance& software) {
  ASSERT_EQ(viewer.pixels.size(), software.pixels.size());
  double difference = 0;
  for (std::size_t i = 0; i < viewer.pixels.size(); ++i) difference += std::fabs(viewer.pixels[i] - software.pixels[i]);
  difference /= static_cast<double>(viewer.pixels.size());
  std::printf("mean luminance: viewer %.2f, software %.2f; mean |difference| %.2f (%.2f%% of the mean)\n", viewer.mean(), software.mean(),
              difference, 100 * difference / software.mean());
  EXPECT_LT(std::fabs(viewer.mean() - software.mean()), 0.02 * software.mean());
  EXPECT_LT(difference, 0.02 * software.mean());
}

// lambert's own software rasterizer, on the same solution (mesh, solver, tolerance and light
// samples as the viewer's defaults), camera and tone mapping.
Luminance softwareImage(const fs::path& path, const std::string& arguments, const std::string& lightSamples = "") {
  CommandResult rendered = shell(kCli + " render --no-cache --quiet --solver shoot --tolerance 1e-4 " + lightSamples + " --width " + std::to_string(kWidth) +
                                 " --height " + std::to_string(kHeight) + " -o " + path.string() + " " + arguments);
  EXPECT_EQ(rendered.exitCode, 0) << rendered.output;
  return luminance(path);
}

bool haveXvfb() { return shell("command -v xvfb-run").exitCode == 0; }

TEST(ViewerTest, MatchesTheSoftwareRendererAndBrightensWhileConverging) {
  if (!haveXvfb()) GTEST_SKIP() << "no xvfb-run here (Debian xvfb): the viewer needs an X server";
  const fs::path dir = testing::scratchDirectory("viewer", "converging");
  // One shot per update, without the ambient term: the first picture on screen is the light's
  // first shots, far from converged.
  CommandResult viewed = view(dir,
                              "ambient off\n"
                              "wait-solution\n"
                              "screenshot " + (dir / "early.png").string() + "\n"
                              "wait-converged\n"
                              "screenshot " + (dir / "late.png").string() + "\n",
                              "--scene cornell --patches 1000 --shots-per-update 1 --json");
  if (noXServer(viewed)) GTEST_SKIP() << "Xvfb could not start here: " << viewed.output;
  ASSERT_EQ(viewed.exitCode, 0) << viewed.output;
  EXPECT_TRUE(contains(viewed.output, "\"frames_per_second\"")) << viewed.output;

  const Luminance early = luminance(dir / "early.png"), late = luminance(dir / "late.png");
  // Not blank: the box fills the middle of the frame.
  EXPECT_GT(late.mean(), 20);
  expectSamePicture(late, softwareImage(dir / "software.png", "--scene cornell --patches 1000"));
  // The picture brightens while the solve converges (interreflections arrive shot by shot).
  std::printf("first solution on screen: mean luminance %.2f\n", early.mean());
  EXPECT_LT(early.mean(), 0.95 * late.mean());
}

TEST(ViewerTest, MovingASpotMovesTheLitRegion) {
  if (!haveXvfb()) GTEST_SKIP() << "no xvfb-run here (Debian xvfb): the viewer needs an X server";
  const fs::path dir = testing::scratchDirectory("viewer", "spot");
  // The scene's spots as they are (their direct light per pixel, shadowed from the corners); then
  // the warm spot aimed at the floor's front left and at the back wall above the blocks, the cool
  // one off.
  const Vec3 floorPoint{120, 0, 120}, wallPoint{330, 420, 559.2};
  CommandResult viewed = view(dir,
                              "wait-converged\n"
                              "screenshot " + (dir / "scene.png").string() + "\n"
                              "light 1 intensity 0 0 0\n"
                              "light 0 aim 120 0 120\n"
                              "wait-converged\n"
                              "screenshot " + (dir / "floor.png").string() + "\n"
                              "light 0 aim 330 420 559.2\n"
                              "wait-converged\n"
                              "screenshot " + (dir / "wall.png").string() + "\n",
                              "--scene cornell-spots --patches 800 --quiet");
  if (noXServer(viewed)) GTEST_SKIP() << "Xvfb could not start here: " << viewed.output;
  ASSERT_EQ(viewed.exitCode, 0) << viewed.output;
  expectSamePicture(luminance(dir / "scene.png"), softwareImage(dir / "software.png", "--scene cornell-spots --patches 800", "--light-samples 4"));
  const Luminance floorLit = luminance(dir / "floor.png"), wallLit = luminance(dir / "wall.png");
  // Where the aimed points are on screen, from the scene's camera (render/camera.h).
  const PinholeCamera camera(cornellBoxWithSpots().camera, kWidth, kHeight);
  const ScreenPoint floorPixel = *camera.project(floorPoint), wallPixel = *camera.project(wallPoint);
  const double floorBefore = around(floorLit, floorPixel.x, floorPixel.y, 4), floorAfter = around(wallLit, floorPixel.x, floorPixel.y, 4);
  const double wallBefore = around(floorLit, wallPixel.x, wallPixel.y, 4), wallAfter = around(wallLit, wallPixel.x, wallPixel.y, 4);
  std::printf("floor spot: %.1f -> %.1f; wall spot: %.1f -> %.1f\n", floorBefore, floorAfter, wallBefore, wallAfter);
  EXPECT_GT(floorBefore, 2 * floorAfter);
  EXPECT_GT(wallAfter, 2 * wallBefore);
}

TEST(ViewerTest, ABadScriptIsRefusedWithItsLineBeforeAnyWindowOpens) {
  const fs::path dir = testing::scratchDirectory("viewer", "bad-script");
  const fs::path script = dir / "moves.txt";
  std::ofstream(script) << "frames 2\n# a comment\nlight 0 aim 1 2\n";
  // No DISPLAY: the script is read before any window is asked for.
  CommandResult result = shell("env -u DISPLAY " + kCli + " view --scene cornell-spots --script " + script.string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, script.string() + ":3:")) << result.output;
  EXPECT_TRUE(contains(result.output, "three numbers")) << result.output;

  std::ofstream(script) << "light 5 position 0 0 0\n";
  result = shell("env -u DISPLAY " + kCli + " view --scene cornell-spots --script " + script.string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, ":1: light 5 does not exist")) << result.output;
}

TEST(ViewerTest, WithoutADisplayItSaysSoAndExits) {
  CommandResult result = shell("env -u DISPLAY -u WAYLAND_DISPLAY " + kCli + " view --scene cornell --patches 200 --frames 1");
  EXPECT_EQ(result.exitCode, 1) << result.output;
  EXPECT_TRUE(contains(result.output, "no display")) << result.output;
}

}  // namespace
}  // namespace lambert
