// The CLI when its run is cut short: Ctrl-C or SIGTERM in the middle of a solve, and a write that
// fails for lack of space. Neither may leave a partial file or harm the previous output.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "lambert/core/memory.h"
#include "lambert/io/png.h"
#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::contains;
using testing::hasTemporaryFiles;
using testing::shell;

// Starts the CLI with the arguments, its output into `log`.
pid_t start(const std::vector<std::string>& arguments, const fs::path& log) {
  std::vector<std::string> args{LAMBERT_CLI_PATH};
  args.insert(args.end(), arguments.begin(), arguments.end());
  pid_t pid = fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stderr);
    std::freopen(log.c_str(), "a", stdout);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

// Waits up to `limit` for the process; its exit code, or -1 (killed, or still running: then it
// is killed).
int waitFor(pid_t pid, std::chrono::duration<double> limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

void interruptMidSolve(int signal, int expectedExit) {
  const fs::path dir = testing::scratchDirectory("reliability", "signal-" + std::to_string(signal));
  const fs::path image = dir / "cornell.png", cache = dir / "cache";
  // The previous output and a cache from an earlier run, which must survive.
  ASSERT_EQ(shell(std::string(LAMBERT_CLI_PATH) + " render --quiet --width 64 --height 64 --cache-dir " + cache.string() +
                  " -o " + image.string())
                .exitCode,
            0);
  const std::vector<char> previousImage = testing::readBytes(image);
  std::vector<std::pair<fs::path, std::vector<char>>> previousCache;
  for (const auto& entry : fs::directory_iterator(cache)) previousCache.emplace_back(entry.path(), testing::readBytes(entry.path()));
  ASSERT_FALSE(previousCache.empty());

  // A solve that takes several seconds (the default method refining the box to link error 3e-6,
  // some twenty times the default's time), stopped after a second and a half.
  const pid_t pid = start({"render", "--link-error", "3e-6", "--cache-dir", cache.string(), "-o", image.string()}, dir / "log.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(waitpid(pid, nullptr, WNOHANG), 0) << "the solve ended before it could be interrupted";
  const auto sent = std::chrono::steady_clock::now();
  kill(pid, signal);
  const int exitCode = waitFor(pid, std::chrono::seconds(5));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  const std::vector<char> log = testing::readBytes(dir / "log.txt");
  const std::string output(log.begin(), log.end());
  EXPECT_EQ(exitCode, expectedExit) << output;
  std::printf("signal %d: exited %.3f s after it was sent\n", signal, seconds);
  EXPECT_LT(seconds, 1.0);
  EXPECT_TRUE(contains(output, "lambert: interrupted")) << output;
  EXPECT_EQ(testing::readBytes(image), previousImage);
  EXPECT_FALSE(hasTemporaryFiles(dir));
  EXPECT_FALSE(hasTemporaryFiles(cache));
  // The earlier run's cache files are all there, unchanged. The interrupted run may have added
  // its own links whole (they are written atomically once the refinement ends, which on an idle
  // machine comes before the signal), never a part of one (no temporary files, above).
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(cache)) ++files, (void)entry;
  EXPECT_GE(files, previousCache.size());
  for (const auto& [path, bytes] : previousCache) EXPECT_EQ(testing::readBytes(path), bytes) << path;
}

TEST(ReliabilityTest, CtrlCStopsWithin1SecondAndKeepsThePreviousImageAndCache) { interruptMidSolve(SIGINT, 130); }

TEST(ReliabilityTest, SigtermStopsTheSameWay) { interruptMidSolve(SIGTERM, 143); }

TEST(ReliabilityTest, AWriteBeyondTheFileSizeLimitFailsNamingTheFileAndKeepsTheOldOne) {
  const fs::path dir = testing::scratchDirectory("reliability", "disk-full");
  const fs::path image = dir / "cornell.png";
  testing::writeBytes(image, {'o', 'l', 'd'});
  // A full disk, as the process sees it: no file may grow past 4 KiB (the PNG is larger).
  testing::CommandResult result = shell("ulimit -f 4 && " + std::string(LAMBERT_CLI_PATH) +
                                        " render --no-cache --width 256 --height 256 -o " + image.string());
  EXPECT_EQ(result.exitCode, 1) << result.output;
  EXPECT_TRUE(contains(result.output, image.string())) << result.output;
  EXPECT_TRUE(contains(result.output, "File too large")) << result.output;
  EXPECT_EQ(testing::readBytes(image), (std::vector<char>{'o', 'l', 'd'}));
  EXPECT_FALSE(hasTemporaryFiles(dir));
}

// One solve and render through the CLI with a thread limit: the solution's hash and the image.
struct ThreadedRun {
  std::string solutionHash;
  std::vector<char> image;
};

ThreadedRun renderWithThreads(int threads, const std::string& arguments, const fs::path& dir) {
  const fs::path image = dir / ("threads-" + std::to_string(threads) + ".png");
  testing::CommandResult result = shell(std::string(LAMBERT_CLI_PATH) + " render --threads " + std::to_string(threads) +
                                        " --no-cache --json --width 96 --height 96 -o " + image.string() + " " + arguments);
  EXPECT_EQ(result.exitCode, 0) << arguments << "\n" << result.output;
  ThreadedRun run;
  const std::string key = "\"solution_hash\": \"";
  if (std::size_t at = result.output.find(key); at != std::string::npos)
    run.solutionHash = result.output.substr(at + key.size(), 16);
  run.image = testing::readBytes(image);
  return run;
}

// Every method and loader gives the same radiosity and image to the bit on 1 thread as on 2.
class DeterminismTest : public ::testing::TestWithParam<const char*> {};

TEST_P(DeterminismTest, OneAndTwoThreadsGiveBitIdenticalRadiosityAndImages) {
  const fs::path dir = testing::scratchDirectory("reliability", "determinism-" + std::to_string(std::hash<std::string>{}(GetParam())));
  std::string arguments = GetParam();
  if (arguments.find("{ply}") != std::string::npos) {
    // A PLY box, written here: a floor and a lit ceiling facing each other.
    const fs::path ply = dir / "box.ply";
    std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                          "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n1 0 0\n1 0 1\n0 0 1\n0 1 0\n0 1 1\n1 1 1\n1 1 0\n4 0 3 2 1\n4 4 7 6 5\n";
    arguments.replace(arguments.find("{ply}"), 5, ply.string());
  }
  const ThreadedRun one = renderWithThreads(1, arguments, dir), two = renderWithThreads(2, arguments, dir);
  ASSERT_EQ(one.solutionHash.size(), 16u);
  EXPECT_EQ(one.solutionHash, two.solutionHash) << arguments;
  EXPECT_FALSE(one.image.empty());
  EXPECT_TRUE(one.image == two.image) << arguments << ": the images differ";
}

INSTANTIATE_TEST_SUITE_P(
    EveryMethodAndLoader, DeterminismTest,
    ::testing::Values(
        // Methods on the Cornell box: hierarchical (the default) with both gathering solvers and
        // without clusters; the flat mesh with every form-factor method and solver; adaptive.
        "--scene cornell", "--scene cornell-spots --solver jacobi", "--scene cornell --no-clusters --link-error 1e-3",
        "--scene cornell --patches 300 --formfactor mc --solver gs", "--scene cornell --patches 300 --formfactor point --solver jacobi",
        "--scene cornell --patches 300 --formfactor hemicube --hemicube-resolution 64 --solver direct",
        "--scene cornell-spots --patches 300 --formfactor hemisphere --hemisphere-rays 256 --solver shoot",
        "--scene cornell-spots --adaptive --max-level 2",
        // Loaders: a scene file, OBJ, glTF, GLB with lights, MGF, PLY.
        "--scene " LAMBERT_SOURCE_DIR "/scenes/cornell/cornell-spots.json",
        "--scene " LAMBERT_SOURCE_DIR "/scenes/cornell/cornell.obj --units mm",
        "--scene " LAMBERT_SOURCE_DIR "/scenes/room/room.gltf", "--scene " LAMBERT_SOURCE_DIR "/tests/data/blender_room.glb",
        "--scene " LAMBERT_SOURCE_DIR "/scenes/floor/floor.mgf --mgf-divisions 8", "--scene {ply}"));

// 21 renders at once on one cache directory, a third of them on the uniform mesh (the form-factor
// matrix, .lff), a third adaptive (the master table, .lft) and a third hierarchical with a glb
// (the links, .lhl, and the final gather's visibility values and irradiance at every vertex, .lhv
// and .lhg): writers race to rename their caches into place while others read them. Every image
// must be the one a cacheless render makes, and the cache must be whole afterwards.
TEST(ReliabilityTest, TwentyConcurrentRendersShareOneCacheDirectory) {
  const fs::path dir = testing::scratchDirectory("reliability", "concurrent-cache");
  const fs::path cache = dir / "cache";
  const std::string cli = LAMBERT_CLI_PATH;
  const std::string kinds[] = {" render --threads 1 --scene cornell-spots --patches 300 --width 64 --height 64",
                               " render --threads 1 --scene cornell-spots --adaptive --max-level 2 --width 64 --height 64",
                               " render --threads 1 --scene cornell-spots --link-error 1e-3 --width 64 --height 64 --exposure -3 --export " +
                                   (dir / "hierarchical.glb").string()};
  const std::string quiet = " --quiet";
  std::vector<std::vector<char>> images;
  for (int k = 0; k < 3; ++k) {
    const fs::path image = dir / ("cacheless-" + std::to_string(k) + ".png");
    ASSERT_EQ(shell(cli + kinds[k] + quiet + " --no-cache -o " + image.string()).exitCode, 0);
    images.push_back(testing::readBytes(image));
  }

  // Two waves, so that the second starts while the first writes its caches.
  std::string script = "pids=''; status=0\n";
  for (int i = 0; i < 21; ++i) {
    if (i == 9) script += "sleep 0.3\n";
    script += cli + kinds[i % 3] + quiet + " --cache-dir " + cache.string() + " -o " + (dir / ("run-" + std::to_string(i) + ".png")).string() +
              " > " + (dir / ("run-" + std::to_string(i) + ".log")).string() + " 2>&1 & pids=\"$pids $!\"\n";
  }
  script += "for p in $pids; do wait $p || status=1; done; exit $status\n";
  std::ofstream(dir / "race.sh") << script;
  testing::CommandResult raced = shell("sh " + (dir / "race.sh").string());
  EXPECT_EQ(raced.exitCode, 0) << raced.output;

  for (int i = 0; i < 21; ++i) {
    const std::vector<char> log = testing::readBytes(dir / ("run-" + std::to_string(i) + ".log"));
    EXPECT_TRUE(testing::readBytes(dir / ("run-" + std::to_string(i) + ".png")) == images[i % 3])
        << "run " << i << ": " << std::string(log.begin(), log.end());
  }
  EXPECT_FALSE(hasTemporaryFiles(cache));
  EXPECT_EQ(std::distance(fs::directory_iterator(cache), fs::directory_iterator()), 5);
  // The caches left behind are whole: the next runs load them and draw the same images.
  for (int k = 0; k < 3; ++k) {
    const fs::path image = dir / "after.png";
    testing::CommandResult after = shell(cli + kinds[k] + " --json --cache-dir " + cache.string() + " -o " + image.string());
    EXPECT_EQ(after.exitCode, 0) << after.output;
    EXPECT_TRUE(contains(after.output, "loaded")) << after.output;
    EXPECT_FALSE(contains(after.output, "lambert: warning")) << after.output;
    EXPECT_TRUE(testing::readBytes(image) == images[k]) << kinds[k];
  }
}

// Solves that would not fit are refused before they allocate, naming the figure and what to do,
// exit 2 and no image: the dense matrix, the hierarchical links, the adaptive active set. The
// same solves pass once --memory-limit allows them.
TEST(ReliabilityTest, SolvesThatWouldNotFitAreRefusedWithTheFigure) {
  const fs::path dir = testing::scratchDirectory("reliability", "memory");
  const fs::path image = dir / "out.png";
  const std::string cli = std::string(LAMBERT_CLI_PATH) + " render --no-cache --width 32 --height 32 -o " + image.string();
  struct Case {
    std::string arguments, message;
  };
  const Case cases[] = {
      {"--patches 3000 --memory-limit 10M",
       "the dense form-factor matrix of 3152 patches needs 37.9 MiB, more than the 10.0 MiB of memory --memory-limit allows; use the "
       "hierarchical method"},
      {"--memory-limit 200k", "the hierarchical refinement, unfinished at"},
      {"--scene cornell-spots --adaptive --memory-limit 100k", "active cells needs"},
  };
  for (const Case& c : cases) {
    testing::CommandResult refused = shell(cli + " " + c.arguments);
    EXPECT_EQ(refused.exitCode, 2) << c.arguments << "\n" << refused.output;
    EXPECT_TRUE(contains(refused.output, c.message)) << refused.output;
    EXPECT_TRUE(contains(refused.output, "--memory-limit to allow more")) << refused.output;
    EXPECT_FALSE(fs::exists(image));
    EXPECT_FALSE(hasTemporaryFiles(dir));
  }
  EXPECT_EQ(shell(cli + " --patches 3000 --memory-limit 64M --formfactor point").exitCode, 0);
  EXPECT_TRUE(fs::exists(image));

  // Without --memory-limit the machine's available memory is the limit: a mesh whose matrix is
  // twice that is refused before anything is computed.
  const double available = availableMemoryBytes();
  if (available <= 0) GTEST_SKIP() << "no MemAvailable in /proc/meminfo";
  const double patches = std::sqrt(2 * available / sizeof(float));
  if (patches > 200000) GTEST_SKIP() << "this machine's memory holds the largest dense matrix --patches allows";
  testing::CommandResult refused = shell(cli + " --patches " + std::to_string(static_cast<long>(patches)));
  EXPECT_EQ(refused.exitCode, 2) << refused.output;
  EXPECT_TRUE(contains(refused.output, "of memory available (MemAvailable)")) << refused.output;
}

}  // namespace
}  // namespace lambert
