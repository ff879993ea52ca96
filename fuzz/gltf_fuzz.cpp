// glTF 2.0 (load/gltf.h): readGltf on input.glb when the input starts with the binary container's
// magic "glTF", else on input.gltf (JSON), so one target covers both containers.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_file.h"
#include "lambert/load/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = lambert::fuzz::writeInput(binary ? "input.glb" : "input.gltf", data, size);
  lambert::Result<lambert::Scene> scene = lambert::readGltf(path);
  lambert::fuzz::report(scene);
  return 0;
}
