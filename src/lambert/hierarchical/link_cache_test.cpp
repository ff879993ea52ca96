// The hierarchical method with a cache directory: the first run saves its splits, links and warm
// start, a second loads them, refines nothing and solves to the same bits (and so do later
// frames with moved lights); every input the refinement reads changes the key; damaged,
// truncated, foreign and inconsistent files are warnings that never change the answer.
#include "lambert/hierarchical/link_cache.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "lambert/engine/radiosity.h"
#include "lambert/scene/builtin.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::contains;
using testing::hasTemporaryFiles;

fs::path scratch(const std::string& name) { return testing::scratchDirectory("link-cache", name); }

// The Cornell box with two spots: the spots split elements at their cone and shadow edges, the
// links split more, and two passes refine from a solve, so every part of a file is exercised.
RadiosityOptions options(const fs::path& dir) {
  RadiosityOptions o;
  o.meshing = MeshStrategy::Hierarchical;
  o.hierarchical.links.linkError = 1e-3;
  o.tolerance = 1e-6;
  o.cacheDirectory = dir.string();
  return o;
}

struct SolvedRun {
  std::unique_ptr<Radiosity> engine;
  std::vector<Rgb> radiosity, moved;  // after the first solve; after a second with a spot moved
  std::string stderrText;

  Stats::Value stat(const std::string& key) const {
    const Stats stats = engine->stats();
    const Stats::Entry* entry = stats.find(key);
    if (!entry) ADD_FAILURE() << "no stat " << key;
    return entry ? entry->value : Stats::Value{};
  }
  std::int64_t count(const std::string& key) const { return std::get<std::int64_t>(stat(key)); }
  std::string text(const std::string& key) const { return std::get<std::string>(stat(key)); }
  std::string cache() const { return text("formfactor_cache"); }
};

SolvedRun solve(const RadiosityOptions& o, const Scene& scene = cornellBoxWithSpots()) {
  SolvedRun run;
  ::testing::internal::CaptureStderr();
  auto created = Radiosity::create(scene, o);
  if (created) {
    run.engine = std::move(*created);
    EXPECT_TRUE(run.engine->solve().ok());
    run.radiosity = run.engine->solution().radiosity();
    std::vector<Light> lights = run.engine->lights();
    lights.at(0).position += Vec3{30, 0, -20};
    run.engine->setLights(lights);
    EXPECT_TRUE(run.engine->solve().ok());
    run.moved = run.engine->solution().radiosity();
  }
  run.stderrText = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(created.ok()) << created.error().message;
  return run;
}

std::string pathFor(const RadiosityOptions& o, const Scene& scene = cornellBoxWithSpots()) {
  return linkCachePath(o.cacheDirectory, linkCacheKey(scene, scene.lights, o, SolveBudget{}));
}

std::string gatherPathFor(const RadiosityOptions& o, const Scene& scene = cornellBoxWithSpots()) {
  return gatherVisibilityPath(o.cacheDirectory, linkCacheKey(scene, scene.lights, o, SolveBudget{}));
}

std::string irradiancePathFor(const RadiosityOptions& o, const Scene& scene = cornellBoxWithSpots()) {
  return gatherIrradiancePath(o.cacheDirectory, linkCacheKey(scene, scene.lights, o, SolveBudget{}));
}

// A solve and its final gather (the vertex radiosity).
struct GatheredRun {
  std::unique_ptr<Radiosity> engine;
  std::vector<Rgb> vertices;
  std::string stderrText;
  std::string text(const std::string& key) const { return std::get<std::string>(engine->stats().find(key)->value); }
  std::int64_t count(const std::string& key) const { return std::get<std::int64_t>(engine->stats().find(key)->value); }
  double number(const std::string& key) const { return std::get<double>(engine->stats().find(key)->value); }
};

GatheredRun gather(const RadiosityOptions& o) {
  GatheredRun run;
  ::testing::internal::CaptureStderr();
  auto created = Radiosity::create(cornellBoxWithSpots(), o);
  if (created) {
    run.engine = std::move(*created);
    EXPECT_TRUE(run.engine->solve().ok());
    run.vertices = run.engine->solution().vertexValues(VertexQuantity::Radiosity);
  }
  run.stderrText = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(created.ok()) << created.error().message;
  return run;
}

// The final gather's visibility values are saved beside the links after the first gather and read
// by the next process's: it casts no gather rays, and its vertex values are the same bits as the
// first run's and as a run without any cache. The values depend on geometry alone: with the
// lights moved after the first solve (over the same links, so the same file), the gather asks
// for other values too, casts those, and still matches an uncached run exactly.
TEST(LinkCacheTest, GatherVisibilityIsReadBackAndGivesTheSameBits) {
  const fs::path dir = scratch("gather") / "cache";
  RadiosityOptions off = options(dir);
  off.cacheDirectory.clear();
  const GatheredRun uncached = gather(off);
  EXPECT_EQ(uncached.text("formfactor_cache"), "off");
  EXPECT_EQ(uncached.engine->stats().find("gather_cache"), nullptr);
  EXPECT_GT(uncached.number("gather_rays_per_vertex"), 0);

  const GatheredRun first = gather(options(dir));
  EXPECT_TRUE(first.stderrText.empty()) << first.stderrText;
  const std::string path = gatherPathFor(options(dir));
  EXPECT_EQ(first.text("gather_cache").rfind("saved " + path + " (", 0), 0u) << first.text("gather_cache");
  ASSERT_TRUE(fs::is_regular_file(path));
  EXPECT_EQ(first.count("gather_cache_bytes"), static_cast<std::int64_t>(fs::file_size(path)));
  EXPECT_EQ(first.count("gather_visibility_cached"), 0);
  EXPECT_EQ(first.vertices, uncached.vertices);

  // Without the gather's irradiance file (which would answer the whole gather), the visibility
  // values are read and no ray is cast.
  ASSERT_TRUE(fs::remove(irradiancePathFor(options(dir))));
  const GatheredRun second = gather(options(dir));
  EXPECT_TRUE(second.stderrText.empty()) << second.stderrText;
  EXPECT_EQ(second.text("gather_cache").rfind("loaded " + path + " (", 0), 0u) << second.text("gather_cache");
  EXPECT_EQ(second.count("gather_irradiance_reads"), 0);
  EXPECT_GT(second.count("gather_visibility_cached"), 0);
  EXPECT_EQ(second.number("gather_rays_per_vertex"), 0.0);
  EXPECT_EQ(second.vertices, uncached.vertices);

  // The lights moved after the links were made (the dynamic-light path over the same links): the
  // file serves what it holds, the rest is cast, and the answer is an uncached run's.
  GatheredRun shifted;
  {
    shifted.engine = std::move(*Radiosity::create(cornellBoxWithSpots(), options(dir)));
    ASSERT_TRUE(shifted.engine->solve().ok());
    std::vector<Light> lights = shifted.engine->lights();
    lights.at(0).position += Vec3{30, 0, -20};
    shifted.engine->setLights(lights);
    ASSERT_TRUE(shifted.engine->solve().ok());
    shifted.vertices = shifted.engine->solution().vertexValues(VertexQuantity::Radiosity);
  }
  auto plain = std::move(*Radiosity::create(cornellBoxWithSpots(), off));
  ASSERT_TRUE(plain->solve().ok());
  std::vector<Light> lights = plain->lights();
  lights.at(0).position += Vec3{30, 0, -20};
  plain->setLights(lights);
  ASSERT_TRUE(plain->solve().ok());
  EXPECT_EQ(shifted.vertices, plain->solution().vertexValues(VertexQuantity::Radiosity));
  EXPECT_NE(shifted.vertices, uncached.vertices);
  EXPECT_GT(shifted.count("gather_visibility_cached"), 0);
  EXPECT_EQ(shifted.count("gather_irradiance_reads"), 0);
}

// Within one process, a vertex output asked again for the same solution (Python's
// vertex_radiance then vertex_values, a picture then its glb) reuses the last gather: the same
// bits, nothing gathered. After the lights move and the scene is solved again, the gather runs
// anew and matches an engine that went the same way without asking for vertices in between.
TEST(LinkCacheTest, ARepeatedVertexOutputReusesTheLastGather) {
  RadiosityOptions off = options(scratch("gather-reuse") / "cache");
  off.cacheDirectory.clear();
  const GatheredRun run = gather(off);
  EXPECT_EQ(run.count("gather_reused"), 0);
  EXPECT_GT(run.number("gather_sources_per_vertex"), 0.0);
  const std::vector<Rgb> irradiance = run.engine->solution().vertexValues(VertexQuantity::Irradiance);
  EXPECT_EQ(run.engine->solution().vertexValues(VertexQuantity::Radiosity), run.vertices);
  EXPECT_EQ(run.count("gather_reused"), 2);
  EXPECT_EQ(run.number("gather_sources_per_vertex"), 0.0);  // nothing gathered
  EXPECT_NE(irradiance, run.vertices);

  std::vector<Light> lights = run.engine->lights();
  lights.at(0).position += Vec3{30, 0, -20};
  run.engine->setLights(lights);
  ASSERT_TRUE(run.engine->solve().ok());
  const std::vector<Rgb> moved = run.engine->solution().vertexValues(VertexQuantity::Radiosity);
  EXPECT_EQ(run.count("gather_reused"), 2);
  EXPECT_NE(moved, run.vertices);
  auto fresh = std::move(*Radiosity::create(cornellBoxWithSpots(), off));
  ASSERT_TRUE(fresh->solve().ok());
  fresh->setLights(lights);
  ASSERT_TRUE(fresh->solve().ok());
  EXPECT_EQ(fresh->solution().vertexValues(VertexQuantity::Radiosity), moved);
}

// The gather's irradiance file answers a gather only for the input that made it: the same node
// radiosity and the same visibility values. A second run of the same solve reads it and writes the
// same vertex values as an uncached run; what it holds is what that run uses; a run whose
// radiosity differs under the same links (one refinement pass, so the tolerance is not in the
// key; or lights moved after the first solve) and one whose visibility values differ compute
// their own and match their uncached runs; a damaged file is a warning and is recomputed.
TEST(LinkCacheTest, GatherIrradianceIsReadOnlyForItsOwnInput) {
  const fs::path dir = scratch("gather-irradiance") / "cache";
  RadiosityOptions off = options(dir);
  off.cacheDirectory.clear();
  const GatheredRun uncached = gather(off);
  const std::string path = irradiancePathFor(options(dir));

  const GatheredRun first = gather(options(dir));
  EXPECT_TRUE(first.stderrText.empty()) << first.stderrText;
  EXPECT_EQ(first.text("gather_irradiance_cache").rfind("saved " + path + " (", 0), 0u) << first.text("gather_irradiance_cache");
  ASSERT_TRUE(fs::is_regular_file(path));
  EXPECT_EQ(first.count("gather_irradiance_cache_bytes"), static_cast<std::int64_t>(fs::file_size(path)));
  EXPECT_EQ(first.count("gather_irradiance_reads"), 0);
  const std::vector<char> good = testing::readBytes(path);

  const GatheredRun second = gather(options(dir));
  EXPECT_TRUE(second.stderrText.empty()) << second.stderrText;
  EXPECT_EQ(second.text("gather_irradiance_cache").rfind("loaded " + path + " (", 0), 0u) << second.text("gather_irradiance_cache");
  EXPECT_EQ(second.count("gather_irradiance_reads"), 1);
  EXPECT_EQ(second.number("gather_sources_per_vertex"), 0.0);  // nothing gathered
  EXPECT_EQ(second.vertices, uncached.vertices);
  EXPECT_EQ(testing::readBytes(path), good);  // read, not rewritten

  // What the file holds is what the gather returns: the same input digest over doubled values
  // makes every lit vertex brighter (the vertex radiosity is emission + ρ × (direct + gathered)).
  const std::uint64_t key = linkCacheKey(cornellBoxWithSpots(), cornellBoxWithSpots().lights, options(dir), SolveBudget{});
  const std::uint64_t numVertices = first.engine->solution().vertexMesh().numVertices();
  Result<CachedGatherIrradiance> loaded = loadGatherIrradiance(path, key, numVertices);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  CachedGatherIrradiance doubled = *loaded;
  for (Rgb& e : doubled.irradiance) e = e * 2.0;
  ASSERT_TRUE(saveGatherIrradiance(path, key, doubled).ok());
  const GatheredRun brighter = gather(options(dir));
  EXPECT_EQ(brighter.count("gather_irradiance_reads"), 1);
  double before = 0, after = 0;
  for (std::size_t v = 0; v < uncached.vertices.size(); ++v) {
    before += uncached.vertices[v].maxComponent();
    after += brighter.vertices[v].maxComponent();
  }
  EXPECT_GT(after, before * 1.05);

  // The same values under another input's digest: not read (no warning: it is another solve's),
  // computed, and the file replaced by this input's.
  CachedGatherIrradiance foreign = *loaded;
  foreign.inputDigest ^= 1;
  ASSERT_TRUE(saveGatherIrradiance(path, key, foreign).ok());
  const GatheredRun other = gather(options(dir));
  EXPECT_TRUE(other.stderrText.empty()) << other.stderrText;
  EXPECT_EQ(other.count("gather_irradiance_reads"), 0);
  EXPECT_GT(other.count("gather_visibility_cached"), 0);
  EXPECT_EQ(other.vertices, uncached.vertices);
  EXPECT_EQ(testing::readBytes(path), good);

  // One refinement pass: the tolerance of the one solve is not in the links' key, so a looser one
  // shares the links and the visibility values but gathers another radiosity.
  RadiosityOptions onePass = options(dir), onePassOff = off;
  onePass.hierarchical.refinePasses = onePassOff.hierarchical.refinePasses = 1;
  RadiosityOptions loose = onePass, looseOff = onePassOff;
  loose.tolerance = looseOff.tolerance = 1e-2;
  ASSERT_EQ(linkCacheKey(cornellBoxWithSpots(), cornellBoxWithSpots().lights, onePass, SolveBudget{}),
            linkCacheKey(cornellBoxWithSpots(), cornellBoxWithSpots().lights, loose, SolveBudget{}));
  const GatheredRun tight = gather(onePass);
  EXPECT_EQ(tight.vertices, gather(onePassOff).vertices);
  const GatheredRun looser = gather(loose);
  EXPECT_TRUE(looser.stderrText.empty()) << looser.stderrText;
  EXPECT_EQ(looser.count("gather_irradiance_reads"), 0);
  const std::vector<Rgb> looseUncached = gather(looseOff).vertices;
  EXPECT_EQ(looser.vertices, looseUncached);
  EXPECT_NE(looser.vertices, tight.vertices);
  const GatheredRun looserAgain = gather(loose);
  EXPECT_EQ(looserAgain.count("gather_irradiance_reads"), 1);
  EXPECT_EQ(looserAgain.vertices, looseUncached);

  // Checked before use: another mesh's vertex count, values that are not finite; damaged bytes.
  EXPECT_FALSE(loadGatherIrradiance(path, key, numVertices + 1).ok());
  CachedGatherIrradiance infinite = *loaded;
  infinite.irradiance[infinite.irradiance.size() / 2].g = INFINITY;
  ASSERT_TRUE(saveGatherIrradiance(path, key, infinite).ok());
  Result<CachedGatherIrradiance> refused = loadGatherIrradiance(path, key, numVertices);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "is not finite")) << refused.error().message;
  std::vector<char> flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  for (const auto& [name, bytes, says] : {std::tuple{"flipped", flipped, "checksum mismatch"},
                                          std::tuple{"truncated", std::vector<char>(good.begin(), good.end() - 9), "truncated"},
                                          std::tuple{"not finite", testing::readBytes(path), "is not finite"}}) {
    SCOPED_TRACE(name);
    testing::writeBytes(path, bytes);
    const GatheredRun again = gather(options(dir));
    EXPECT_TRUE(contains(again.stderrText, "lambert: warning: " + path + ": ")) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, says)) << again.stderrText;
    EXPECT_EQ(again.count("gather_irradiance_reads"), 0);
    EXPECT_EQ(again.vertices, uncached.vertices);
    EXPECT_EQ(testing::readBytes(path), good);
    EXPECT_FALSE(hasTemporaryFiles(dir));
  }
}

// The file's values are what the gather uses: a valid file (right key, checksum and indices)
// whose values are all 0 darkens the vertices that read them; a damaged one is a warning, the
// values are cast again, and the file is replaced by the one the first run wrote.
TEST(LinkCacheTest, GatherVisibilityIsUsedAndADamagedFileIsRecomputed) {
  const fs::path dir = scratch("gather-damaged") / "cache";
  const GatheredRun first = gather(options(dir));
  const std::string path = gatherPathFor(options(dir));
  const std::vector<char> good = testing::readBytes(path);
  ASSERT_GT(good.size(), 100u);
  const std::uint64_t key = linkCacheKey(cornellBoxWithSpots(), cornellBoxWithSpots().lights, options(dir), SolveBudget{});
  const std::uint64_t numVertices = first.engine->solution().vertexMesh().numVertices();
  const std::uint64_t numLinks = static_cast<std::uint64_t>(first.count("links"));
  const std::uint64_t numNodes = static_cast<std::uint64_t>(first.count("clusters") + first.count("elements"));
  Result<GatherVisibility> loaded = loadGatherVisibility(path, key, numVertices, numLinks, numNodes);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_GT(loaded->size(), 0u);
  ASSERT_TRUE(fs::remove(irradiancePathFor(options(dir))));  // which would answer the whole gather
  EXPECT_EQ(loaded->size(), static_cast<std::size_t>(gather(options(dir)).count("gather_visibility_cached")));

  GatherVisibility dark = *loaded;
  std::fill(dark.seen.begin(), dark.seen.end(), 0.0);
  ASSERT_TRUE(saveGatherVisibility(path, key, dark).ok());
  const GatheredRun darkened = gather(options(dir));
  EXPECT_TRUE(darkened.stderrText.empty()) << darkened.stderrText;
  double before = 0, after = 0;
  for (std::size_t v = 0; v < first.vertices.size(); ++v) {
    before += first.vertices[v].maxComponent();
    after += darkened.vertices[v].maxComponent();
  }
  EXPECT_LT(after, before * (1 - 1e-3));

  // Checked before use: another mesh's vertex count, a link or source beyond the solve's, an
  // order broken within a vertex, a negative value.
  EXPECT_FALSE(loadGatherVisibility(path, key, numVertices + 1, numLinks, numNodes).ok());
  auto refused = [&](auto change, const char* says) {
    GatherVisibility bad = *loaded;
    change(bad);
    ASSERT_TRUE(saveGatherVisibility(path, key, bad).ok());
    Result<GatherVisibility> r = loadGatherVisibility(path, key, numVertices, numLinks, numNodes);
    ASSERT_FALSE(r.ok()) << says;
    EXPECT_TRUE(contains(r.error().message, says)) << r.error().message;
  };
  refused([&](GatherVisibility& g) { g.link[g.size() / 2] = static_cast<std::uint32_t>(numLinks); }, "is not a valid visibility");
  refused([&](GatherVisibility& g) { g.source[0] = static_cast<std::uint32_t>(numNodes); }, "is not a valid visibility");
  refused([&](GatherVisibility& g) { g.seen.back() = -0.5; }, "is not a valid visibility");
  refused([&](GatherVisibility& g) {
    std::size_t v = 0;
    while (g.start[v + 1] - g.start[v] < 2) ++v;
    std::swap(g.link[g.start[v]], g.link[g.start[v] + 1]);
    std::swap(g.source[g.start[v]], g.source[g.start[v] + 1]);
  }, "is not a valid visibility");

  std::vector<char> flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  std::vector<char> foreign = good;
  foreign[16] ^= 0x01;  // the key
  for (const auto& [name, bytes, says] : {std::tuple{"flipped", flipped, "checksum mismatch"},
                                          std::tuple{"truncated", std::vector<char>(good.begin(), good.end() - 9), "truncated"},
                                          std::tuple{"another key", foreign, "key mismatch"}}) {
    SCOPED_TRACE(name);
    testing::writeBytes(path, bytes);
    const GatheredRun again = gather(options(dir));
    EXPECT_TRUE(contains(again.stderrText, "lambert: warning: " + path + ": ")) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, says)) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, "; recomputing\n")) << again.stderrText;
    EXPECT_EQ(again.vertices, first.vertices);
    EXPECT_GT(again.number("gather_rays_per_vertex"), 0);
    EXPECT_EQ(again.text("gather_cache").rfind("saved " + path, 0), 0u) << again.text("gather_cache");
    EXPECT_EQ(testing::readBytes(path), good);
    EXPECT_FALSE(hasTemporaryFiles(dir));
  }
}

TEST(LinkCacheTest, SecondRunLoadsTheLinksAndSolvesToTheSameBits) {
  const fs::path dir = scratch("hit") / "cache";
  const std::string path = pathFor(options(dir));
  SolvedRun first = solve(options(dir));
  EXPECT_TRUE(first.stderrText.empty()) << first.stderrText;
  EXPECT_EQ(first.cache().rfind("saved " + path + " (", 0), 0u) << first.cache();
  ASSERT_TRUE(fs::is_regular_file(path));
  EXPECT_EQ(first.count("link_cache_bytes"), static_cast<std::int64_t>(fs::file_size(path)));
  EXPECT_GT(first.count("links_estimated"), 0);
  EXPECT_GT(first.count("light_splits"), 0);
  EXPECT_GT(first.count("elements"), first.count("faces"));  // the refinement split elements

  SolvedRun second = solve(options(dir));
  EXPECT_TRUE(second.stderrText.empty()) << second.stderrText;
  EXPECT_EQ(second.cache().rfind("loaded " + path + " (", 0), 0u) << second.cache();
  EXPECT_EQ(second.count("links_estimated"), 0);
  EXPECT_EQ(second.count("visibility_rays"), 0);
  EXPECT_EQ(second.count("elements"), first.count("elements"));
  EXPECT_EQ(second.count("links"), first.count("links"));
  EXPECT_EQ(second.count("cluster_links"), first.count("cluster_links"));
  EXPECT_EQ(second.count("iterations"), first.count("iterations"));
  // Bitwise: the same links, elements and warm start give the same sweeps.
  EXPECT_EQ(second.radiosity, first.radiosity);
  EXPECT_EQ(second.text("solution_hash"), first.text("solution_hash"));
  // A light that moves afterwards re-solves over the loaded links as over the computed ones.
  EXPECT_EQ(second.moved, first.moved);
  EXPECT_NE(second.moved, second.radiosity);
  // And the vertex values (the final gather over the links) agree too.
  EXPECT_EQ(second.engine->solution().vertexValues(VertexQuantity::Radiosity),
            first.engine->solution().vertexValues(VertexQuantity::Radiosity));

  // Off: neither read nor written, and the same answer as the run that computed the file.
  RadiosityOptions off = options(dir);
  off.cacheDirectory.clear();
  SolvedRun uncached = solve(off);
  EXPECT_EQ(uncached.cache(), "off");
  EXPECT_EQ(uncached.radiosity, first.radiosity);
  // The links and the final gather's visibility values and irradiance beside them.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
  EXPECT_TRUE(fs::is_regular_file(gatherPathFor(options(dir))));
  EXPECT_TRUE(fs::is_regular_file(irradiancePathFor(options(dir))));
  EXPECT_FALSE(hasTemporaryFiles(dir));
}

TEST(LinkCacheTest, EveryInputTheRefinementReadsChangesTheKey) {
  const Scene scene = cornellBoxWithSpots();
  const RadiosityOptions base = options("unused");
  const std::uint64_t key = linkCacheKey(scene, scene.lights, base, SolveBudget{});
  // Unchanged inputs, and what the refinement does not read, keep it.
  EXPECT_EQ(linkCacheKey(cornellBoxWithSpots(), scene.lights, base, SolveBudget{}), key);
  {
    Scene renamed = scene;
    renamed.name = "other";
    renamed.surfaces[0].name = "renamed";
    renamed.camera.eye += Vec3{1, 2, 3};
    RadiosityOptions elsewhere = base;
    elsewhere.cacheDirectory = "elsewhere";
    elsewhere.hierarchical.links.showProgress = true;
    EXPECT_EQ(linkCacheKey(renamed, renamed.lights, elsewhere, SolveBudget{}), key);
  }
  int changes = 0;
  auto expectChanged = [&](const Scene& s, const std::vector<Light>& lights, const RadiosityOptions& o, const SolveBudget& b,
                           const char* what) {
    EXPECT_NE(linkCacheKey(s, lights, o, b), key) << what;
    ++changes;
  };
  auto withOptions = [&](auto change, const char* what) {
    RadiosityOptions o = base;
    change(o);
    expectChanged(scene, scene.lights, o, SolveBudget{}, what);
  };
  auto withScene = [&](auto change, const char* what) {
    Scene s = scene;
    change(s);
    expectChanged(s, s.lights, base, SolveBudget{}, what);
  };
  withOptions([](RadiosityOptions& o) { o.hierarchical.links.linkError *= 0.5; }, "link error");
  withOptions([](RadiosityOptions& o) { o.hierarchical.links.minElementArea = 1; }, "min area");
  withOptions([](RadiosityOptions& o) { o.hierarchical.links.visibilityRays = 16; }, "visibility rays");
  withOptions([](RadiosityOptions& o) { o.hierarchical.links.clusters = false; }, "clusters");
  withOptions([](RadiosityOptions& o) { o.hierarchical.links.seed = 2; }, "seed");
  withOptions([](RadiosityOptions& o) { o.hierarchical.refinePasses = 3; }, "refine passes");
  withOptions([](RadiosityOptions& o) { o.hierarchical.refineAtLights = false; }, "light-edge splits");
  withOptions([](RadiosityOptions& o) { o.solver = SolverKind::Jacobi; }, "solver between passes");
  withOptions([](RadiosityOptions& o) { o.tolerance = 1e-4; }, "tolerance between passes");
  withOptions([](RadiosityOptions& o) { o.directLight.samplesPerPatch = 4; }, "direct-light samples between passes");
  withScene([](Scene& s) { s.surfaces[2].vertices[0].y += 1e-9; }, "geometry moved");
  withScene([](Scene& s) { s.materials[0].albedo.g *= 0.9; }, "albedo");
  withScene([](Scene& s) { s.surfaces[0].emittedRadiance += Rgb{0, 0, 1e-3}; }, "emission");
  withScene([](Scene& s) { s.metresPerUnit *= 2; }, "scale");
  withScene([](Scene& s) { s.lights[1].position.x += 1e-6; }, "light moved");
  withScene([](Scene& s) { s.lights[0].intensity *= 2; }, "light intensity");
  withScene([](Scene& s) { s.lights[0].coneAngleDegrees += 1; }, "spot cone");
  withScene([](Scene& s) { s.lights.pop_back(); }, "light removed");
  expectChanged(scene, scene.lights, base, SolveBudget{0, 5, 0}, "sweep budget between passes");
  EXPECT_EQ(changes, 19);
  // With one pass no solve comes before the refinement: its settings and budget are not read.
  RadiosityOptions onePass = base;
  onePass.hierarchical.refinePasses = 1;
  RadiosityOptions onePassJacobi = onePass;
  onePassJacobi.solver = SolverKind::Jacobi;
  EXPECT_EQ(linkCacheKey(scene, scene.lights, onePassJacobi, SolveBudget{0, 5, 0}), linkCacheKey(scene, scene.lights, onePass, SolveBudget{}));
  // A time budget makes what the later passes refine depend on the clock: no file then.
  EXPECT_FALSE(linkCacheUsable(base, SolveBudget{0, 0, 10}));
  EXPECT_TRUE(linkCacheUsable(onePass, SolveBudget{0, 0, 10}));
  EXPECT_TRUE(linkCacheUsable(base, SolveBudget{0, 5, 0}));
}

TEST(LinkCacheTest, ChangedInputsMissAndMovedLightsBeforeTheFirstSolveToo) {
  const fs::path dir = scratch("miss");
  SolvedRun first = solve(options(dir));
  RadiosityOptions finer = options(dir);
  finer.hierarchical.links.linkError = 5e-4;
  SolvedRun other = solve(finer);
  EXPECT_EQ(other.cache().rfind("saved ", 0), 0u) << other.cache();
  EXPECT_GT(other.count("links"), first.count("links"));

  Scene moved = cornellBoxWithSpots();
  moved.lights[0].position.x -= 40;
  SolvedRun lit = solve(options(dir), moved);
  EXPECT_EQ(lit.cache().rfind("saved " + pathFor(options(dir), moved), 0), 0u) << lit.cache();
  EXPECT_NE(lit.radiosity, first.radiosity);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
  // A time budget on the first solve neither reads nor writes.
  ::testing::internal::CaptureStderr();
  auto engine = Radiosity::create(cornellBoxWithSpots(), options(dir));
  ASSERT_TRUE(engine.ok());
  ASSERT_TRUE((*engine)->solve(SolveBudget{0, 0, 1e6}).ok());
  EXPECT_TRUE(::testing::internal::GetCapturedStderr().empty());
  const std::string status = std::get<std::string>((*engine)->stats().find("formfactor_cache")->value);
  EXPECT_EQ(status.rfind("off: a time budget", 0), 0u) << status;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
}

TEST(LinkCacheTest, DamagedFileWarnsRecomputesAndIsRepaired) {
  const fs::path dir = scratch("damaged");
  SolvedRun first = solve(options(dir));
  const std::string path = pathFor(options(dir));
  const std::vector<char> good = testing::readBytes(path);
  ASSERT_GT(good.size(), 1000u);

  struct Damage {
    const char* name;
    std::vector<char> bytes;
    const char* says;
  };
  std::vector<Damage> damages;
  damages.push_back({"truncated", std::vector<char>(good.begin(), good.begin() + static_cast<long>(good.size() * 2 / 3)), "truncated"});
  damages.push_back({"header only", std::vector<char>(good.begin(), good.begin() + 20), "truncated"});
  damages.push_back({"flipped", good, "checksum mismatch"});
  damages.back().bytes[good.size() / 2] ^= 0x10;
  damages.push_back({"extended", good, "trailing bytes"});
  damages.back().bytes.push_back(0);
  damages.push_back({"not ours", std::vector<char>(good.size(), 'x'), "bad magic"});
  for (const Damage& damage : damages) {
    SCOPED_TRACE(damage.name);
    testing::writeBytes(path, damage.bytes);
    SolvedRun again = solve(options(dir));
    EXPECT_TRUE(contains(again.stderrText, "lambert: warning: " + path + ": ")) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, damage.says)) << again.stderrText;
    EXPECT_TRUE(contains(again.stderrText, "; recomputing\n")) << again.stderrText;
    EXPECT_EQ(again.count("links_estimated"), first.count("links_estimated"));
    EXPECT_EQ(again.radiosity, first.radiosity);
    EXPECT_EQ(again.moved, first.moved);
    // Replaced by a valid file, the same bytes as the first run's.
    EXPECT_EQ(again.cache().rfind("saved " + path, 0), 0u) << again.cache();
    EXPECT_EQ(testing::readBytes(path), good);
    EXPECT_FALSE(hasTemporaryFiles(dir));
  }
}

TEST(LinkCacheTest, FileOfAnotherKeyAtThePathIsRecomputed) {
  const fs::path dir = scratch("foreign"), elsewhere = scratch("foreign-other");
  RadiosityOptions reseeded = options(elsewhere);
  reseeded.hierarchical.links.seed = 99;
  solve(reseeded);
  const std::string path = pathFor(options(dir));
  fs::create_directories(dir);
  fs::copy_file(pathFor(reseeded), path);
  SolvedRun again = solve(options(dir));
  EXPECT_TRUE(contains(again.stderrText, "lambert: warning: " + path + ": key mismatch")) << again.stderrText;
  EXPECT_EQ(again.cache().rfind("saved ", 0), 0u) << again.cache();
  EXPECT_TRUE(contains(solve(options(dir)).cache(), "loaded "));
}

// Files whose checksum is right but whose contents cannot be this hierarchy's (as a writer with a
// bug would leave them): every index is checked before it is used, never trusted.
TEST(LinkCacheTest, InconsistentContentsAreRefusedNotTrusted) {
  const fs::path dir = scratch("inconsistent");
  SolvedRun first = solve(options(dir));
  const std::string path = pathFor(options(dir));
  const std::uint64_t key = linkCacheKey(cornellBoxWithSpots(), cornellBoxWithSpots().lights, options(dir), SolveBudget{});
  Result<CachedRefinement> loaded = loadRefinement(path, key);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_FALSE(loaded->splits.empty());
  EXPECT_EQ(loaded->links->size(), static_cast<std::size_t>(first.count("links")));
  EXPECT_EQ(loaded->warmStart.size(), static_cast<std::size_t>(first.count("patches")));
  EXPECT_EQ(loaded->openFraction.size(), loaded->warmStart.size());
  // The Cornell box's blocks cover part of the floor: open fractions below 1 are kept.
  EXPECT_LT(*std::min_element(loaded->openFraction.begin(), loaded->openFraction.end()), 1.0);

  auto rewritten = [&](auto change) {
    CachedRefinement bad = *loaded;
    Links links = *bad.links;
    change(bad, links);
    bad.links = std::make_shared<Links>(std::move(links));
    EXPECT_TRUE(saveRefinement(path, key, bad).ok());
  };
  // A source beyond the nodes: refused by the loader.
  rewritten([](CachedRefinement& r, Links& l) { l.source[l.size() / 2] = static_cast<std::uint32_t>(r.numNodes + 5); });
  Result<CachedRefinement> refused = loadRefinement(path, key);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "is not a valid link")) << refused.error().message;
  // A split of the root cluster: refused by the replay, and the run recomputes from a fresh hierarchy.
  for (std::uint32_t node : {0u, static_cast<std::uint32_t>(loaded->numNodes + 1)}) {
    rewritten([&](CachedRefinement& r, Links&) { r.splits.front() = node; });
    SolvedRun again = solve(options(dir));
    EXPECT_TRUE(contains(again.stderrText, "does not apply to this hierarchy (")) << again.stderrText;
    EXPECT_EQ(again.radiosity, first.radiosity);
    EXPECT_EQ(again.cache().rfind("saved ", 0), 0u) << again.cache();
  }
  // A warm start for other leaves.
  rewritten([](CachedRefinement& r, Links&) {
    r.warmStart.pop_back();
    r.openFraction.pop_back();
  });
  SolvedRun again = solve(options(dir));
  EXPECT_TRUE(contains(again.stderrText, "leaves, the file's warm start")) << again.stderrText;
  EXPECT_EQ(again.radiosity, first.radiosity);
  // The header's payload size is what the checks start from: one the file does not back up.
  std::vector<char> bytes = testing::readBytes(path);
  bytes[24] = static_cast<char>(0xff), bytes[30] = static_cast<char>(0x7f);
  testing::writeBytes(path, bytes);
  Result<CachedRefinement> oversized = loadRefinement(path, key);
  ASSERT_FALSE(oversized.ok());
  EXPECT_TRUE(contains(oversized.error().message, "truncated")) << oversized.error().message;
}

TEST(LinkCacheTest, UnwritableDirectoryWarnsAndStillSolves) {
  const fs::path dir = scratch("readonly");
  testing::writeBytes(dir / "file", {'x'});
  const fs::path cache = dir / "file" / "cache";
  SolvedRun run = solve(options(cache));
  const std::string path = pathFor(options(cache));
  EXPECT_TRUE(contains(run.stderrText, "lambert: warning: " + path + ": ")) << run.stderrText;
  EXPECT_TRUE(contains(run.stderrText, "; links not cached")) << run.stderrText;
  EXPECT_EQ(run.cache().rfind("not saved: " + path, 0), 0u) << run.cache();
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  RadiosityOptions off = options(cache);
  off.cacheDirectory.clear();
  EXPECT_EQ(solve(off).radiosity, run.radiosity);
}

}  // namespace
}  // namespace lambert
