// The JSON scene file (scene/scene_file.h): parseSceneFile on the input as text, as readSceneFile
// calls it after reading the file. The path only names the file in messages and is the base for
// relative mesh paths, which then point into the private directory where nothing else lies.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_file.h"
#include "lambert/scene/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const std::string text(reinterpret_cast<const char*>(data), size);
  lambert::Result<lambert::Scene> scene = lambert::parseSceneFile(text, "/tmp/lambert-fuzz-scene/input.json");
  (void)scene;
  return 0;
}
