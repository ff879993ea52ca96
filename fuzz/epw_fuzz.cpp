// EnergyPlus weather files (load/epw.h): readEpw on input.epw, its repairs (missing values, negative
// light, leap days) and refusals.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_file.h"
#include "lambert/load/epw.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lambert::fuzz::silenceWarnings();
  const std::string path = lambert::fuzz::writeInput("input.epw", data, size);
  lambert::Result<lambert::WeatherData> weather = lambert::readEpw(path);
  lambert::fuzz::report(weather);
  return 0;
}
