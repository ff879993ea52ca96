// The adaptive mesh's master form-factor table file (flat/table.h, .lft):
// FormFactorTable::load, what the adaptive meshing calls to reuse an earlier run's pairs, on the
// input as it is and with its checksum made valid (cache_input.h), so the checks of the pairs'
// order and values are reached. The expected key is the header's own.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cache_input.h"
#include "fuzz_file.h"
#include "lambert/flat/table.h"
#include "lambert/geometry/ray_caster.h"

namespace {

// load() reads the file into the table without touching the mesh or the caster, so an empty
// mesh serves; the table is made afresh per input so one input's pairs never shape the next.
void load(const std::uint8_t* data, std::size_t size) {
  static const lambert::Mesh mesh;
  static const std::unique_ptr<lambert::RayCaster> caster = lambert::makeBruteForceRayCaster(mesh);
  lambert::FormFactorTable table(mesh, *caster, lambert::FormFactorOptions{});
  const std::string path = lambert::fuzz::writeInput("input.lft", data, size);
  lambert::Result<std::size_t> pairs = table.load(path, lambert::fuzz::headerKey(data, size));
  lambert::fuzz::report(pairs);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  lambert::fuzz::loadAsIsAndWithValidChecksum(data, size, load);
  return 0;
}
