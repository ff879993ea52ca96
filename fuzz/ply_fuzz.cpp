// PLY scene meshes (load/ply.h): readPly on input.ply, ASCII and binary (both byte orders).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_file.h"
#include "lambert/load/ply.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const std::string path = lambert::fuzz::writeInput("input.ply", data, size);
  lambert::Result<lambert::Scene> scene = lambert::readPly(path);
  lambert::fuzz::report(scene);
  return 0;
}
