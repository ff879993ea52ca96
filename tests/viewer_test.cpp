// `lambert view` in a real window: an X server without a screen (Xvfb) and Mesa's software
// OpenGL. The viewer plays a script and takes screenshots; the tests read them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "lambert/bake/probes.h"
#include "lambert/core/rgb.h"
#include "lambert/core/srgb.h"
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
// difference per pixel, each within `tolerance` (2%) of the software image's mean luminance.
void expectSamePicture(const Luminance& viewer, const Luminance& software, double tolerance = 0.02) {
  ASSERT_EQ(viewer.pixels.size(), software.pixels.size());
  double difference = 0;
  for (std::size_t i = 0; i < viewer.pixels.size(); ++i) difference += std::fabs(viewer.pixels[i] - software.pixels[i]);
  difference /= static_cast<double>(viewer.pixels.size());
  std::printf("mean luminance: viewer %.2f, software %.2f; mean |difference| %.2f (%.2f%% of the mean)\n", viewer.mean(), software.mean(),
              difference, 100 * difference / software.mean());
  EXPECT_LT(std::fabs(viewer.mean() - software.mean()), tolerance * software.mean());
  EXPECT_LT(difference, tolerance * software.mean());
}

// lambert's own software rasterizer, on the same solution (`arguments` give the viewer's mesh,
// solver, tolerance and light samples), camera and tone mapping.
Luminance softwareImage(const fs::path& path, const std::string& arguments) {
  CommandResult rendered = shell(kCli + " render --no-cache --quiet --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight) +
                                 " -o " + path.string() + " " + arguments);
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
  // The viewer's flat method: progressive shooting to 1e-4.
  expectSamePicture(late, softwareImage(dir / "software.png", "--scene cornell --patches 1000 --solver shoot --tolerance 1e-4"));
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
                              "--scene cornell-spots --quiet");
  if (noXServer(viewed)) GTEST_SKIP() << "Xvfb could not start here: " << viewed.output;
  ASSERT_EQ(viewed.exitCode, 0) << viewed.output;
  // The viewer's default method: Gauss–Seidel to 1e-4 with 4 light samples an element.
  expectSamePicture(luminance(dir / "scene.png"), softwareImage(dir / "software.png", "--scene cornell-spots --tolerance 1e-4 --light-samples 4"));
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

// Lightmap mode against render/lightmap_image.h's CPU render of the same bake (`lambert solve
// --lightmaps --image`: another renderer, another solve with the viewer's settings, the same
// camera, exposure and sRGB encoding, one sample per pixel as the viewer draws): mean luminance
// and mean |difference| within 0.5% of the CPU image's mean (measured: 0.08%; the GPU's bilinear
// filter and rasterisation rules differ from the CPU's in the last bits). Then a
// spot moved while the lightmaps are shown: the re-baked lightmaps light the floor where it points.
TEST(ViewerTest, LightmapsMatchTheCpuLightmapRenderAndFollowAMovedSpot) {
  if (!haveXvfb()) GTEST_SKIP() << "no xvfb-run here (Debian xvfb): the viewer needs an X server";
  const fs::path dir = testing::scratchDirectory("viewer", "lightmaps");
  const Vec3 floorPoint{120, 0, 120};
  CommandResult viewed = view(dir,
                              "exposure 0\n"
                              "wait-lightmaps\n"
                              "screenshot " + (dir / "baked.png").string() + "\n"
                              "light 1 intensity 0 0 0\n"
                              "light 0 aim 120 0 120\n"
                              "wait-lightmaps\n"
                              "screenshot " + (dir / "moved.png").string() + "\n",
                              "--scene cornell-spots --lightmaps --lightmap-size 128 --json");
  if (noXServer(viewed)) GTEST_SKIP() << "Xvfb could not start here: " << viewed.output;
  ASSERT_EQ(viewed.exitCode, 0) << viewed.output;
  EXPECT_TRUE(contains(viewed.output, "\"lightmap_move_to_screen_ms_mean\"")) << viewed.output;

  CommandResult cpu = shell(kCli + " solve --no-cache --quiet --scene cornell-spots --tolerance 1e-4 --light-samples 4 --export " +
                            (dir / "cpu.glb").string() + " --lightmaps --lightmap-size 128 --image " + (dir / "cpu.png").string() +
                            " --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight) + " --supersample 1 --exposure 0");
  ASSERT_EQ(cpu.exitCode, 0) << cpu.output;
  const Luminance baked = luminance(dir / "baked.png"), moved = luminance(dir / "moved.png");
  EXPECT_GT(baked.mean(), 20);
  expectSamePicture(baked, luminance(dir / "cpu.png"), 0.005);

  const PinholeCamera camera(cornellBoxWithSpots().camera, kWidth, kHeight);
  const ScreenPoint floorPixel = *camera.project(floorPoint);
  const double before = around(baked, floorPixel.x, floorPixel.y, 4), after = around(moved, floorPixel.x, floorPixel.y, 4);
  std::printf("lightmapped floor at the aimed point: %.1f -> %.1f\n", before, after);
  EXPECT_GT(after, 2 * before);
}

// The probe sphere's pixels against the L2 SH evaluated on the CPU from the probe file `lambert
// solve --probes` writes for the same scene and settings (bake/probes.h's irradianceShAt and
// evaluateSh; E(n) clamped at 0, L = ρE/π, exposure 0, sRGB), at points across the sphere where
// the normal is found by intersecting the pixel's ray with it. Then the SH's behaviour: a spot
// straight above lights the sphere's top more than its bottom; the sphere moved out of the cone
// darkens; the spot moved over it again (probes re-baked for the moved light) lights it again.
TEST(ViewerTest, TheProbeSphereIsLitAsTheProbesSay) {
  if (!haveXvfb()) GTEST_SKIP() << "no xvfb-run here (Debian xvfb): the viewer needs an X server";
  const fs::path dir = testing::scratchDirectory("viewer", "probes");
  const Vec3 centre{278, 250, 250}, aside{110, 250, 420};
  const double radius = 60, albedo = 0.8;
  const std::string probeArguments = "--scene cornell-spots --probe-spacing 40";
  CommandResult viewed = view(dir,
                              "exposure 0\n"
                              "sphere 278 250 250\n"
                              "wait-probes\n"
                              "screenshot " + (dir / "scene-lights.png").string() + "\n"
                              "light 1 intensity 0 0 0\n"
                              "light 0 position 278 540 250\n"
                              "light 0 aim 278 0 250\n"
                              "wait-probes\n"
                              "screenshot " + (dir / "under.png").string() + "\n"
                              "sphere 110 250 420\n"
                              "frames 2\n"
                              "screenshot " + (dir / "aside.png").string() + "\n"
                              "light 0 position 110 540 420\n"
                              "light 0 aim 110 0 420\n"
                              "wait-probes\n"
                              "screenshot " + (dir / "followed.png").string() + "\n",
                              probeArguments + " --probes --sphere-radius 60 --quiet");
  if (noXServer(viewed)) GTEST_SKIP() << "Xvfb could not start here: " << viewed.output;
  ASSERT_EQ(viewed.exitCode, 0) << viewed.output;

  const fs::path probeFile = dir / "cornell-spots.probes";
  CommandResult solved = shell(kCli + " solve --no-cache --quiet --tolerance 1e-4 --light-samples 4 " + probeArguments + " --probes " +
                               probeFile.string());
  ASSERT_EQ(solved.exitCode, 0) << solved.output;
  Result<ProbeVolume> probes = readProbes(probeFile.string());
  ASSERT_TRUE(probes) << probes.error().message;
  const std::optional<ShRgb> sh = probes->irradianceShAt(centre);
  ASSERT_TRUE(sh);

  Result<PngImage> shot = readPng((dir / "scene-lights.png").string());
  ASSERT_TRUE(shot);
  const PinholeCamera camera(cornellBoxWithSpots().camera, kWidth, kHeight);
  const ScreenPoint middle = *camera.project(centre);
  const double pixelsAcross = camera.focalPixels * radius / camera.toView(centre).z;
  int compared = 0;
  double worst = 0;
  for (double dy : {-0.7, -0.35, 0.0, 0.35, 0.7})
    for (double dx : {-0.7, -0.35, 0.0, 0.35, 0.7}) {
      if (dx * dx + dy * dy > 0.6) continue;
      const int px = static_cast<int>(middle.x + dx * pixelsAcross), py = static_cast<int>(middle.y + dy * pixelsAcross);
      // The normal where the ray through the pixel's centre meets the sphere.
      const Vec3 ray = normalize(camera.forward + camera.right * ((px + 0.5 - 0.5 * kWidth) / camera.focalPixels) +
                                 camera.up * ((0.5 * kHeight - py - 0.5) / camera.focalPixels));
      const Vec3 toCentre = centre - camera.eye;
      const double along = dot(toCentre, ray), missSquared = lengthSquared(toCentre) - along * along;
      ASSERT_LT(missSquared, radius * radius);
      const Vec3 hit = camera.eye + ray * (along - std::sqrt(radius * radius - missSquared));
      const Vec3 normal = normalize(hit - centre);
      const Rgb e = evaluateSh(*sh, normal);
      for (int c = 0; c < 3; ++c) {
        const double expected = 255 * srgbEncode(std::clamp(albedo * std::fmax(e[c], 0.0) / kPi, 0.0, 1.0));
        const double drawn = shot->rgb8[(static_cast<std::size_t>(py) * kWidth + static_cast<std::size_t>(px)) * 3 + static_cast<std::size_t>(c)];
        worst = std::max(worst, std::fabs(drawn - expected));
        EXPECT_NEAR(drawn, expected, 3 + 0.03 * expected) << "pixel " << px << "," << py << " channel " << c;
      }
      ++compared;
    }
  std::printf("probe sphere: %d pixels against the CPU's SH, worst difference %.1f of 255\n", compared, worst);
  EXPECT_GE(compared, 9);

  // Top and bottom of the sphere on screen (the camera looks along +z, up is +y).
  auto topAndBottom = [&](const fs::path& path, const Vec3& at) {
    const Luminance l = luminance(path);
    const ScreenPoint p = *camera.project(at);
    const double across = camera.focalPixels * radius / camera.toView(at).z;
    return std::pair{around(l, p.x, p.y - 0.6 * across, 2), around(l, p.x, p.y + 0.6 * across, 2)};
  };
  const auto [underTop, underBottom] = topAndBottom(dir / "under.png", centre);
  const auto [asideTop, asideBottom] = topAndBottom(dir / "aside.png", aside);
  const auto [followedTop, followedBottom] = topAndBottom(dir / "followed.png", aside);
  std::printf("sphere top/bottom: under the spot %.1f/%.1f, out of its cone %.1f/%.1f, the spot moved over it %.1f/%.1f\n", underTop,
              underBottom, asideTop, asideBottom, followedTop, followedBottom);
  EXPECT_GT(underTop, 1.5 * underBottom);   // facing the lamp
  EXPECT_LT(asideTop, 0.5 * underTop);      // out of the light
  EXPECT_GT(followedTop, 2 * asideTop);     // the probes re-baked for the moved spot
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

  // Lightmaps gather at texels over the hierarchy's links: a flat mesh cannot have them.
  result = shell("env -u DISPLAY " + kCli + " view --scene cornell-spots --method flat --patches 200 --lightmaps --frames 1");
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "--lightmaps needs the hierarchical method")) << result.output;
  result = shell("env -u DISPLAY " + kCli + " view --scene cornell-spots --probe-spacing 30 --frames 1");
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "no --probes is asked for")) << result.output;
}

TEST(ViewerTest, WithoutADisplayItSaysSoAndExits) {
  CommandResult result = shell("env -u DISPLAY -u WAYLAND_DISPLAY " + kCli + " view --scene cornell --frames 1");
  EXPECT_EQ(result.exitCode, 1) << result.output;
  EXPECT_TRUE(contains(result.output, "no display")) << result.output;
}

}  // namespace
}  // namespace lambert
