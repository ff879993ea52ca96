// The JSON scene file (load/scene_file.h): parseSceneFile on the input as text, as readSceneFile
// calls it after reading the file. The path names the file in messages and is the base of
// relative mesh paths: it is made to lie in the source tree's scenes/cornell/, so the seeds'
// meshes (cornell.obj, ../floor/floor.mgf) are found and loaded with their transforms.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_file.h"
#include "lambert/load/scene_file.h"

namespace {
const std::string kPath = std::string(LAMBERT_SOURCE_DIR) + "/scenes/cornell/fuzz-input.json";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const std::string text(reinterpret_cast<const char*>(data), size);
  lambert::Result<lambert::Scene> scene = lambert::parseSceneFile(text, kPath);
  lambert::fuzz::report(scene);
  return 0;
}
