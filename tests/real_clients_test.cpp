// End-to-end: real clients of the lightmapped glb (`lambert solve --lightmaps --export`,
// docs/lightmaps.md "Real clients"). Headless Chromium draws the glb with three.js
// (examples/web/lightmap.js) from the glb's camera, and its screenshot must agree with lambert's own
// picture of the same glb (`--image`, render/lightmap_image.h) pixel by pixel; without the lightmap
// it must not. Blender imports the glb with both its UV sets, the second holding TEXCOORD_1 corner
// by corner (tests/blender_import.py, which also reads the glb's bytes itself). Each test
// is skipped, saying why, where its client is absent (scripts/install-deps.sh installs Chromium,
// three.js and Blender).
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lambert/io/png.h"
#include "tests/support/files.h"
#include "tests/support/process.h"

extern char** environ;

namespace lambert {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 256, kHeight = 256;

std::string chromiumSkipReason() {
  if (std::system("command -v chromium > /dev/null 2>&1") != 0)
    return "no chromium here (Debian package chromium; scripts/install-deps.sh installs it)";
  if (!fs::exists(fs::path(LAMBERT_SOURCE_DIR) / ".tools/node_modules/three/build/three.module.js"))
    return "no three.js in .tools/ (npm three, installed by scripts/install-deps.sh where npm reaches the registry)";
  if (std::system("command -v python3 > /dev/null 2>&1") != 0) return "no python3 here to serve the page";
  return "";
}

std::string blenderSkipReason() {
  if (std::system("command -v blender > /dev/null 2>&1") != 0)
    return "no blender here (Debian package blender, about 550 MB with its dependencies: scripts/install-deps.sh installs it)";
  return "";
}

// A static file server over a folder on a free localhost port (python3's http.server), for the
// object's life; the page must come over HTTP (module scripts and fetch() refuse file://).
class LocalServer {
 public:
  explicit LocalServer(const fs::path& root) {
    int out[2];
    if (pipe(out) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);  // its request log
    const std::string directory = root.string();
    const char* argv[] = {"python3", "-u", "-m", "http.server", "0", "--bind", "127.0.0.1", "--directory", directory.c_str(), nullptr};
    const int spawned = posix_spawnp(&pid_, "python3", &actions, nullptr, const_cast<char**>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    if (spawned != 0) {
      pid_ = -1;
      close(out[0]);
      return;
    }
    // "Serving HTTP on 127.0.0.1 port 40123 (http://127.0.0.1:40123/) ..."
    std::string line;
    char c;
    while (line.find('\n') == std::string::npos && read(out[0], &c, 1) == 1) line += c;
    readEnd_ = out[0];
    const std::size_t at = line.find(" port ");
    if (at != std::string::npos) port_ = std::atoi(line.c_str() + at + 6);
  }
  ~LocalServer() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
    if (readEnd_ >= 0) close(readEnd_);
  }
  LocalServer(const LocalServer&) = delete;
  LocalServer& operator=(const LocalServer&) = delete;
  int port() const { return port_; }

 private:
  pid_t pid_ = -1;
  int readEnd_ = -1;
  int port_ = 0;
};

// How far a client's picture is from lambert's, in 8-bit sRGB steps: per pixel, the largest
// channel difference from the nearest-matching pixel of lambert's picture within one pixel
// (so that a silhouette drawn one pixel over by another rasteriser's rules or multisampling is not
// counted as a difference of shading); the mean and the 99th percentile over all pixels. The
// differences, 8×, are written to `picture` for a person to look at.
struct Difference {
  double mean = 0, p99 = 0, max = 0;
  double meanExact = 0;  // the same without the one-pixel tolerance
};

Difference difference(const PngImage& a, const PngImage& b, const fs::path& picture) {
  Difference d;
  std::vector<std::uint8_t> shown;
  std::vector<double> perPixel;
  auto channelDifference = [&](int x, int y, int u, int v) {
    int largest = 0;
    for (int c = 0; c < 3; ++c)
      largest = std::max(largest, std::abs(int(a.rgb8[3 * (y * a.width + x) + c]) - int(b.rgb8[3 * (v * b.width + u) + c])));
    return largest;
  };
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      int best = 255;
      for (int v = std::max(0, y - 1); v <= std::min(b.height - 1, y + 1); ++v)
        for (int u = std::max(0, x - 1); u <= std::min(b.width - 1, x + 1); ++u) best = std::min(best, channelDifference(x, y, u, v));
      perPixel.push_back(best);
      for (int c = 0; c < 3; ++c) shown.push_back(static_cast<std::uint8_t>(std::min(255, 8 * best)));
      d.meanExact += channelDifference(x, y, x, y);
    }
  d.meanExact /= static_cast<double>(perPixel.size());
  (void)writePng(picture.string(), a.width, a.height, shown);  // for a person to look at
  for (double p : perPixel) d.mean += p;
  d.mean /= static_cast<double>(perPixel.size());
  std::sort(perPixel.begin(), perPixel.end());
  d.p99 = perPixel[static_cast<std::size_t>(0.99 * static_cast<double>(perPixel.size() - 1))];
  d.max = perPixel.back();
  return d;
}

class RealClientsTest : public ::testing::Test {
 protected:
  // One bake for every test: the Cornell box at a 128² atlas, its glb, and lambert's picture of
  // the glb from its camera.
  // Nothing is baked where no client can run (each test then says why it is skipped).
  static bool anyClient() { return chromiumSkipReason().empty() || blenderSkipReason().empty(); }
  static void SetUpTestSuite() {
    dir_ = new fs::path(testing::scratchDirectory("clients", "cornell"));
    bakeOutput_ = new std::string;
    if (!anyClient()) return;
    const fs::path glb = *dir_ / "site/cornell.glb";
    fs::create_directories(glb.parent_path());
    testing::CommandResult result =
        testing::shell(std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --no-cache --lightmaps --lightmap-size 128 --export " +
                       glb.string() + " --image " + (*dir_ / "lambert.png").string() + " --width " + std::to_string(kWidth) +
                       " --height " + std::to_string(kHeight) + " --supersample 1 --json");
    *bakeOutput_ = result.output;
    if (result.exitCode != 0) return;
    const nlohmann::json stats = nlohmann::json::parse(result.output.substr(result.output.find('{')));
    exposureStops_ = stats["exposure_stops"].get<double>();
    baked_ = true;
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete bakeOutput_;
  }
  void SetUp() override {
    if (anyClient()) {
      ASSERT_TRUE(baked_) << *bakeOutput_;
    }
  }

  // The page's screenshot in headless Chromium (software WebGL: SwiftShader), with the page's
  // URL parameters `query` added; fails the test where the page does not say it rendered.
  static std::optional<PngImage> screenshot(const std::string& query, const std::string& name) {
    const fs::path site = *dir_ / "site";
    if (!fs::exists(site / "examples/web")) {
      fs::create_directories(site / "examples");
      fs::create_directories(site / ".tools/node_modules");
      fs::create_directory_symlink(fs::path(LAMBERT_SOURCE_DIR) / "examples/web", site / "examples/web");
      fs::create_directory_symlink(fs::path(LAMBERT_SOURCE_DIR) / ".tools/node_modules/three", site / ".tools/node_modules/three");
    }
    LocalServer server(site);
    EXPECT_GT(server.port(), 0) << "python3 -m http.server did not start";
    if (server.port() <= 0) return std::nullopt;
    const fs::path png = *dir_ / (name + ".png"), profile = *dir_ / (name + "-profile");
    char url[512];
    std::snprintf(url, sizeof url, "http://127.0.0.1:%d/examples/web/lightmap.html?glb=../../cornell.glb&exposure=%.17g&width=%d&height=%d&antialias=0%s",
                  server.port(), exposureStops_, kWidth, kHeight, query.c_str());
    // Closed network, no first-run or background work, a fresh profile; the screenshot is taken
    // once the page is idle (virtual time), at one device pixel per CSS pixel, in plain sRGB.
    const std::string command = "timeout 120 chromium --headless --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader "
                                "--disable-quic --no-first-run --disable-background-networking --disable-component-update --disable-sync "
                                "--user-data-dir=" + profile.string() + " --force-color-profile=srgb --force-device-scale-factor=1 "
                                "--hide-scrollbars --window-size=" + std::to_string(kWidth) + "," + std::to_string(kHeight) +
                                " --virtual-time-budget=30000 --enable-logging=stderr --v=0 --screenshot=" + png.string() + " '" + url + "'";
    testing::CommandResult result = testing::shell(command);
    fs::remove_all(profile);
    EXPECT_TRUE(testing::contains(result.output, "lambert-lightmap: rendered")) << command << "\n" << result.output;
    Result<PngImage> image = readPng(png.string());
    EXPECT_TRUE(image.ok()) << (image.ok() ? "" : image.error().message) << "\n" << result.output;
    if (!image.ok()) return std::nullopt;
    EXPECT_EQ(image->width, kWidth);
    EXPECT_EQ(image->height, kHeight);
    return *image;
  }

  static PngImage lambertImage() {
    Result<PngImage> image = readPng((*dir_ / "lambert.png").string());
    EXPECT_TRUE(image.ok());
    return image.ok() ? *image : PngImage{};
  }

  static inline fs::path* dir_ = nullptr;
  static inline std::string* bakeOutput_ = nullptr;
  static inline double exposureStops_ = 0;
  static inline bool baked_ = false;
};

// The share of pixels brighter than black, and whether the left wall is red and the right green
// (the page drew the box, not a blank or black canvas).
void expectTheCornellBox(const PngImage& image) {
  std::size_t lit = 0;
  for (std::size_t i = 0; i < image.rgb8.size(); i += 3) lit += image.rgb8[i] + image.rgb8[i + 1] + image.rgb8[i + 2] > 30;
  EXPECT_GT(static_cast<double>(lit) / (image.width * image.height), 0.9);
  auto pixel = [&](int x, int y, int c) { return int(image.rgb8[3 * (y * image.width + x) + c]); };
  const int y = image.height / 2;
  EXPECT_GT(pixel(image.width / 10, y, 0), pixel(image.width / 10, y, 1) + 40) << "left wall not red";
  EXPECT_GT(pixel(image.width * 9 / 10, y, 1), pixel(image.width * 9 / 10, y, 0) + 15) << "right wall not green";
}

// `solve --image` is lambert's picture of the lightmapped glb: it and its size need --lightmaps
// (and --image), and an EXR takes no exposure; each is refused before any work.
TEST(LightmapImageCliTest, ImageOptionsAreRefusedWhereTheyWouldDoNothing) {
  const std::string lambert = std::string(LAMBERT_CLI_PATH) + " solve --scene cornell --no-cache ";
  const fs::path dir = testing::scratchDirectory("clients", "refusals");
  const std::string glb = " --export " + (dir / "a.glb").string();
  struct Case {
    std::string arguments, says;
  };
  for (const Case& c : {Case{"--image " + (dir / "a.png").string(), "--image has no effect"},
                        Case{"--lightmaps" + glb + " --width 64", "--width has no effect"},
                        Case{"--lightmaps" + glb + " --image " + (dir / "a.jpg").string(), ".png"},
                        Case{"--lightmaps" + glb + " --image " + (dir / "a.exr").string() + " --exposure 1", "--exposure has no effect"},
                        Case{"--lightmaps" + glb + " --exposure 1", "--exposure has no effect"}}) {
    testing::CommandResult result = testing::shell(lambert + c.arguments);
    EXPECT_EQ(result.exitCode, 2) << c.arguments << "\n" << result.output;
    EXPECT_TRUE(testing::contains(result.output, c.says)) << c.arguments << "\n" << result.output;
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

// One test for the three pages, so that a process (ctest runs each test in its own) bakes once.
TEST_F(RealClientsTest, ChromiumDrawsTheGlbAsLambertDoesAndNotWithoutItsLightmap) {
  if (const std::string skip = chromiumSkipReason(); !skip.empty()) GTEST_SKIP() << skip;
  const PngImage lambert = lambertImage();
  {
    SCOPED_TRACE("the glb's own lightmap");
    std::optional<PngImage> browser = screenshot("", "browser");
    ASSERT_TRUE(browser);
    expectTheCornellBox(*browser);
    const Difference d = difference(*browser, lambert, *dir_ / "browser-difference.png");
    std::printf("three.js (glb's 8-bit lightmap) vs lambert: mean %.2f, p99 %.0f, max %.0f (exact pixels: mean %.2f) / 255\n", d.mean,
                d.p99, d.max, d.meanExact);
    // The glb's lightmap is linear 8-bit (io/lightmap_export.h): E is rounded to S/510, which
    // the sRGB transfer, steepest near black, turns into up to 6 steps on the darkest faces
    // (measured: the blocks' sides in shadow, in bands; the mean is 0.9).
    EXPECT_LT(d.mean, 1.5);
    EXPECT_LE(d.p99, 6.0);
    EXPECT_LE(d.max, 10.0);
  }
  {
    SCOPED_TRACE("the EXR lightmap");
    std::optional<PngImage> browser = screenshot("&lightmap=exr", "browser-exr");
    ASSERT_TRUE(browser);
    expectTheCornellBox(*browser);
    const Difference d = difference(*browser, lambert, *dir_ / "browser-exr-difference.png");
    std::printf("three.js (EXR lightmap) vs lambert: mean %.2f, p99 %.0f, max %.0f (exact pixels: mean %.2f) / 255\n", d.mean, d.p99,
                d.max, d.meanExact);
    // Half floats: nothing left but the GPU's own rounding.
    EXPECT_LT(d.mean, 0.25);
    EXPECT_LE(d.p99, 1.0);
    EXPECT_LE(d.max, 3.0);
  }
  {
    SCOPED_TRACE("no lightmap");  // the comparison can fail: the page without its lightmap
    std::optional<PngImage> browser = screenshot("&lightmap=none", "browser-no-lightmap");
    ASSERT_TRUE(browser);
    const Difference d = difference(*browser, lambert, *dir_ / "browser-no-lightmap-difference.png");
    std::printf("three.js without the lightmap vs lambert: mean %.2f, p99 %.0f / 255\n", d.mean, d.p99);
    EXPECT_GT(d.mean, 10.0);
    EXPECT_GT(d.p99, 50.0);
  }
}

TEST_F(RealClientsTest, BlenderImportsTheGlbWithItsLightmapUvs) {
  if (const std::string skip = blenderSkipReason(); !skip.empty()) GTEST_SKIP() << skip;
  const std::string command = "timeout 120 blender -b --factory-startup --python-exit-code 1 --python " + std::string(LAMBERT_SOURCE_DIR) +
                              "/tests/blender_import.py -- " + (*dir_ / "site/cornell.glb").string();
  testing::CommandResult result = testing::shell(command);
  if (result.exitCode == 77) {
    const std::size_t at = result.output.find("blender-import: skip: ");
    GTEST_SKIP() << (at == std::string::npos ? result.output : result.output.substr(at, result.output.find('\n', at) - at));
  }
  EXPECT_EQ(result.exitCode, 0) << command << "\n" << result.output;
  EXPECT_TRUE(testing::contains(result.output, "blender-import: ok")) << result.output;
}

}  // namespace
}  // namespace lambert
