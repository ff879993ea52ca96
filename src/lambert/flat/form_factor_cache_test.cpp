#include "lambert/flat/form_factor_cache.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/builtin.h"

#include "tests/support/engines.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::hasTemporaryFiles;
using testing::contains;
using testing::quietFormFactorOptions;

constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kChecksumBytes = 8;

fs::path scratch(const std::string& name) { return testing::scratchDirectory("formfactor-cache", name); }

using testing::readBytes;
using testing::writeBytes;

void storeLe(std::vector<char>& bytes, std::size_t offset, std::uint64_t value, int size) {
  for (int k = 0; k < size; ++k) bytes[offset + k] = static_cast<char>(value >> (8 * k));
}


std::size_t fileCount(const fs::path& dir) {
  if (!fs::is_directory(dir)) return 0;
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

bool bitIdentical(const FormFactorMatrix& a, const FormFactorMatrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(float)) == 0;
}


// One small Cornell-box mesh and its form factors, computed once for the whole file.
class FormFactorCacheTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mesh_ = std::make_unique<Mesh>(subdivideScene(cornellBox(), 200));
    caster_ = makeEmbreeRayCaster(*mesh_);
    F_ = std::make_unique<FormFactorMatrix>(computeFormFactors(*mesh_, *caster_, quietFormFactorOptions()));
  }
  static void TearDownTestSuite() {
    F_.reset();
    caster_.reset();
    mesh_.reset();
  }

  static const Mesh& mesh() { return *mesh_; }
  static const RayCaster& caster() { return *caster_; }
  static const FormFactorMatrix& F() { return *F_; }
  static std::size_t n() { return mesh_->numPatches(); }
  static std::uint64_t key() { return formFactorCacheKey(*mesh_, quietFormFactorOptions()); }

  // A valid file for F() in a fresh scratch directory; its bytes in *bytes.
  static std::string savedFile(const std::string& test, std::vector<char>* bytes = nullptr) {
    const std::string path = (scratch(test) / "ff.lff").string();
    Status saved = saveFormFactors(path, key(), F());
    EXPECT_TRUE(saved.ok()) << saved.error().message;
    if (bytes) *bytes = readBytes(path);
    return path;
  }

  static std::size_t payloadBytes() { return n() * n() * sizeof(float); }

 private:
  static inline std::unique_ptr<Mesh> mesh_;
  static inline std::unique_ptr<RayCaster> caster_;
  static inline std::unique_ptr<FormFactorMatrix> F_;
};

// ---------------------------------------------------------------------------------------------
// Keys and paths

TEST_F(FormFactorCacheTest, MeshIsNontrivial) {
  ASSERT_GT(n(), 20u);
  EXPECT_GT((F().array() > 0).count(), static_cast<Eigen::Index>(n()));
}

TEST_F(FormFactorCacheTest, KeyIsStableForEqualInputs) {
  FormFactorOptions options = quietFormFactorOptions();
  Mesh copy = mesh();
  EXPECT_EQ(formFactorCacheKey(mesh(), options), formFactorCacheKey(mesh(), options));
  EXPECT_EQ(formFactorCacheKey(copy, options), formFactorCacheKey(mesh(), options));
  // A freshly built mesh of the same scene is the same input.
  EXPECT_EQ(formFactorCacheKey(subdivideScene(cornellBox(), 200), options), formFactorCacheKey(mesh(), options));
  // showProgress changes nothing about the result, so not the key either.
  FormFactorOptions loud = options;
  loud.showProgress = true;
  EXPECT_EQ(formFactorCacheKey(mesh(), loud), formFactorCacheKey(mesh(), options));
}

TEST_F(FormFactorCacheTest, KeyChangesWithEveryInput) {
  const FormFactorOptions base = quietFormFactorOptions();
  std::vector<std::pair<std::string, std::uint64_t>> keys = {{"base", formFactorCacheKey(mesh(), base)}};
  auto withOptions = [&](const std::string& what, auto change) {
    FormFactorOptions options = base;
    change(options);
    keys.emplace_back(what, formFactorCacheKey(mesh(), options));
  };
  auto withMesh = [&](const std::string& what, auto change) {
    Mesh changed = mesh();
    change(changed);
    keys.emplace_back(what, formFactorCacheKey(changed, base));
  };
  withOptions("seed", [](FormFactorOptions& o) { o.seed += 1; });
  withOptions("samplePairs", [](FormFactorOptions& o) { o.samplePairs *= 2; });
  withOptions("nearFieldBoost", [](FormFactorOptions& o) { o.nearFieldBoost += 1; });
  withOptions("method", [](FormFactorOptions& o) { o.method = FormFactorMethod::PointToPoint; });
  withMesh("vertex moved 1e-9", [](Mesh& m) { m.positions[3].y += 1e-9; });
  withMesh("vertex moved one ulp", [](Mesh& m) {
    m.positions[5].x = std::nextafter(m.positions[5].x, std::numeric_limits<double>::infinity());
  });
  withMesh("patch surface", [](Mesh& m) { m.patches[2].surface += 1; });
  withMesh("patch corner order", [](Mesh& m) { std::swap(m.patches[1].vertices[0], m.patches[1].vertices[1]); });
  withMesh("patch corner count", [](Mesh& m) {
    for (Patch& p : m.patches)
      if (p.numCorners == 3) {
        p.numCorners = 4;
        break;
      }
  });
  withMesh("patch area", [](Mesh& m) { m.patches[0].area *= 1.5; });
  withMesh("patch dropped", [](Mesh& m) { m.patches.pop_back(); });

  std::set<std::uint64_t> distinct;
  for (const auto& [what, key] : keys) EXPECT_TRUE(distinct.insert(key).second) << what << " did not change the key";
}

TEST(FormFactorCachePathTest, NamesTheKeyInSixteenHexDigits) {
  EXPECT_EQ(formFactorCachePath("/tmp/cache", 0xff), "/tmp/cache/formfactors-00000000000000ff.lff");
  EXPECT_EQ(formFactorCachePath("cache/", 0x0123456789abcdefULL), "cache/formfactors-0123456789abcdef.lff");
  EXPECT_EQ(formFactorCachePath("c", ~0ULL), "c/formfactors-ffffffffffffffff.lff");
}

// ---------------------------------------------------------------------------------------------
// saveFormFactors / loadFormFactors

TEST_F(FormFactorCacheTest, RoundTripIsBitIdentical) {
  std::vector<char> bytes;
  const std::string path = savedFile("roundtrip", &bytes);
  EXPECT_EQ(bytes.size(), kHeaderBytes + payloadBytes() + kChecksumBytes);
  EXPECT_EQ(std::string(bytes.data(), 8), std::string("LMBRTFF\0", 8));
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(bitIdentical(*loaded, F()));
  EXPECT_FALSE(hasTemporaryFiles(fs::path(path).parent_path()));
  EXPECT_EQ(fileCount(fs::path(path).parent_path()), 1u);
}

TEST(FormFactorCacheFileTest, SpecialValuesRoundTripBitIdentical) {
  const std::string path = (scratch("special") / "ff.lff").string();
  FormFactorMatrix F(3, 3);
  F << 0.0f, -0.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min(),
      std::numeric_limits<float>::infinity(), 1.0f, std::numeric_limits<float>::max(), 0.25f, -1e-30f;
  ASSERT_TRUE(saveFormFactors(path, 42, F).ok());
  Result<FormFactorMatrix> loaded = loadFormFactors(path, 42, 3);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(bitIdentical(*loaded, F));
}

// The exact bytes of a small file, so the documented layout and checksum cannot drift. The
// checksum is XXH64 (seed 0) of the first 48 bytes, from an independent implementation checked
// against the xxHash project's own sanity vectors.
TEST(FormFactorCacheFileTest, FileLayoutIsExactlyAsDocumented) {
  const std::string path = (scratch("golden") / "ff.lff").string();
  FormFactorMatrix F(2, 2);
  F << 0.5f, 0.25f, 0.125f, 1.0f;
  ASSERT_TRUE(saveFormFactors(path, 0x0123456789abcdefULL, F).ok());
  const std::vector<unsigned char> expected = {
      'L', 'M', 'B', 'R', 'T', 'F', 'F', 0,            // magic
      1, 0, 0, 0,                                      // format version
      0, 0, 0, 0,                                      // reserved
      0xef, 0xcd, 0xab, 0x89, 0x67, 0x45, 0x23, 0x01,  // key
      2, 0, 0, 0, 0, 0, 0, 0,                          // n
      0x00, 0x00, 0x00, 0x3f, 0x00, 0x00, 0x80, 0x3e,  // 0.5, 0.25
      0x00, 0x00, 0x00, 0x3e, 0x00, 0x00, 0x80, 0x3f,  // 0.125, 1
      0xc5, 0xd2, 0x1b, 0xc3, 0xcb, 0xad, 0x2e, 0xb7,  // XXH64 = 0xb72eadcbc31bd2c5
  };
  const std::vector<char> bytes = readBytes(path);
  EXPECT_EQ(std::vector<unsigned char>(bytes.begin(), bytes.end()), expected);
}

TEST(FormFactorCacheFileTest, EmptyMatrixRoundTrips) {
  const std::string path = (scratch("empty") / "ff.lff").string();
  ASSERT_TRUE(saveFormFactors(path, 7, FormFactorMatrix(0, 0)).ok());
  EXPECT_EQ(fs::file_size(path), kHeaderBytes + kChecksumBytes);
  Result<FormFactorMatrix> loaded = loadFormFactors(path, 7, 0);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->size(), 0);
}

TEST_F(FormFactorCacheTest, SaveCreatesDirectoriesAndLeavesNoTemporaryFiles) {
  const fs::path dir = scratch("nested") / "a" / "b";
  const std::string path = (dir / "ff.lff").string();
  ASSERT_TRUE(saveFormFactors(path, key(), F()).ok());
  // Overwriting an existing file goes through a temporary file too.
  ASSERT_TRUE(saveFormFactors(path, key(), F()).ok());
  EXPECT_FALSE(hasTemporaryFiles(dir));
  EXPECT_EQ(fileCount(dir), 1u);
  EXPECT_TRUE(loadFormFactors(path, key(), n()).ok());
}

TEST_F(FormFactorCacheTest, SaveOverwritesADamagedFile) {
  std::vector<char> bytes;
  const std::string path = savedFile("overwrite", &bytes);
  writeBytes(path, std::vector<char>(bytes.begin(), bytes.begin() + 100));
  ASSERT_FALSE(loadFormFactors(path, key(), n()).ok());
  ASSERT_TRUE(saveFormFactors(path, key(), F()).ok());
  EXPECT_EQ(readBytes(path), bytes);
}

TEST_F(FormFactorCacheTest, SaveFailureNamesThePathAndLeavesNothing) {
  const fs::path dir = scratch("unwritable");
  writeBytes(dir / "file", {'x'});
  const std::string path = (dir / "file" / "cache" / "ff.lff").string();
  Status saved = saveFormFactors(path, key(), F());
  ASSERT_FALSE(saved.ok());
  EXPECT_TRUE(contains(saved.error().message, path)) << saved.error().message;
  EXPECT_EQ(fileCount(dir), 1u);
  EXPECT_EQ(readBytes(dir / "file"), std::vector<char>{'x'});

  // Renaming over a directory fails after the temporary file is written: it must be removed.
  const fs::path blocked = dir / "blocked.lff";
  fs::create_directories(blocked / "inside");
  saved = saveFormFactors(blocked.string(), key(), F());
  ASSERT_FALSE(saved.ok());
  EXPECT_TRUE(contains(saved.error().message, blocked.string())) << saved.error().message;
  EXPECT_FALSE(hasTemporaryFiles(dir));
  EXPECT_EQ(fileCount(dir), 2u);
}

TEST(FormFactorCacheFileTest, SaveRejectsNonSquareMatrices) {
  const fs::path dir = scratch("nonsquare");
  Status saved = saveFormFactors((dir / "ff.lff").string(), 1, FormFactorMatrix::Zero(2, 3));
  ASSERT_FALSE(saved.ok());
  EXPECT_TRUE(contains(saved.error().message, "square")) << saved.error().message;
  EXPECT_EQ(fileCount(dir), 0u);
}

TEST_F(FormFactorCacheTest, MissingFileIsAnErrorNamingThePath) {
  const std::string path = (scratch("missing") / "nothing.lff").string();
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, DirectoryIsNotACacheFile) {
  const fs::path path = scratch("directory") / "ff.lff";
  fs::create_directories(path);
  Result<FormFactorMatrix> loaded = loadFormFactors(path.string(), key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, path.string())) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, TruncatedFilesAreRejected) {
  std::vector<char> bytes;
  const std::string path = savedFile("truncated", &bytes);
  const std::size_t payloadEnd = kHeaderBytes + payloadBytes();
  for (std::size_t length : {std::size_t{0}, std::size_t{5}, std::size_t{8}, std::size_t{20}, kHeaderBytes - 1,
                             kHeaderBytes, kHeaderBytes + 3, kHeaderBytes + payloadBytes() / 2, payloadEnd - 1,
                             payloadEnd, payloadEnd + 4, bytes.size() - 1}) {
    writeBytes(path, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(length)));
    Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
    ASSERT_FALSE(loaded.ok()) << "cut at " << length;
    EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
    EXPECT_TRUE(contains(loaded.error().message, "truncated")) << "cut at " << length << ": " << loaded.error().message;
  }
}

TEST_F(FormFactorCacheTest, TrailingBytesAreRejected) {
  std::vector<char> bytes;
  const std::string path = savedFile("trailing", &bytes);
  bytes.push_back('\0');
  writeBytes(path, bytes);
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
  EXPECT_TRUE(contains(loaded.error().message, "trailing")) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, FlippedPayloadOrChecksumByteFailsTheChecksum) {
  std::vector<char> bytes;
  const std::string path = savedFile("flipped", &bytes);
  // One bit in the middle of the payload, one in its last byte, one in the stored checksum.
  for (std::size_t offset : {kHeaderBytes + payloadBytes() / 2 + 1, kHeaderBytes + payloadBytes() - 1,
                             bytes.size() - 3}) {
    std::vector<char> damaged = bytes;
    damaged[offset] = static_cast<char>(damaged[offset] ^ 0x10);
    writeBytes(path, damaged);
    Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
    ASSERT_FALSE(loaded.ok()) << "byte " << offset;
    EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
    EXPECT_TRUE(contains(loaded.error().message, "checksum")) << "byte " << offset << ": " << loaded.error().message;
  }
}

TEST_F(FormFactorCacheTest, WrongMagicIsRejected) {
  std::vector<char> bytes;
  const std::string path = savedFile("magic", &bytes);
  bytes[0] = 'X';
  writeBytes(path, bytes);
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
  EXPECT_TRUE(contains(loaded.error().message, "magic")) << loaded.error().message;

  // Some other short file is not a cache file either, rather than a truncated one.
  writeBytes(path, {'h', 'i', '\n'});
  loaded = loadFormFactors(path, key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, "magic")) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, WrongVersionIsRejected) {
  std::vector<char> bytes;
  const std::string path = savedFile("version", &bytes);
  storeLe(bytes, 8, 2, 4);
  writeBytes(path, bytes);
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
  EXPECT_TRUE(contains(loaded.error().message, "version 2")) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, NonzeroReservedFieldIsRejected) {
  std::vector<char> bytes;
  const std::string path = savedFile("reserved", &bytes);
  storeLe(bytes, 12, 1, 4);
  writeBytes(path, bytes);
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, "reserved")) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, KeyMismatchIsRejected) {
  const std::string path = savedFile("key");
  Result<FormFactorMatrix> loaded = loadFormFactors(path, key() + 1, n());
  ASSERT_FALSE(loaded.ok());
  EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
  EXPECT_TRUE(contains(loaded.error().message, "key")) << loaded.error().message;
}

TEST_F(FormFactorCacheTest, PatchCountMismatchIsRejected) {
  const std::string path = savedFile("patches");
  for (std::size_t expected : {n() - 1, n() + 1, std::size_t{0}}) {
    Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), expected);
    ASSERT_FALSE(loaded.ok()) << expected;
    EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
    EXPECT_TRUE(contains(loaded.error().message, "expected " + std::to_string(expected))) << loaded.error().message;
  }
}

// A damaged patch count must not make the reader allocate for it: it is either not what the
// caller expects, or (when it is) the file is far too short for it.
TEST_F(FormFactorCacheTest, HugePatchCountIsRejectedWithoutAllocating) {
  std::vector<char> bytes;
  const std::string path = savedFile("huge", &bytes);
  for (std::uint64_t huge : {std::uint64_t{1} << 20, std::uint64_t{1} << 31, std::uint64_t{1} << 62, ~std::uint64_t{0}}) {
    storeLe(bytes, 24, huge, 8);
    writeBytes(path, bytes);
    Result<FormFactorMatrix> loaded = loadFormFactors(path, key(), n());
    ASSERT_FALSE(loaded.ok());
    EXPECT_TRUE(contains(loaded.error().message, "patches")) << loaded.error().message;
    if (huge <= std::numeric_limits<std::size_t>::max()) {
      loaded = loadFormFactors(path, key(), static_cast<std::size_t>(huge));
      ASSERT_FALSE(loaded.ok()) << huge;
      EXPECT_TRUE(contains(loaded.error().message, path)) << loaded.error().message;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// cachedFormFactors

TEST_F(FormFactorCacheTest, ComputesOnceThenLoads) {
  const fs::path dir = scratch("cached") / "cache";
  FormFactorStats stats;
  CachedFormFactors first = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), dir.string(), &stats);
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(first.warning.empty()) << first.warning;
  EXPECT_EQ(first.path, formFactorCachePath(dir.string(), key()));
  EXPECT_TRUE(fs::is_regular_file(first.path));
  EXPECT_TRUE(bitIdentical(first.matrix, F()));
  EXPECT_GT(stats.pairsEvaluated, 0u);
  EXPECT_GT(stats.visibilityRays, 0u);

  stats = FormFactorStats{};
  stats.pairsEvaluated = 99;
  CachedFormFactors second = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), dir.string(), &stats);
  EXPECT_TRUE(second.fromCache);
  EXPECT_TRUE(second.warning.empty()) << second.warning;
  EXPECT_EQ(second.path, first.path);
  EXPECT_TRUE(bitIdentical(second.matrix, F()));
  EXPECT_EQ(stats.pairsEvaluated, 0u);
  EXPECT_EQ(stats.pairsCulled, 0u);
  EXPECT_EQ(stats.visibilityRays, 0u);
  EXPECT_GE(stats.seconds, 0.0);

  // Other options are another computation, in another file beside the first.
  FormFactorOptions other = quietFormFactorOptions();
  other.seed = 2;
  CachedFormFactors third = cachedFormFactors(mesh(), caster(), other, dir.string());
  EXPECT_FALSE(third.fromCache);
  EXPECT_NE(third.path, first.path);
  EXPECT_FALSE(bitIdentical(third.matrix, F()));
  EXPECT_EQ(fileCount(dir), 2u);
  EXPECT_FALSE(hasTemporaryFiles(dir));
  EXPECT_TRUE(cachedFormFactors(mesh(), caster(), other, dir.string()).fromCache);
  EXPECT_TRUE(cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), dir.string()).fromCache);
}

TEST_F(FormFactorCacheTest, DamagedFileWarnsRecomputesAndIsRepaired) {
  const fs::path dir = scratch("damaged");
  const std::string path = formFactorCachePath(dir.string(), key());
  ASSERT_TRUE(saveFormFactors(path, key(), F()).ok());
  const std::vector<char> good = readBytes(path);

  std::vector<char> damaged = good;
  damaged[kHeaderBytes + payloadBytes() / 3] ^= 0x01;
  writeBytes(path, damaged);
  ::testing::internal::CaptureStderr();
  CachedFormFactors result = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), dir.string());
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_FALSE(result.fromCache);
  EXPECT_TRUE(contains(result.warning, path)) << result.warning;
  EXPECT_TRUE(contains(result.warning, "checksum")) << result.warning;
  EXPECT_TRUE(contains(printed, "lambert: warning: " + path + ": ")) << printed;
  EXPECT_TRUE(contains(printed, "; recomputing\n")) << printed;
  EXPECT_TRUE(bitIdentical(result.matrix, F()));
  // The damaged file was replaced by a valid one.
  EXPECT_EQ(readBytes(path), good);
  EXPECT_FALSE(hasTemporaryFiles(dir));
  CachedFormFactors again = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), dir.string());
  EXPECT_TRUE(again.fromCache);
  EXPECT_TRUE(again.warning.empty()) << again.warning;
}

TEST_F(FormFactorCacheTest, StaleFileAtTheKeysPathIsRecomputed) {
  // The right name but a matrix of another size (as if the file had been copied or renamed).
  const fs::path dir = scratch("stale");
  const std::string path = formFactorCachePath(dir.string(), key());
  ASSERT_TRUE(saveFormFactors(path, key(), FormFactorMatrix::Zero(4, 4)).ok());
  ::testing::internal::CaptureStderr();
  CachedFormFactors result = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), dir.string());
  ::testing::internal::GetCapturedStderr();
  EXPECT_FALSE(result.fromCache);
  EXPECT_TRUE(contains(result.warning, path)) << result.warning;
  EXPECT_TRUE(bitIdentical(result.matrix, F()));
  EXPECT_TRUE(loadFormFactors(path, key(), n()).ok());
}

TEST_F(FormFactorCacheTest, EmptyDirectoryDisablesTheCache) {
  const fs::path dir = scratch("disabled");
  // In dir, where a cache file at a relative path would land; restored however the test ends.
  struct WorkingDirectory {
    fs::path before = fs::current_path();
    explicit WorkingDirectory(const fs::path& to) { fs::current_path(to); }
    ~WorkingDirectory() { fs::current_path(before); }
  } inDir(dir);
  FormFactorStats stats;
  CachedFormFactors first = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), "", &stats);
  CachedFormFactors second = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), "");
  EXPECT_FALSE(first.fromCache);
  EXPECT_FALSE(second.fromCache);
  EXPECT_TRUE(first.path.empty());
  EXPECT_TRUE(first.warning.empty()) << first.warning;
  EXPECT_TRUE(bitIdentical(first.matrix, F()));
  EXPECT_TRUE(bitIdentical(second.matrix, F()));
  EXPECT_GT(stats.pairsEvaluated, 0u);
  EXPECT_EQ(fileCount(dir), 0u);
}

TEST_F(FormFactorCacheTest, UnwritableDirectoryWarnsAndStillComputes) {
  const fs::path dir = scratch("readonly");
  writeBytes(dir / "file", {'x'});
  const std::string cacheDirectory = (dir / "file" / "cache").string();
  ::testing::internal::CaptureStderr();
  CachedFormFactors result = cachedFormFactors(mesh(), caster(), quietFormFactorOptions(), cacheDirectory);
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_FALSE(result.fromCache);
  EXPECT_TRUE(bitIdentical(result.matrix, F()));
  EXPECT_FALSE(result.warning.empty());
  EXPECT_TRUE(contains(result.warning, result.path)) << result.warning;
  EXPECT_TRUE(contains(printed, "lambert: warning: ")) << printed;
  EXPECT_EQ(fileCount(dir), 1u);
}

}  // namespace
}  // namespace lambert
