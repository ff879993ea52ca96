// MGF, the Materials and Geometry Format (load/mgf.h): readMgf on input.mgf, with its
// entities, transforms, contexts and includes (an include of input.mgf itself is a cycle the
// reader must refuse).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_file.h"
#include "lambert/load/mgf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const std::string path = lambert::fuzz::writeInput("input.mgf", data, size);
  lambert::Result<lambert::Scene> scene = lambert::readMgf(path);
  lambert::fuzz::report(scene);
  return 0;
}
