// Form-factor cache files (.lff). All fields are little-endian.
//
//   offset  size      field
//   0       8         magic "LMBRTFF\0"
//   8       4         u32 format version (1)
//   12      4         u32 reserved, 0
//   16      8         u64 key: formFactorCacheKey of the mesh and options the matrix was computed for
//   24      8         u64 n, the number of patches
//   32      4·n·n     float32 F(i, j), row-major (row i is contiguous)
//   32+4n²  8         u64 checksum: XXH64 (seed 0) of every byte before it, header and payload
//
// A file is accepted only when every field checks out and its size is exactly 32 + 4n² + 8, so a
// truncated or extended file is caught before its checksum is even computed. The header, the
// XXH64 checksum and the atomic write are cache_file.h's, shared with the adaptive master table's
// file (table.cpp).
#include "lambert/flat/form_factor_cache.h"

#include "lambert/core/warning.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "lambert/core/timer.h"
#include "lambert/core/cache_file.h"

namespace lambert {
namespace {

using cachefile::KeyHasher;

constexpr cachefile::Format kFormat{{'L', 'M', 'B', 'R', 'T', 'F', 'F', '\0'}, 1, "form-factor cache file"};

// The payload size of an n-patch matrix in bytes, or 0 when it would not fit in a size_t.
std::size_t payloadBytes(std::uint64_t n) {
  constexpr std::uint64_t kMax =
      std::numeric_limits<std::size_t>::max() - cachefile::kHeaderBytes - cachefile::kChecksumBytes;
  if (n != 0 && n > kMax / 4 / n) return 0;
  return static_cast<std::size_t>(n * n * 4);
}

}  // namespace

std::uint64_t formFactorCacheKey(const Mesh& mesh, const FormFactorOptions& options) {
  KeyHasher h;
  h.text("lambert form factors");
  h.u32(kFormat.version);
  h.u32(cachefile::kEstimatorVersion);
  // The method's name, not its enum value, so that reordering the enum does not alias old files.
  h.text(formFactorMethodName(options.method));
  h.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(options.samplePairs)));
  h.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(options.nearFieldBoost)));
  h.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(options.hemicubeResolution)));
  h.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(options.hemisphereRays)));
  h.u64(options.seed);
  h.u64(mesh.positions.size());
  for (const Vec3& p : mesh.positions) h.vec3(p);
  h.u64(mesh.patches.size());
  for (const Patch& patch : mesh.patches) {
    h.u32(patch.numCorners);
    for (std::uint32_t k = 0; k < std::min<std::uint32_t>(patch.numCorners, 4); ++k) h.u32(patch.vertices[k]);
    h.u32(patch.surface);
    // Derived from the positions by makePatch, but computeFormFactors reads them as given.
    h.vec3(patch.normal);
    h.vec3(patch.centroid);
    h.f64(patch.area);
  }
  return h.digest();
}

std::string formFactorCachePath(const std::string& directory, std::uint64_t key) {
  return cachefile::keyedPath(directory, "formfactors-", key, ".lff");
}

Status saveFormFactors(const std::string& path, std::uint64_t key, const FormFactorMatrix& F) {
  if (path.empty()) return Error{"saveFormFactors: empty path"};
  if (F.rows() != F.cols())
    return Error{path + ": form-factor matrix is " + std::to_string(F.rows()) + "x" + std::to_string(F.cols()) +
                 ", not square"};
  const auto n = static_cast<std::uint64_t>(F.rows());
  const std::size_t payload = payloadBytes(n);
  if (payload == 0 && n != 0) return Error{path + ": " + std::to_string(n) + " patches are too many to store"};
  // Written straight from the matrix's memory: row-major floats are the file's layout.
  return cachefile::writeFile(path, kFormat, key, n,
                              std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(F.data()), payload));
}

Result<FormFactorMatrix> loadFormFactors(const std::string& path, std::uint64_t key, std::size_t expectedPatches) {
  Result<cachefile::Reader> opened = cachefile::Reader::open(path, kFormat, key);
  if (!opened) return opened.error();
  cachefile::Reader& reader = *opened;
  // Checked before anything is allocated: n comes from the file, expectedPatches from the caller.
  const std::uint64_t n = reader.count();
  if (n != expectedPatches)
    return Error{path + ": holds " + std::to_string(n) + " patches, expected " + std::to_string(expectedPatches)};
  const std::size_t payload = payloadBytes(n);
  if (payload == 0 && n != 0) return Error{path + ": " + std::to_string(n) + " patches are too many to load"};
  if (Status sized = reader.checkSize(payload, std::to_string(n) + " patches"); !sized) return sized.error();

  const auto size = static_cast<Eigen::Index>(n);
  FormFactorMatrix F(size, size);
  if (Status read = reader.readPayload(F.data()); !read) return read.error();
  return F;
}

CachedFormFactors cachedFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    const std::string& cacheDirectory, FormFactorStats* stats) {
  CachedFormFactors result;
  if (cacheDirectory.empty()) {
    result.matrix = computeFormFactors(mesh, caster, options, stats);
    return result;
  }
  auto warn = [&](const std::string& line) {
    warning(line);
    if (!result.warning.empty()) result.warning += '\n';
    result.warning += line;
  };

  const std::uint64_t key = formFactorCacheKey(mesh, options);
  result.path = formFactorCachePath(cacheDirectory, key);
  Timer timer;
  Result<FormFactorMatrix> loaded = loadFormFactors(result.path, key, mesh.numPatches());
  if (loaded) {
    result.matrix = std::move(*loaded);
    result.fromCache = true;
    if (stats) {
      *stats = FormFactorStats{};
      stats->seconds = timer.seconds();
    }
    return result;
  }
  // No file is the ordinary cache miss; anything else (unreadable, damaged, stale) is reported.
  if (!cachefile::isMissing(result.path)) warn(loaded.error().message + "; recomputing");

  result.matrix = computeFormFactors(mesh, caster, options, stats);
  if (Status saved = saveFormFactors(result.path, key, result.matrix); !saved)
    warn(saved.error().message + "; form factors not cached");
  return result;
}

}  // namespace lambert
