// The uniform mesh's form-factor matrix cache (flat/form_factor_cache.h, .lff): loadFormFactors, what
// cachedFormFactors calls on a cache hit, on the input as it is and with its checksum made valid
// (cache_input.h). The expected key and patch count are the header's own, as they are for a file
// written for the scene being loaded.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cache_input.h"
#include "fuzz_file.h"
#include "lambert/flat/form_factor_cache.h"

namespace {

void load(const std::uint8_t* data, std::size_t size) {
  const std::string path = lambert::fuzz::writeInput("input.lff", data, size);
  const std::uint64_t count = lambert::fuzz::headerCount(data, size);
  // A count beyond size_t cannot be a caller's patch count; the reader then sees the mismatch.
  const std::size_t expected = count > std::numeric_limits<std::size_t>::max() ? 0 : static_cast<std::size_t>(count);
  lambert::Result<lambert::FormFactorMatrix> F = lambert::loadFormFactors(path, lambert::fuzz::headerKey(data, size), expected);
  lambert::fuzz::report(F);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  lambert::fuzz::loadAsIsAndWithValidChecksum(data, size, load);
  return 0;
}
