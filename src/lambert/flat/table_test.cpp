// The master form-factor table's file: cells named by stable addresses, so a later run, whose
// cells have other ids, finds every pair an earlier run computed; and the same guarantees as the
// uniform cache (atomic writes, damaged or foreign files rejected with a warning, recomputed).
#include "lambert/flat/table.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "lambert/flat/form_factor_cache.h"
#include "lambert/core/cache_file.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/flat/quadtree.h"
#include "tests/support/scenes.h"

#include "tests/support/engines.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::hasTemporaryFiles;
using testing::contains;
using testing::quietFormFactorOptions;

constexpr std::size_t kHeaderBytes = 32, kEntryBytes = 20, kChecksumBytes = 8;

fs::path scratch(const std::string& name) { return testing::scratchDirectory("formfactor-table", name); }

using testing::readBytes;
using testing::writeBytes;

std::uint64_t loadLe64(const std::vector<char>& bytes, std::size_t offset) {
  std::uint64_t v = 0;
  for (int k = 7; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(bytes[offset + k]);
  return v;
}


bool bitIdentical(const FormFactorMatrix& a, const FormFactorMatrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(float)) == 0;
}


const QuadtreeOptions kQuadtree{0.5, 2};  // four level-0 cells per face of the unit cube

// An adaptive mesh of the unit cube with its master table, as AdaptiveMethod sets them up.
// Heap-allocated and never moved: the table refers to the mesh.
struct Cells {
  AdaptiveMesh mesh;
  Mesh base;
  std::unique_ptr<RayCaster> caster;
  std::unique_ptr<FormFactorTable> table;

  explicit Cells(AdaptiveMesh built) : mesh(std::move(built)), base(mesh.activeMesh()) {
    caster = makeEmbreeRayCaster(base);
    table = std::make_unique<FormFactorTable>(mesh.nodeMesh(), *caster, quietFormFactorOptions(),
                                              [this](std::uint32_t id) { return mesh.address(id); });
  }

  std::uint32_t idOf(std::uint64_t address) const {
    for (std::uint32_t id = 0; id < mesh.numNodes(); ++id)
      if (mesh.address(id) == address) return id;
    ADD_FAILURE() << "no cell at address " << address;
    return 0;
  }
  // Splits the active cell at each address in turn.
  void refine(const std::vector<std::uint64_t>& addresses) {
    for (std::uint64_t a : addresses) EXPECT_TRUE(mesh.refine(idOf(a)));
  }
  // The ids of the cells at these addresses, in the same order.
  std::vector<std::uint32_t> ids(const std::vector<std::uint64_t>& addresses) const {
    std::vector<std::uint32_t> result;
    for (std::uint64_t a : addresses) result.push_back(idOf(a));
    return result;
  }
  std::vector<std::uint64_t> activeAddresses() const {
    std::vector<std::uint64_t> result;
    for (std::uint32_t id : mesh.activeNodes()) result.push_back(mesh.address(id));
    return result;
  }
};

std::unique_ptr<Cells> cube(const std::vector<std::uint64_t>& refineOrder = {}) {
  Result<AdaptiveMesh> mesh = AdaptiveMesh::build(testing::closedCube(1), kQuadtree);
  EXPECT_TRUE(mesh.ok()) << mesh.error().message;
  auto cells = std::make_unique<Cells>(std::move(*mesh));
  cells->refine(refineOrder);
  return cells;
}

std::uint64_t at(std::uint32_t surface, int level, std::uint32_t i, std::uint32_t j) {
  return AdaptiveMesh::packAddress(surface, level, i, j);
}

// Two refinement orders that reach the same cells with different ids: in the first, face 0's
// cell (0, 0) is split before face 3's cell (1, 1); in the second, after it. Then one child of
// the first split is split again.
const std::vector<std::uint64_t> kOrderA = {at(0, 0, 0, 0), at(3, 0, 1, 1), at(0, 1, 1, 0)};
const std::vector<std::uint64_t> kOrderB = {at(3, 0, 1, 1), at(0, 0, 0, 0), at(0, 1, 1, 0)};

std::size_t pairsOf(std::size_t n) { return n * (n - 1) / 2; }

// ---------------------------------------------------------------------------------------------
// Addresses

TEST(FormFactorTableAddressTest, PackedAsDocumented) {
  EXPECT_EQ(AdaptiveMesh::packAddress(0, 0, 0, 0), 0u);
  EXPECT_EQ(AdaptiveMesh::packAddress(3, 2, 5, 7), (3ULL << 44) | (2ULL << 40) | (7ULL << 20) | 5ULL);
  const std::uint32_t maxCell = (1u << 20) - 1, maxSurface = (1u << 20) - 1;
  EXPECT_EQ(AdaptiveMesh::packAddress(maxSurface, 15, maxCell, maxCell), ~0ULL);
  // Ordered by surface, then level, row, column.
  EXPECT_LT(at(0, 3, maxCell, maxCell), at(1, 0, 0, 0));
  EXPECT_LT(at(1, 0, maxCell, maxCell), at(1, 1, 0, 0));
  EXPECT_LT(at(1, 1, maxCell, 0), at(1, 1, 0, 1));
}

TEST(FormFactorTableAddressTest, AddressesAreUniqueAndStableAcrossRefinementOrders) {
  auto a = cube(kOrderA), b = cube(kOrderB);
  ASSERT_EQ(a->mesh.numNodes(), b->mesh.numNodes());
  std::set<std::uint64_t> seen;
  int idsDiffer = 0;
  for (std::uint32_t id = 0; id < a->mesh.numNodes(); ++id) {
    const QuadNode& n = a->mesh.node(id);
    const std::uint64_t address = a->mesh.address(id);
    EXPECT_EQ(address, at(n.surface, n.level, n.i, n.j));
    EXPECT_TRUE(seen.insert(address).second) << "address " << address << " repeated";
    const std::uint32_t other = b->idOf(address);
    idsDiffer += other != id;
    // The same cell, wherever its id puts it.
    EXPECT_DOUBLE_EQ(a->mesh.nodeMesh().patches[id].area, b->mesh.nodeMesh().patches[other].area);
    EXPECT_EQ(a->mesh.nodeMesh().patches[id].centroid, b->mesh.nodeMesh().patches[other].centroid);
  }
  EXPECT_GT(idsDiffer, 0);
}

TEST(FormFactorTableAddressTest, GridsTooLargeToAddressAreRejected) {
  // More cells along an edge at the deepest level than an address's 2^20 columns: rejected before
  // anything is allocated for the grid.
  for (QuadtreeOptions options : {QuadtreeOptions{1e-7, 0}, QuadtreeOptions{1.0 / 4097, 8}, QuadtreeOptions{1.0 / 1048577, 0}}) {
    Result<AdaptiveMesh> mesh = AdaptiveMesh::build(testing::closedCube(1), options);
    ASSERT_FALSE(mesh.ok()) << options.baseEdgeLength << " " << options.maxLevel;
    EXPECT_TRUE(contains(mesh.error().message, "cell address")) << mesh.error().message;
  }
}

// ---------------------------------------------------------------------------------------------
// Keys and paths

TEST(FormFactorTableKeyTest, ChangesWithQuadtreeOptionsFormFactorOptionsAndGeometry) {
  const Scene scene = testing::closedCube(1);
  const FormFactorOptions options = quietFormFactorOptions();
  const std::uint64_t key = formFactorTableKey(scene, kQuadtree, options);
  EXPECT_EQ(formFactorTableKey(testing::closedCube(1), kQuadtree, quietFormFactorOptions()), key);

  std::set<std::uint64_t> keys = {key};
  auto expectNew = [&](std::uint64_t k, const char* what) { EXPECT_TRUE(keys.insert(k).second) << what; };
  expectNew(formFactorTableKey(scene, {0.25, 2}, options), "base edge length");
  expectNew(formFactorTableKey(scene, {std::nextafter(0.5, 1.0), 2}, options), "base edge length, one ulp");
  expectNew(formFactorTableKey(scene, {0.5, 3}, options), "deepest level");
  FormFactorOptions o = options;
  o.seed = 2;
  expectNew(formFactorTableKey(scene, kQuadtree, o), "seed");
  o = options;
  o.samplePairs = 32;
  expectNew(formFactorTableKey(scene, kQuadtree, o), "sample pairs");
  o = options;
  o.nearFieldBoost = 1;
  expectNew(formFactorTableKey(scene, kQuadtree, o), "near-field boost");
  o = options;
  o.method = FormFactorMethod::PointToPoint;
  expectNew(formFactorTableKey(scene, kQuadtree, o), "method");
  Scene moved = scene;
  moved.surfaces[2].vertices[1].y = std::nextafter(moved.surfaces[2].vertices[1].y, 2.0);
  expectNew(formFactorTableKey(moved, kQuadtree, options), "a vertex, one ulp");
  Scene swapped = scene;
  std::swap(swapped.surfaces[0], swapped.surfaces[1]);
  expectNew(formFactorTableKey(swapped, kQuadtree, options), "surface order (part of every address)");
  Scene fewer = scene;
  fewer.surfaces.pop_back();
  expectNew(formFactorTableKey(fewer, kQuadtree, options), "surface count");
  // Nor is it the uniform cache's key for anything.
  EXPECT_NE(formFactorCacheKey(subdivideScene(scene, 24), options), key);

  // What F does not depend on leaves the key alone.
  o = options;
  o.showProgress = true;
  EXPECT_EQ(formFactorTableKey(scene, kQuadtree, o), key);
  Scene repainted = scene;
  repainted.surfaces[0].emittedRadiance = {1, 1, 1};
  repainted.materials[0].albedo = Rgb::gray(0.9);
  repainted.name = "renamed";
  EXPECT_EQ(formFactorTableKey(repainted, kQuadtree, options), key);
}

TEST(FormFactorTableKeyTest, PathNamesTheKeyInSixteenHexDigits) {
  EXPECT_EQ(formFactorTablePath("/tmp/cache", 0xff), "/tmp/cache/formfactor-table-00000000000000ff.lft");
  EXPECT_EQ(formFactorTablePath("c", 0x0123456789abcdefULL), "c/formfactor-table-0123456789abcdef.lft");
}

// ---------------------------------------------------------------------------------------------
// save / load

// A table that has seen two active sets (the level-0 cells, then the refined mesh), saved.
struct SavedTable {
  std::unique_ptr<Cells> cells;
  std::vector<std::uint64_t> coarse, refined;  // the two active sets, by address
  FormFactorMatrix coarseF, refinedF;
  std::string path;
  std::uint64_t key = 0;
};

SavedTable savedTable(const std::string& test) {
  SavedTable s;
  s.cells = cube();
  s.coarse = s.cells->activeAddresses();
  s.coarseF = s.cells->table->matrix(s.cells->ids(s.coarse));
  s.cells->refine(kOrderA);
  s.refined = s.cells->activeAddresses();
  s.refinedF = s.cells->table->matrix(s.cells->ids(s.refined));
  s.key = formFactorTableKey(testing::closedCube(1), kQuadtree, quietFormFactorOptions());
  s.path = formFactorTablePath(scratch(test).string(), s.key);
  Result<std::size_t> saved = s.cells->table->save(s.path, s.key);
  EXPECT_TRUE(saved.ok()) << saved.error().message;
  if (saved) {
    EXPECT_EQ(*saved, s.cells->table->pairsStored());
  }
  return s;
}

TEST(FormFactorTableFileTest, RoundTripGivesIdenticalMatricesWhenIdsDiffer) {
  SavedTable saved = savedTable("roundtrip");
  const Cells& a = *saved.cells;
  EXPECT_EQ(a.table->pairsEstimated(), a.table->pairsStored());
  EXPECT_GT(saved.refinedF.maxCoeff(), 0.0f);

  auto b = cube(kOrderB);
  // The point of addresses: the same cells have other ids, and for some pairs the order of the
  // ids is the other way round, so a value keyed or directed by id would be read backwards.
  int flipped = 0;
  for (std::size_t x = 0; x < saved.refined.size(); ++x)
    for (std::size_t y = x + 1; y < saved.refined.size(); ++y)
      flipped += (a.idOf(saved.refined[x]) < a.idOf(saved.refined[y])) != (b->idOf(saved.refined[x]) < b->idOf(saved.refined[y]));
  ASSERT_GT(flipped, 0);

  Result<std::size_t> loaded = b->table->load(saved.path, saved.key);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(*loaded, a.table->pairsStored());
  // The same active sets, in the same order of cells, give bit-identical matrices without one
  // pair estimated.
  EXPECT_TRUE(bitIdentical(b->table->matrix(b->ids(saved.refined)), saved.refinedF));
  EXPECT_TRUE(bitIdentical(b->table->matrix(b->ids(saved.coarse)), saved.coarseF));
  EXPECT_EQ(b->table->pairsEstimated(), 0u);
  EXPECT_EQ(b->table->pairsLoaded(), a.table->pairsStored());
  EXPECT_EQ(b->table->pairsReused(), pairsOf(saved.refined.size()) + pairsOf(saved.coarse.size()) - a.table->pairsStored());
  // Once taken from the file, a pair is in the table like any other.
  const std::uint64_t reused = b->table->pairsReused();
  b->table->matrix(b->ids(saved.refined));
  EXPECT_EQ(b->table->pairsLoaded(), a.table->pairsStored());
  EXPECT_EQ(b->table->pairsReused(), reused + pairsOf(saved.refined.size()));
}

// The memory check before an active set's matrix counts the matrix and the pairs the table must
// add; once they are stored, only the matrix.
TEST(FormFactorTableMemoryTest, AssemblyBytesCountTheMatrixAndTheNewPairs) {
  auto cells = cube();
  const std::vector<std::uint32_t> ids = cells->ids(cells->activeAddresses());
  const double n = static_cast<double>(ids.size()), matrixBytes = n * n * 4;
  const double fresh = cells->table->assemblyBytes(ids.size());
  // 16 bytes in the working list and 40 in the hash table per new pair.
  EXPECT_EQ(fresh, matrixBytes + static_cast<double>(pairsOf(ids.size())) * (16 + 40));
  cells->table->matrix(ids);
  EXPECT_EQ(cells->table->assemblyBytes(ids.size()), matrixBytes);
}

TEST(FormFactorTableFileTest, NewPairsAreEstimatedAndUnusedLoadedPairsAreKept) {
  SavedTable saved = savedTable("union");
  const std::set<std::uint64_t> known(saved.coarse.begin(), saved.coarse.end());
  std::set<std::uint64_t> everActive = known;
  everActive.insert(saved.refined.begin(), saved.refined.end());

  // Another run splits a cell the first never did, and never shows the level-0 set again.
  auto b = cube(kOrderB);
  ASSERT_TRUE(b->table->load(saved.path, saved.key).ok());
  b->refine({at(5, 0, 0, 1)});
  const std::vector<std::uint64_t> active = b->activeAddresses();
  const FormFactorMatrix F = b->table->matrix(b->ids(active));
  std::size_t newCells = 0;
  for (std::uint64_t address : active) newCells += !everActive.count(address);
  ASSERT_EQ(newCells, 4u);
  const std::size_t newPairs = pairsOf(active.size()) - pairsOf(active.size() - newCells);
  EXPECT_EQ(b->table->pairsEstimated(), newPairs);
  EXPECT_EQ(b->table->pairsLoaded(), pairsOf(active.size()) - newPairs);

  // Saved again: the file's pairs this run never used are kept, the new ones added.
  const std::string path = formFactorTablePath(scratch("union-again").string(), saved.key);
  Result<std::size_t> resaved = b->table->save(path, saved.key);
  ASSERT_TRUE(resaved.ok()) << resaved.error().message;
  EXPECT_EQ(*resaved, saved.cells->table->pairsStored() + newPairs);

  // A third run, in the first order, finds all of both runs' pairs.
  auto c = cube(kOrderA);
  ASSERT_TRUE(c->table->load(path, saved.key).ok());
  EXPECT_TRUE(bitIdentical(c->table->matrix(c->ids(saved.coarse)), saved.coarseF));
  EXPECT_TRUE(bitIdentical(c->table->matrix(c->ids(saved.refined)), saved.refinedF));
  c->refine({at(5, 0, 0, 1)});
  EXPECT_TRUE(bitIdentical(c->table->matrix(c->ids(active)), F));
  EXPECT_EQ(c->table->pairsEstimated(), 0u);
}

TEST(FormFactorTableFileTest, FileLayoutIsAsDocumented) {
  SavedTable saved = savedTable("layout");
  const std::vector<char> bytes = readBytes(saved.path);
  const std::size_t m = saved.cells->table->pairsStored();
  ASSERT_EQ(bytes.size(), kHeaderBytes + kEntryBytes * m + kChecksumBytes);
  EXPECT_EQ(std::string(bytes.data(), 8), std::string("LMBRTFT\0", 8));
  EXPECT_EQ(loadLe64(bytes, 8), 1u);  // version 1, reserved 0
  EXPECT_EQ(loadLe64(bytes, 16), saved.key);
  EXPECT_EQ(loadLe64(bytes, 24), m);
  // Entries ascend by (p, q) with p < q, and F runs from p to q: checked against the matrix.
  std::map<std::uint64_t, std::size_t> position;
  for (std::size_t k = 0; k < saved.refined.size(); ++k) position[saved.refined[k]] = k;
  std::size_t checked = 0;
  std::uint64_t lastP = 0, lastQ = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t offset = kHeaderBytes + k * kEntryBytes;
    const std::uint64_t p = loadLe64(bytes, offset), q = loadLe64(bytes, offset + 8);
    float f;
    std::memcpy(&f, bytes.data() + offset + 16, 4);
    EXPECT_LT(p, q);
    if (k > 0) {
      EXPECT_TRUE(p > lastP || (p == lastP && q > lastQ)) << "entry " << k;
    }
    lastP = p;
    lastQ = q;
    if (position.count(p) && position.count(q)) {
      EXPECT_EQ(f, saved.refinedF(static_cast<Eigen::Index>(position[p]), static_cast<Eigen::Index>(position[q])));
      ++checked;
    }
  }
  EXPECT_EQ(checked, pairsOf(saved.refined.size()));
  cachefile::Xxh64 checksum;
  checksum.update(bytes.data(), bytes.size() - kChecksumBytes);
  EXPECT_EQ(loadLe64(bytes, bytes.size() - kChecksumBytes), checksum.digest());
  EXPECT_FALSE(hasTemporaryFiles(fs::path(saved.path).parent_path()));
}

// A table that failed to load is as it was: the pairs are estimated, none loaded.
void expectUnloaded(const SavedTable& saved, Cells& cells) {
  EXPECT_TRUE(bitIdentical(cells.table->matrix(cells.ids(saved.coarse)), saved.coarseF));
  EXPECT_EQ(cells.table->pairsLoaded(), 0u);
  EXPECT_EQ(cells.table->pairsEstimated(), pairsOf(saved.coarse.size()));
}

TEST(FormFactorTableFileTest, TruncatedDamagedAndForeignFilesAreRejected) {
  SavedTable saved = savedTable("rejected");
  const std::vector<char> good = readBytes(saved.path);
  struct Case {
    std::string what;
    std::vector<char> bytes;
    std::uint64_t key;
    std::string why;
  };
  std::vector<Case> cases;
  for (std::size_t length : {std::size_t{0}, std::size_t{20}, kHeaderBytes, kHeaderBytes + 7, good.size() / 2,
                             good.size() - kChecksumBytes, good.size() - 1})
    cases.push_back({"cut at " + std::to_string(length),
                     std::vector<char>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length)), saved.key, "truncated"});
  std::vector<char> flipped = good;
  flipped[kHeaderBytes + kEntryBytes * 3 + 17] ^= 0x04;  // one bit of a form factor
  cases.push_back({"flipped value bit", flipped, saved.key, "checksum"});
  flipped = good;
  flipped[kHeaderBytes + kEntryBytes * 5 + 2] ^= 0x01;  // one bit of an address
  cases.push_back({"flipped address bit", flipped, saved.key, "checksum"});
  cases.push_back({"another key", good, saved.key + 1, "key"});
  std::vector<char> extended = good;
  extended.push_back(0);
  cases.push_back({"trailing byte", extended, saved.key, "trailing"});
  std::vector<char> huge = good;
  for (int k = 0; k < 8; ++k) huge[24 + k] = k == 7 ? 0x7f : static_cast<char>(0xff);  // 2^63 − 1 pairs
  cases.push_back({"absurd pair count", huge, saved.key, "pairs"});
  // The uniform cache's file at this path is not a table.
  const std::string lff = (fs::path(saved.path).parent_path() / "matrix.lff").string();
  ASSERT_TRUE(saveFormFactors(lff, saved.key, FormFactorMatrix::Zero(2, 2)).ok());
  cases.push_back({"a matrix cache file", readBytes(lff), saved.key, "magic"});

  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    writeBytes(saved.path, c.bytes);
    auto cells = cube();
    Result<std::size_t> loaded = cells->table->load(saved.path, c.key);
    ASSERT_FALSE(loaded.ok());
    EXPECT_TRUE(contains(loaded.error().message, saved.path)) << loaded.error().message;
    EXPECT_TRUE(contains(loaded.error().message, c.why)) << loaded.error().message;
    expectUnloaded(saved, *cells);
  }
  auto cells = cube();
  Result<std::size_t> missing = cells->table->load(saved.path + ".missing", saved.key);
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(contains(missing.error().message, saved.path + ".missing")) << missing.error().message;
}

// Files whose checksum is right but whose pairs are not what save() writes: a buggy or foreign
// writer. Lookups rely on the order, and solutions on the values.
TEST(FormFactorTableFileTest, MisorderedOrInvalidPairsAreRejected) {
  SavedTable saved = savedTable("invalid");
  const std::vector<char> good = readBytes(saved.path);
  const std::vector<unsigned char> payload(good.begin() + kHeaderBytes, good.end() - kChecksumBytes);
  const std::size_t m = payload.size() / kEntryBytes;
  const cachefile::Format format{{'L', 'M', 'B', 'R', 'T', 'F', 'T', '\0'}, 1, "form-factor table file"};
  auto entry = [&](std::vector<unsigned char>& bytes, std::size_t k) { return bytes.data() + k * kEntryBytes; };

  std::vector<std::pair<std::string, std::vector<unsigned char>>> cases;
  std::vector<unsigned char> swapped = payload;  // two entries out of order
  std::swap_ranges(entry(swapped, 3), entry(swapped, 4), entry(swapped, 4));
  cases.push_back({"out of order", swapped});
  std::vector<unsigned char> repeated = payload;  // one pair twice
  std::memcpy(entry(repeated, 4), entry(repeated, 3), kEntryBytes);
  cases.push_back({"out of order or repeated", repeated});
  std::vector<unsigned char> backwards = payload;  // q before p
  std::swap_ranges(entry(backwards, 0), entry(backwards, 0) + 8, entry(backwards, 0) + 8);
  cases.push_back({"not in address order", backwards});
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -0.5f}) {
    std::vector<unsigned char> value = payload;
    std::memcpy(entry(value, m - 1) + 16, &bad, 4);
    cases.push_back({"form factor", value});
  }
  for (const auto& [why, bytes] : cases) {
    SCOPED_TRACE(why);
    ASSERT_TRUE(cachefile::writeFile(saved.path, format, saved.key, m, bytes).ok());
    auto cells = cube();
    Result<std::size_t> loaded = cells->table->load(saved.path, saved.key);
    ASSERT_FALSE(loaded.ok());
    EXPECT_TRUE(contains(loaded.error().message, saved.path)) << loaded.error().message;
    EXPECT_TRUE(contains(loaded.error().message, why)) << loaded.error().message;
    expectUnloaded(saved, *cells);
  }
  // The same pairs as written are accepted: the checks above are not just rejecting everything.
  ASSERT_TRUE(cachefile::writeFile(saved.path, format, saved.key, m, payload).ok());
  EXPECT_TRUE(cube()->table->load(saved.path, saved.key).ok());
}

TEST(FormFactorTableFileTest, EmptyTableRoundTrips) {
  auto cells = cube();
  const std::string path = (scratch("empty") / "t.lft").string();
  Result<std::size_t> saved = cells->table->save(path, 9);
  ASSERT_TRUE(saved.ok()) << saved.error().message;
  EXPECT_EQ(*saved, 0u);
  EXPECT_EQ(fs::file_size(path), kHeaderBytes + kChecksumBytes);
  Result<std::size_t> loaded = cube()->table->load(path, 9);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(*loaded, 0u);
}

}  // namespace
}  // namespace lambert

namespace lambert {
namespace {

TEST(RowContractionBoundTest, RowsAboveOneByNoiseAreKeptAtHighReflectance) {
  // At ρ = 0.95 a fixed bound of 0.95 on ρS would cut every row above 1 — the noise of estimated
  // rows around a true sum of 1 — and a closed room 11% dark (CIE 171 §5.8, engine/cie171_test).
  // The bound half way from ρ to 1 keeps rows up to 1 + (1 − ρ)/(2ρ) = 1.0263 as measured, scales
  // those above to 1, and every row it leaves has ρS < 1 (a contraction). Below ρ = 0.9 it is 0.95.
  EXPECT_DOUBLE_EQ(rowContractionBound(0.5), 0.95);
  EXPECT_DOUBLE_EQ(rowContractionBound(0.9), 0.95);
  EXPECT_DOUBLE_EQ(rowContractionBound(0.95), 0.975);
  EXPECT_DOUBLE_EQ(rowContractionBound(0.99), 0.995);
  FormFactorMatrix F = FormFactorMatrix::Zero(3, 3);
  F(0, 1) = 0.52f, F(0, 2) = 0.50f;  // 1.02: noise, kept
  F(1, 0) = 0.53f, F(1, 2) = 0.50f;  // 1.03: above 1.0263, scaled to 1
  F(2, 0) = 0.40f, F(2, 1) = 0.50f;  // 0.90: kept
  const std::vector<Rgb> albedo(3, Rgb::gray(0.95));
  EXPECT_EQ(boundRowSums(F, albedo), 1u);
  EXPECT_NEAR(F.row(0).sum(), 1.02, 1e-6);
  EXPECT_NEAR(F.row(1).sum(), 1.0, 1e-6);
  EXPECT_NEAR(F.row(2).sum(), 0.90, 1e-6);
  for (int i = 0; i < 3; ++i) EXPECT_LT(0.95 * F.row(i).sum(), 1.0) << "row " << i;
}

}  // namespace
}  // namespace lambert
