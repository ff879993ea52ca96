// The hierarchical link cache from the command line: --cache-dir is an option every method reads
// (it never chooses the flat method), a second run loads the links and the final gather's
// visibility values and irradiance and writes the same vertex file, byte for byte, and --no-cache reads and
// writes nothing, not even in the default cache directory.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::contains;
using testing::shell;

std::size_t filesIn(const fs::path& dir) {
  if (!fs::exists(dir)) return 0;
  std::size_t n = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) n += entry.is_regular_file();
  return n;
}

nlohmann::json statsOf(const CommandResult& r) {
  EXPECT_EQ(r.exitCode, 0) << r.output;
  const std::size_t brace = r.output.find('{');
  return brace == std::string::npos ? nlohmann::json::object() : nlohmann::json::parse(r.output.substr(brace));
}

TEST(LinkCacheCliTest, CacheDirSolvesHierarchicallyAndTheSecondRunLoadsTheLinks) {
  const fs::path dir = testing::scratchDirectory("link-cache-cli", "building");
  const std::string cli = LAMBERT_CLI_PATH;
  const std::string building = (dir / "b.json").string();
  ASSERT_EQ(shell(cli + " generate building --rooms 2 --face-size 0.5 -o " + building).exitCode, 0);
  // Everything but the cache is left at the defaults: --cache-dir alone must not choose flat.
  const std::string solve = cli + " solve --scene " + building + " --json --cache-dir " + (dir / "cache").string();
  const std::string exported = " --export-vertices ";
  nlohmann::json first = statsOf(shell(solve + exported + (dir / "first.csv").string()));
  EXPECT_EQ(first["mesh"], "hierarchical, clustered");
  const std::string saved = first["formfactor_cache"];
  ASSERT_EQ(saved.rfind("saved " + (dir / "cache" / "links-").string(), 0), 0u) << saved;
  const fs::path file = saved.substr(6, saved.find(" (") - 6);
  ASSERT_TRUE(fs::is_regular_file(file)) << file;
  EXPECT_EQ(first["link_cache_bytes"].get<std::uintmax_t>(), fs::file_size(file));
  EXPECT_GT(first["links_estimated"].get<long>(), 0);

  // The final gather's visibility values beside the links.
  const std::string gatherSaved = first["gather_cache"];
  EXPECT_EQ(gatherSaved.rfind("saved " + file.string().substr(0, file.string().size() - 4) + ".lhv (", 0), 0u) << gatherSaved;
  EXPECT_GT(first["gather_rays_per_vertex"].get<double>(), 0);

  nlohmann::json second = statsOf(shell(solve + exported + (dir / "second.csv").string()));
  EXPECT_EQ(second["formfactor_cache"].get<std::string>().rfind("loaded " + file.string() + " (", 0), 0u) << second["formfactor_cache"];
  EXPECT_EQ(second["gather_cache"].get<std::string>().rfind("loaded ", 0), 0u) << second["gather_cache"];
  // The same radiosity and visibility values as the first run's gather: its irradiance is read.
  EXPECT_EQ(second["gather_irradiance_cache"].get<std::string>().rfind("loaded ", 0), 0u) << second["gather_irradiance_cache"];
  EXPECT_EQ(second["gather_irradiance_reads"].get<long>(), 1);
  EXPECT_EQ(second["gather_rays_per_vertex"].get<double>(), 0.0);
  // What the user gets: the same vertex file, byte for byte, and the same as without a cache.
  EXPECT_TRUE(testing::readBytes(dir / "first.csv") == testing::readBytes(dir / "second.csv"));
  ASSERT_EQ(shell(cli + " solve --scene " + building + " --no-cache" + exported + (dir / "uncached.csv").string()).exitCode, 0);
  EXPECT_TRUE(testing::readBytes(dir / "first.csv") == testing::readBytes(dir / "uncached.csv"));
  EXPECT_EQ(second["links_estimated"].get<long>(), 0);
  EXPECT_EQ(second["visibility_rays"].get<long>(), 0);
  EXPECT_EQ(second["links"], first["links"]);
  EXPECT_EQ(second["solution_hash"], first["solution_hash"]);
  EXPECT_EQ(second["absorbed_watts"].get<double>(), first["absorbed_watts"].get<double>());

  // --method hierarchical takes --cache-dir too; --no-cache still refuses it.
  nlohmann::json named = statsOf(shell(solve + " --method hierarchical"));
  EXPECT_EQ(named["formfactor_cache"].get<std::string>().rfind("loaded ", 0), 0u) << named["formfactor_cache"];
  CommandResult both = shell(solve + " --no-cache");
  EXPECT_EQ(both.exitCode, 2);
  EXPECT_TRUE(contains(both.output, "--cache-dir has no effect: --no-cache turns the cache off")) << both.output;
}

TEST(LinkCacheCliTest, TheDefaultDirectoryIsUsedAndNoCacheWritesNothing) {
  const fs::path dir = testing::scratchDirectory("link-cache-cli", "default");
  const fs::path xdg = dir / "xdg", home = dir / "home";
  fs::create_directories(home);
  const std::string environment = "XDG_CACHE_HOME=" + xdg.string() + " HOME=" + home.string() + " ";
  const std::string render = environment + LAMBERT_CLI_PATH + " render --scene cornell --link-error 1e-3 --width 32 --height 32 --json -o ";

  nlohmann::json off = statsOf(shell(render + (dir / "off.png").string() + " --no-cache"));
  EXPECT_EQ(off["mesh"], "hierarchical, clustered");
  EXPECT_EQ(off["formfactor_cache"], "off");
  EXPECT_FALSE(off.contains("link_cache_bytes"));
  EXPECT_EQ(filesIn(xdg), 0u);
  EXPECT_EQ(filesIn(home), 0u);

  nlohmann::json cached = statsOf(shell(render + (dir / "cached.png").string()));
  EXPECT_EQ(cached["formfactor_cache"].get<std::string>().rfind("saved " + (xdg / "lambert" / "links-").string(), 0), 0u)
      << cached["formfactor_cache"];
  // The links alone: a picture gathers at the vertices it shows, and only a gather at every
  // vertex (an export) keeps its visibility values and irradiance.
  EXPECT_EQ(filesIn(xdg), 1u);
  EXPECT_EQ(filesIn(home), 0u);
  nlohmann::json exported = statsOf(shell(render + (dir / "exported.png").string() + " --export " + (dir / "exported.glb").string()));
  EXPECT_EQ(exported["formfactor_cache"].get<std::string>().rfind("loaded ", 0), 0u) << exported["formfactor_cache"];
  EXPECT_EQ(filesIn(xdg), 3u);  // the links and the final gather's visibility values and irradiance
  EXPECT_TRUE(testing::readBytes(dir / "off.png") == testing::readBytes(dir / "exported.png"));
  // The image does not depend on where the links came from.
  nlohmann::json loaded = statsOf(shell(render + (dir / "loaded.png").string()));
  EXPECT_EQ(loaded["formfactor_cache"].get<std::string>().rfind("loaded ", 0), 0u) << loaded["formfactor_cache"];
  EXPECT_TRUE(testing::readBytes(dir / "off.png") == testing::readBytes(dir / "cached.png"));
  EXPECT_TRUE(testing::readBytes(dir / "off.png") == testing::readBytes(dir / "loaded.png"));
}

}  // namespace
}  // namespace lambert
