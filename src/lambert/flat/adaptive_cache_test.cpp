// The adaptive engine with a cache directory: the master table is saved at the end of a run and
// loaded by the next, which then estimates nothing and solves identically; damaged, foreign and
// unwritable files are warnings that never change the answer.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "lambert/engine/radiosity.h"
#include "lambert/flat/table.h"
#include "tests/support/files.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::hasTemporaryFiles;
using testing::contains;

constexpr std::size_t kHeaderBytes = 32, kEntryBytes = 20;  // the .lft layout (table.cpp)
const QuadtreeOptions kQuadtree{0.34, 2};

fs::path scratch(const std::string& name) { return testing::scratchDirectory("adaptive-cache", name); }


Light downwardSpot() {
  Light spot;
  spot.kind = LightKind::Spot;
  spot.position = {0.5, 0.95, 0.5};
  spot.direction = normalize(Vec3{0.3, -1, 0.2});
  spot.intensity = {1, 1, 1};
  spot.coneAngleDegrees = 25;
  spot.falloffDegrees = 5;
  return spot;
}

RadiosityOptions cachedOptions(const fs::path& dir) {
  RadiosityOptions options;
  options.meshing = MeshStrategy::Adaptive;
  options.adaptive.quadtree = kQuadtree;
  options.formFactors.showProgress = false;
  options.cacheDirectory = dir.string();
  return options;
}

std::string tablePath(const fs::path& dir, const RadiosityOptions& options) {
  return formFactorTablePath(dir.string(), formFactorTableKey(testing::closedCube(1), kQuadtree, options.formFactors));
}

struct SolvedRun {
  std::unique_ptr<Radiosity> engine;
  std::vector<Rgb> radiosity;
  std::string stderrText;
  Status saved = Ok{};

  std::int64_t stat(const std::string& key) const { return std::get<std::int64_t>(engine->stats().find(key)->value); }
  std::string cache() const { return std::get<std::string>(engine->stats().find("formfactor_cache")->value); }
};

// Creates, solves twice (refining along the spot's edge and then by gradient) and saves.
SolvedRun solve(const RadiosityOptions& options, bool save = true) {
  SolvedRun run;
  ::testing::internal::CaptureStderr();
  auto created = Radiosity::create(testing::closedCube(1), options);
  if (created) {
    run.engine = std::move(*created);
    run.engine->setLights({downwardSpot()});
    EXPECT_TRUE(run.engine->solve().ok());
    EXPECT_TRUE(run.engine->solve().ok());
    run.radiosity = run.engine->solution().radiosity();
    if (save) run.saved = run.engine->saveCache();
  }
  run.stderrText = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(created.ok()) << created.error().message;
  return run;
}

TEST(AdaptiveCacheTest, SecondRunLoadsEverythingAndSolvesIdentically) {
  const fs::path dir = scratch("adaptive") / "cache";
  const std::string path = tablePath(dir, cachedOptions(dir));
  SolvedRun first = solve(cachedOptions(dir));
  EXPECT_TRUE(first.stderrText.empty()) << first.stderrText;
  EXPECT_EQ(first.cache().rfind("saved " + path + " (", 0), 0u) << first.cache();
  EXPECT_TRUE(fs::is_regular_file(path));
  EXPECT_GT(first.stat("pairs_estimated"), 0);
  EXPECT_GT(first.stat("cells_created"), first.stat("patches"));  // it refined

  SolvedRun second = solve(cachedOptions(dir));
  EXPECT_TRUE(second.stderrText.empty()) << second.stderrText;
  EXPECT_EQ(second.cache().rfind("loaded " + path + " (", 0), 0u) << second.cache();
  EXPECT_FALSE(contains(second.cache(), "saved"));  // nothing new: the file already holds these pairs
  EXPECT_EQ(second.stat("pairs_estimated"), 0);
  EXPECT_EQ(second.stat("pairs_loaded"), first.stat("pairs_estimated"));
  EXPECT_EQ(second.radiosity, first.radiosity);

  // Off: neither read nor written.
  RadiosityOptions off = cachedOptions(dir);
  off.cacheDirectory.clear();
  SolvedRun uncached = solve(off);
  EXPECT_EQ(uncached.cache(), "off");
  EXPECT_EQ(uncached.stat("pairs_loaded"), 0);
  EXPECT_EQ(uncached.radiosity, first.radiosity);
  EXPECT_TRUE(uncached.saved.ok());

  // Another seed is another file.
  RadiosityOptions reseeded = cachedOptions(dir);
  reseeded.formFactors.seed = 7;
  SolvedRun other = solve(reseeded);
  EXPECT_FALSE(contains(other.cache(), "loaded"));
  EXPECT_FALSE(contains(other.cache(), path));
  EXPECT_GT(other.stat("pairs_estimated"), 0);
}

TEST(AdaptiveCacheTest, DamagedFileWarnsRecomputesAndIsRepaired) {
  const fs::path dir = scratch("damaged");
  SolvedRun first = solve(cachedOptions(dir));
  const std::string path = tablePath(dir, cachedOptions(dir));
  const std::vector<char> good = testing::readBytes(path);

  for (bool truncate : {false, true}) {
    SCOPED_TRACE(truncate ? "truncated" : "flipped");
    std::vector<char> damaged = good;
    if (truncate) damaged.resize(good.size() * 2 / 3);
    else damaged[kHeaderBytes + kEntryBytes * 7 + 18] ^= 0x20;
    testing::writeBytes(path, damaged);
    SolvedRun again = solve(cachedOptions(dir));
    EXPECT_TRUE(contains(again.stderrText, "lambert: warning: " + path + ": ")) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, truncate ? "truncated" : "checksum")) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, "; recomputing\n")) << again.stderrText;
    EXPECT_EQ(again.stat("pairs_loaded"), 0);
    EXPECT_EQ(again.stat("pairs_estimated"), first.stat("pairs_estimated"));
    EXPECT_EQ(again.radiosity, first.radiosity);
    // Replaced by a valid file, the same bytes as the first run's.
    EXPECT_EQ(again.cache().rfind("saved " + path, 0), 0u) << again.cache();
    EXPECT_EQ(testing::readBytes(path), good);
    EXPECT_FALSE(hasTemporaryFiles(dir));
  }
}

TEST(AdaptiveCacheTest, FileOfAnotherKeyAtThePathIsRecomputed) {
  // The right name but another scene's pairs (as if copied or renamed): a table saved under a
  // different key, written to this run's path.
  const fs::path dir = scratch("stale");
  const fs::path elsewhere = scratch("stale-other");
  RadiosityOptions reseeded = cachedOptions(elsewhere);
  reseeded.formFactors.seed = 99;
  SolvedRun foreign = solve(reseeded);
  const std::string path = tablePath(dir, cachedOptions(dir));
  fs::create_directories(dir);
  fs::copy_file(tablePath(elsewhere, reseeded), path);
  SolvedRun again = solve(cachedOptions(dir));
  EXPECT_TRUE(contains(again.stderrText, "lambert: warning: " + path + ": key mismatch")) << again.stderrText;
  EXPECT_EQ(again.stat("pairs_loaded"), 0);
  EXPECT_EQ(again.cache().rfind("saved ", 0), 0u) << again.cache();
  EXPECT_TRUE(contains(solve(cachedOptions(dir)).cache(), "loaded "));
}

TEST(AdaptiveCacheTest, UnwritableDirectoryWarnsAndStillSolves) {
  const fs::path dir = scratch("readonly");
  testing::writeBytes(dir / "file", {'x'});
  const fs::path cache = dir / "file" / "cache";
  SolvedRun run = solve(cachedOptions(cache), false);
  ::testing::internal::CaptureStderr();
  Status saved = run.engine->saveCache();
  const std::string printed = ::testing::internal::GetCapturedStderr();
  ASSERT_FALSE(saved.ok());
  const std::string path = tablePath(cache, cachedOptions(cache));
  EXPECT_TRUE(contains(saved.error().message, path)) << saved.error().message;
  EXPECT_TRUE(contains(printed, "lambert: warning: " + path + ": ")) << printed;
  EXPECT_EQ(run.cache(), "not saved: " + path);
  EXPECT_FALSE(run.radiosity.empty());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace lambert
