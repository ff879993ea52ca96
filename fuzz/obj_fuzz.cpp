// Wavefront OBJ with its MTL (load/obj.h): readObj on input.obj. An input may carry an MTL file
// too: everything after a line "#%%mtl" is written to input.mtl beside it, which the OBJ part
// names with "mtllib input.mtl" (the seeds do), so materials are fuzzed through the OBJ as users
// give them.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_file.h"
#include "lambert/load/obj.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kSeparator = "#%%mtl\n";
  const std::size_t split = input.find(kSeparator);
  const std::string_view obj = input.substr(0, split);
  const std::string_view mtl = split == std::string_view::npos ? std::string_view{} : input.substr(split + kSeparator.size());
  lambert::fuzz::writeInput("input.mtl", mtl);
  const std::string path = lambert::fuzz::writeInput("input.obj", obj);
  lambert::Result<lambert::Scene> scene = lambert::readObj(path);
  lambert::fuzz::report(scene);
  return 0;
}
