#pragma once
// An on-disk cache of form-factor matrices, so that a scene is not recomputed on every run. A
// cache file is named by a hash of everything that determines its matrix, and carries that hash,
// its size and a checksum: a file that is stale, truncated or damaged is never trusted, only
// reported and recomputed. The file format is documented at the top of cache.cpp.
#include <cstddef>
#include <cstdint>
#include <string>

#include "lambert/core/error.h"
#include "lambert/flat/form_factors.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

// Identifies a form-factor computation: a 64-bit hash (XXH64) of every input that changes the
// result: the mesh's vertex positions (exact bits), each patch's corner indices, corner count,
// surface, normal, centroid and area, and the options method, samplePairs, nearFieldBoost and seed
// (not showProgress), together with the cache's format and estimator versions. The ray caster is
// assumed to be built from the same mesh.
std::uint64_t formFactorCacheKey(const Mesh& mesh, const FormFactorOptions& options);

// The file for a key inside a cache directory: <directory>/formfactors-<16 hex digits>.lff
std::string formFactorCachePath(const std::string& directory, std::uint64_t key);

// Writes F (square) to path atomically: into a temporary file in the same directory, renamed over
// path only once complete, so readers see the old file or the new one, never a partial one. Creates
// the directory; on failure leaves nothing behind and the Error names the path.
Status saveFormFactors(const std::string& path, std::uint64_t key, const FormFactorMatrix& F);

// Reads and validates a file written by saveFormFactors. Any problem (missing file, bad magic,
// another format version, a key other than key, a size other than expectedPatches, a truncated
// file, a checksum mismatch, trailing bytes) is an Error of the form "<path>: <what is wrong>".
// The header is checked before anything is allocated, so a damaged one cannot ask for gigabytes.
Result<FormFactorMatrix> loadFormFactors(const std::string& path, std::uint64_t key, std::size_t expectedPatches);

struct CachedFormFactors {
  FormFactorMatrix matrix;
  bool fromCache = false;  // loaded from path rather than computed
  std::string path;        // the cache file for this computation; empty when caching is disabled
  // Set when a cache file existed but was rejected, or the computed matrix could not be written;
  // one line per problem, each "<path>: <why>; <what was done about it>".
  std::string warning;
};

// The form factors for mesh and options: loaded from cacheDirectory when it holds a valid file for
// their key, else computed with computeFormFactors and saved there. An empty cacheDirectory
// disables the cache. A rejected file is never trusted: it is reported in .warning and on stderr
// ("lambert: warning: <path>: <why>; recomputing"), recomputed and overwritten. A cache that cannot
// be written is a warning too, never a failure. stats (may be null) is filled by
// computeFormFactors when computing; when loading, stats->seconds is the load time and the counts
// are zero.
CachedFormFactors cachedFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    const std::string& cacheDirectory, FormFactorStats* stats = nullptr);

}  // namespace lambert
