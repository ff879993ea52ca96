// Vertex files (io/vertices.h), what `solve --export-vertices` writes: readVertices on
// input.ply when the input starts with "ply", else on input.csv, so one target covers both.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "fuzz_file.h"
#include "lambert/io/vertices.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const bool ply = size >= 3 && std::memcmp(data, "ply", 3) == 0;
  const std::string path = lambert::fuzz::writeInput(ply ? "input.ply" : "input.csv", data, size);
  lambert::Result<std::vector<lambert::VertexSample>> vertices = lambert::readVertices(path);
  lambert::fuzz::report(vertices);
  return 0;
}
