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
#include <map>
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
  if (!fs::exists(fs::path(LAMBERT_SOURCE_DIR) / ".tools/node_modules/puppeteer-core/package.json"))
    return "no puppeteer-core in .tools/ (npm puppeteer-core, installed by scripts/install-deps.sh where npm reaches the registry)";
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

// A scene baked once per test process: its lightmapped glb in `site/` and lambert's picture of
// that glb from its camera (`--image`, what a client of the glb must draw), with its exposure.
struct Baked {
  fs::path dir;
  std::string glb;  // its name in dir/site
  std::string output;
  double exposureStops = 0;
  bool ok = false;
};

// `lambert solve ARGUMENTS --lightmaps --export site/NAME.glb --image lambert.png` at the clients'
// picture size, in a scratch folder of its own; baked at the first call for NAME.
const Baked& bake(const std::string& name, const std::string& arguments) {
  static std::map<std::string, Baked> baked;
  if (auto it = baked.find(name); it != baked.end()) return it->second;
  Baked& b = baked[name];
  b.dir = testing::scratchDirectory("clients", name);
  b.glb = name + ".glb";
  const fs::path glb = b.dir / "site" / b.glb;
  fs::create_directories(glb.parent_path());
  testing::CommandResult result =
      testing::shell(std::string(LAMBERT_CLI_PATH) + " solve " + arguments + " --no-cache --lightmaps --export " + glb.string() +
                     " --image " + (b.dir / "lambert.png").string() + " --width " + std::to_string(kWidth) + " --height " +
                     std::to_string(kHeight) + " --supersample 1 --json");
  b.output = result.output;
  if (result.exitCode != 0) return b;
  const nlohmann::json stats = nlohmann::json::parse(result.output.substr(result.output.find('{')));
  b.exposureStops = stats["exposure_stops"].get<double>();
  b.ok = true;
  return b;
}

// The page's picture of a bake's glb in headless Chromium (software WebGL: SwiftShader; its
// canvas read once the page says it rendered, tests/web-screenshot.js), with the page's URL
// parameters `query` added; fails the test where the page does not say it rendered.
std::optional<PngImage> screenshot(const Baked& baked, const std::string& query, const std::string& name) {
  const fs::path site = baked.dir / "site";
  if (!fs::exists(site / "examples/web")) {
    fs::create_directories(site / "examples");
    fs::create_directories(site / ".tools/node_modules");
    fs::create_directory_symlink(fs::path(LAMBERT_SOURCE_DIR) / "examples/web", site / "examples/web");
    fs::create_directory_symlink(fs::path(LAMBERT_SOURCE_DIR) / ".tools/node_modules/three", site / ".tools/node_modules/three");
  }
  LocalServer server(site);
  EXPECT_GT(server.port(), 0) << "python3 -m http.server did not start";
  if (server.port() <= 0) return std::nullopt;
  const fs::path png = baked.dir / (name + ".png");
  char url[512];
  std::snprintf(url, sizeof url, "http://127.0.0.1:%d/examples/web/lightmap.html?glb=../../%s&exposure=%.17g&width=%d&height=%d&antialias=0%s",
                server.port(), baked.glb.c_str(), baked.exposureStops, kWidth, kHeight, query.c_str());
  const std::string command = "timeout 150 node " + std::string(LAMBERT_SOURCE_DIR) + "/tests/web-screenshot.js " + std::string(LAMBERT_SOURCE_DIR) +
                              "/.tools/node_modules/puppeteer-core '" + url + "' " + png.string() + " " + std::to_string(kWidth) + " " +
                              std::to_string(kHeight) + " 2>&1";
  testing::CommandResult result = testing::shell(command);
  EXPECT_EQ(result.exitCode, 0) << command << "\n" << result.output;
  EXPECT_TRUE(testing::contains(result.output, "lambert-lightmap: rendered")) << command << "\n" << result.output;
  Result<PngImage> image = readPng(png.string());
  EXPECT_TRUE(image.ok()) << (image.ok() ? "" : image.error().message) << "\n" << result.output;
  if (!image.ok()) return std::nullopt;
  EXPECT_EQ(image->width, kWidth);
  EXPECT_EQ(image->height, kHeight);
  return *image;
}

PngImage lambertImage(const Baked& baked) {
  Result<PngImage> image = readPng((baked.dir / "lambert.png").string());
  EXPECT_TRUE(image.ok());
  return image.ok() ? *image : PngImage{};
}

// Chromium's pictures of the glb against lambert's picture of the same glb (the RGBM it carries):
//   - with the glb's own lightmaps: the plugin's decoding and filtering are lambert's, so only the
//     GPU's rounding is left;
//   - with the EXRs beside the glb (half floats, three's own filtering): what RGBM loses against
//     full precision, the dynamic range the glb carries.
// Both within a step in the mean and a few at the 99th percentile. The largest differences are
// where the pictures differ for other reasons, returned for the caller to bound: cracks
// SwiftShader leaves at T-junctions of a scene's mesh (office2), and three.js's mip-mapped
// base-colour textures at grazing angles, where lambert reads the texture at the point (the
// Blender room's checker floor).
struct ClientDifferences {
  Difference glb, exr;
};
ClientDifferences expectChromiumDrawsAsLambert(const Baked& baked, const std::string& what) {
  ClientDifferences out{{255, 255, 255, 255}, {255, 255, 255, 255}};
  const PngImage lambert = lambertImage(baked);
  for (const char* source : {"glb", "exr"}) {
    std::optional<PngImage> browser = screenshot(baked, std::string("&lightmap=") + source, std::string("browser-") + source);
    if (!browser) continue;
    const Difference d = difference(*browser, lambert, baked.dir / ("browser-" + std::string(source) + "-difference.png"));
    std::printf("%s: three.js (%s lightmap) vs lambert: mean %.2f, p99 %.0f, max %.0f (exact pixels: mean %.2f) / 255\n", what.c_str(),
                source, d.mean, d.p99, d.max, d.meanExact);
    EXPECT_LT(d.mean, 0.5) << what << ", " << source;
    EXPECT_LE(d.p99, 6.0) << what << ", " << source;
    (source == std::string("glb") ? out.glb : out.exr) = d;
  }
  return out;
}

const Baked& cornell() { return bake("cornell", "--scene cornell --lightmap-size 128"); }

// The Cornell box: with its lightmaps within a step everywhere; without them (the comparison can
// fail), far off.
TEST(RealClientsTest, ChromiumDrawsTheCornellBoxAsLambertDoesAndNotWithoutItsLightmap) {
  if (const std::string skip = chromiumSkipReason(); !skip.empty()) GTEST_SKIP() << skip;
  const Baked& baked = cornell();
  ASSERT_TRUE(baked.ok) << baked.output;
  const PngImage lambert = lambertImage(baked);
  expectTheCornellBox(lambert);
  const ClientDifferences d = expectChromiumDrawsAsLambert(baked, "cornell");
  EXPECT_LE(d.glb.max, 3.0);
  EXPECT_LE(d.exr.max, 3.0);
  std::optional<PngImage> browser = screenshot(baked, "&lightmap=none", "browser-no-lightmap");
  ASSERT_TRUE(browser);
  const Difference none = difference(*browser, lambert, baked.dir / "browser-no-lightmap-difference.png");
  std::printf("three.js without the lightmap vs lambert: mean %.2f, p99 %.0f / 255\n", none.mean, none.p99);
  EXPECT_GT(none.mean, 10.0);
  EXPECT_GT(none.p99, 50.0);
}

// Blender's export of a room (tests/data/blender_room.glb: two-sided faces, emissive panels, a
// lightmap of 2.5 cm texels whose brightest, beside the panels, is far above the rest).
TEST(RealClientsTest, ChromiumDrawsBlendersRoomAsLambertDoes) {
  if (const std::string skip = chromiumSkipReason(); !skip.empty()) GTEST_SKIP() << skip;
  const Baked& baked = bake("blender-room", "--scene " + std::string(LAMBERT_SOURCE_DIR) + "/tests/data/blender_room.glb");
  ASSERT_TRUE(baked.ok) << baked.output;
  expectChromiumDrawsAsLambert(baked, "blender room");
}

// RenderPark's office2 (RenderPark's own files, which the project does not keep: set LAMBERT_CORPUS
// to the folder scripts/fetch-corpus.py fills). Its lamps light the ceiling above them hundreds
// of times more than the rest: 8-bit linear lightmaps left 99.6% of its texels under 16/255.
TEST(RealClientsTest, ChromiumDrawsRenderParksOffice2AsLambertDoes) {
  if (const std::string skip = chromiumSkipReason(); !skip.empty()) GTEST_SKIP() << skip;
  const char* corpus = std::getenv("LAMBERT_CORPUS");
  const fs::path scene = fs::path(corpus ? corpus : "") / "renderpark/etc/office2/office2.mgf";
  if (!corpus || !fs::exists(scene)) GTEST_SKIP() << "no " << scene << " (set LAMBERT_CORPUS to scripts/fetch-corpus.py's folder)";
  const Baked& baked = bake("office2", "--scene " + scene.string() + " --sides one");
  ASSERT_TRUE(baked.ok) << baked.output;
  expectChromiumDrawsAsLambert(baked, "office2");
}

TEST(RealClientsTest, BlenderImportsTheGlbWithItsLightmapUvs) {
  if (const std::string skip = blenderSkipReason(); !skip.empty()) GTEST_SKIP() << skip;
  const Baked& baked = cornell();
  ASSERT_TRUE(baked.ok) << baked.output;
  const std::string command = "timeout 120 blender -b --factory-startup --python-exit-code 1 --python " + std::string(LAMBERT_SOURCE_DIR) +
                              "/tests/blender_import.py -- " + (baked.dir / "site" / baked.glb).string();
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
